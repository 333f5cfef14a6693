"""Pinhole camera model (no distortion) and the course's two simulated cameras.

Conventions
-----------
* **Optical frame** (``*_optical_frame``): x right, y down, z forward (out of the lens), as in
  OpenCV and REP 103's camera optical frames. Pixels are ``u`` (column) and ``v`` (row); the
  centre of pixel ``(col, row)`` is at ``u = col, v = row`` (OpenCV's convention), so an
  image of width ``W`` spans ``u`` in ``[-0.5, W - 0.5]``.
* **Camera body frame** (``oak_rgb_camera_frame``, ``overhead_camera``): REP 103, x forward,
  y left, z up. ``R_CAMERA_FRAME_OPTICAL`` rotates optical coordinates into body coordinates;
  it is the URDF joint ``rpy = (-pi/2, 0, -pi/2)``, ``Rz(-pi/2) @ Rx(-pi/2)``.
* Intrinsics follow gz-sensors' defaults for an SDF camera with only ``horizontal_fov``:
  ``fx = fy = (W / 2) / tan(hfov / 2)``, ``cx = W / 2``, ``cy = H / 2``; no distortion.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from posekit.geometry import Rotation, Transform
from posekit.msgs.builtin_interfaces import Time
from posekit.msgs.sensor_msgs import CameraInfo
from posekit.msgs.std_msgs import Header
from posekit.vision.errors import CameraModelError

__all__ = [
    "OAK_RGB_CAMERA",
    "OVERHEAD_CAMERA",
    "R_CAMERA_FRAME_OPTICAL",
    "T_CAMERA_FRAME_OPTICAL",
    "PinholeCamera",
]

F64Array = npt.NDArray[np.float64]

#: Rotation taking optical-frame coordinates (x right, y down, z forward) into the REP 103
#: camera body frame (x forward, y left, z up): columns are the optical axes in body axes.
_ROT_CAMERA_FRAME_OPTICAL = Rotation.from_euler("ZX", (-math.pi / 2.0, -math.pi / 2.0))
R_CAMERA_FRAME_OPTICAL: F64Array = _ROT_CAMERA_FRAME_OPTICAL.as_matrix()
R_CAMERA_FRAME_OPTICAL.setflags(write=False)
#: The same as a 4x4 transform with zero translation (``T_camera_frame_optical``).
T_CAMERA_FRAME_OPTICAL: F64Array = Transform(_ROT_CAMERA_FRAME_OPTICAL).as_matrix()
T_CAMERA_FRAME_OPTICAL.setflags(write=False)


@dataclass(frozen=True, slots=True)
class PinholeCamera:
    """An ideal pinhole camera: image size in pixels, focal lengths and principal point in pixels.

    Attributes:
        width: image width in pixels.
        height: image height in pixels.
        fx: focal length along u, pixels.
        fy: focal length along v, pixels.
        cx: principal point u, pixels (pixel-centre convention, see module docstring).
        cy: principal point v, pixels.
        near: near clipping distance along the optical axis, metres (renderer only).
        far: far clipping distance, metres (renderer only).
    """

    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float
    near: float = 0.05
    far: float = 100.0

    def __post_init__(self) -> None:
        if not (isinstance(self.width, int) and isinstance(self.height, int)):
            raise CameraModelError(
                f"width and height must be int, got {type(self.width).__name__}, "
                f"{type(self.height).__name__}"
            )
        if self.width <= 0 or self.height <= 0:
            raise CameraModelError(f"image size must be positive, got {self.width}x{self.height}")
        values = (self.fx, self.fy, self.cx, self.cy, self.near, self.far)
        if not all(math.isfinite(v) for v in values):
            raise CameraModelError(f"camera parameters must be finite, got {values}")
        if self.fx <= 0.0 or self.fy <= 0.0:
            raise CameraModelError(f"focal lengths must be positive, got fx={self.fx} fy={self.fy}")
        if not 0.0 < self.near < self.far:
            raise CameraModelError(f"need 0 < near < far, got near={self.near} far={self.far}")

    @classmethod
    def from_hfov(
        cls, width: int, height: int, hfov: float, *, degrees: bool = False, near: float = 0.05,
        far: float = 100.0,
    ) -> PinholeCamera:
        """Camera with square pixels from a horizontal field of view (gz-sensors' defaults).

        Args:
            width: image width in pixels.
            height: image height in pixels.
            hfov: horizontal field of view, radians (or degrees with ``degrees=True``).
            degrees: interpret ``hfov`` in degrees.
            near: near clipping distance in metres.
            far: far clipping distance in metres.
        """
        angle = math.radians(hfov) if degrees else float(hfov)
        if not 0.0 < angle < math.pi:
            raise CameraModelError(f"horizontal FOV must be in (0, pi) rad, got {angle}")
        f = (width / 2.0) / math.tan(angle / 2.0)
        return cls(width, height, f, f, width / 2.0, height / 2.0, near, far)

    @classmethod
    def from_camera_info(cls, msg: CameraInfo) -> PinholeCamera:
        """Camera from a ``sensor_msgs/CameraInfo`` (reads ``width``, ``height`` and ``k``)."""
        k = np.asarray(msg.k, dtype=np.float64).reshape(-1)
        if k.size != 9:
            raise CameraModelError(f"CameraInfo.k must have 9 elements, got {k.size}")
        return cls(int(msg.width), int(msg.height), float(k[0]), float(k[4]), float(k[2]),
                   float(k[5]))

    @property
    def hfov(self) -> float:
        """Horizontal field of view in radians, ``2 atan(W / (2 fx))``."""
        return 2.0 * math.atan(self.width / (2.0 * self.fx))

    @property
    def K(self) -> F64Array:
        """3x3 intrinsic matrix ``[[fx, 0, cx], [0, fy, cy], [0, 0, 1]]``."""
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])

    @property
    def dist_coeffs(self) -> F64Array:
        """Distortion coefficients (plumb_bob k1, k2, t1, t2, k3): all zero for this model."""
        return np.zeros(5)

    def scaled(self, factor: int) -> PinholeCamera:
        """The camera sampled ``factor`` times more densely along each axis.

        Pixel ``(u, v)`` of this camera covers the ``factor x factor`` block whose centre is
        ``(factor*u + (factor-1)/2, factor*v + (factor-1)/2)`` in the scaled camera, so
        area-averaging the scaled image by ``factor`` gives this camera's image.
        """
        if not isinstance(factor, int) or factor < 1:
            raise CameraModelError(f"scale factor must be a positive int, got {factor!r}")
        off = (factor - 1) / 2.0
        return PinholeCamera(
            self.width * factor, self.height * factor, self.fx * factor, self.fy * factor,
            self.cx * factor + off, self.cy * factor + off, self.near, self.far,
        )

    def project(self, points_optical: npt.ArrayLike) -> F64Array:
        """Pixel coordinates ``(N, 2)`` of points ``(N, 3)`` given in the optical frame, metres.

        Points at or behind the camera (z <= 0) give ``nan``.
        """
        p = np.asarray(points_optical, dtype=np.float64)
        if p.shape[-1] != 3:
            raise CameraModelError(f"points must have shape (..., 3), got {p.shape}")
        z = p[..., 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            u = self.fx * p[..., 0] / z + self.cx
            v = self.fy * p[..., 1] / z + self.cy
        uv = np.stack([u, v], axis=-1)
        uv[z <= 0.0] = np.nan
        return uv

    def project_world(self, points_world: npt.ArrayLike, T_world_optical: npt.ArrayLike
                      ) -> F64Array:
        """Pixels of world points seen by a camera whose optical frame is at ``T_world_optical``."""
        T = np.asarray(T_world_optical, dtype=np.float64)
        p = np.asarray(points_world, dtype=np.float64)
        R, t = T[:3, :3], T[:3, 3]
        return self.project((p - t) @ R)  # R^T (p - t), row-vector form

    def pixel_ray(self, u: float, v: float) -> F64Array:
        """Unit direction (optical frame) of the ray through pixel ``(u, v)``."""
        d = np.array([(u - self.cx) / self.fx, (v - self.cy) / self.fy, 1.0])
        out: F64Array = d / np.linalg.norm(d)
        return out

    def camera_info(self, *, frame_id: str = "", stamp: Time | None = None) -> CameraInfo:
        """``sensor_msgs/CameraInfo`` of this camera: ``plumb_bob``, zero ``d``, identity ``r``.

        ``p`` is ``[K | 0]`` (monocular camera, no rectification).
        """
        k = self.K.reshape(-1).copy()
        p = np.zeros(12)
        p[[0, 2, 5, 6, 10]] = [self.fx, self.cx, self.fy, self.cy, 1.0]
        header = Header(stamp=stamp if stamp is not None else Time(), frame_id=frame_id)
        return CameraInfo(
            header=header, height=self.height, width=self.width, distortion_model="plumb_bob",
            d=np.zeros(5), k=k, r=np.eye(3).reshape(-1), p=p,
        )


#: ROSbot's OAK-D-PRO colour camera in simulation: 1280x720, horizontal FOV 60 degrees, 30 Hz
#: (docs/specs/rosbot_and_worlds.md). K = [[1108.513, 0, 640], [0, 1108.513, 360]].
OAK_RGB_CAMERA: PinholeCamera = PinholeCamera.from_hfov(1280, 720, 60.0, degrees=True)
#: The overhead camera of aruco_box_camera_world: 640x480, horizontal_fov 1.047 rad, clip
#: 0.1-100 m. K = [[554.383, 0, 320], [0, 554.383, 240]].
OVERHEAD_CAMERA: PinholeCamera = PinholeCamera.from_hfov(640, 480, 1.047, near=0.1, far=100.0)
