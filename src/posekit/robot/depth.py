"""The OAK-D's stereo depth, simulated by z-buffering the world's geometry (numpy only).

Geometry: every face of every box (one-sided, outward normals), every wall face (a vertical
quad from the ground to the wall's height, seen from both sides) and the ground plane
``z = 0``. :func:`rasterize` draws planar convex quads into an **inverse-depth buffer**: for a
plane ``n . p = c`` (optical frame) the inverse depth ``1/z`` of the ray through pixel
``(u, v)`` is ``(n . ((u - cx)/fx, (v - cy)/fy, 1)) / c``, affine in ``u`` and ``v``, so each
quad costs a few numpy passes over its bounding box (edge functions for coverage, one affine
plane for depth, a max for the z test). Pixel centres follow OpenCV (pixel ``(col, row)`` is
at ``u = col, v = row``). Quads crossing the camera plane are clipped to ``z >= 1 mm``.
posekit's colour renderer uses the same buffer to hide boxes behind walls.

The sensor (:class:`DepthCamera`, defaults :data:`DEFAULT_DEPTH`) is the one Husarion's
``husarion_components_description`` gives the ROSbot's OAK-D in Gazebo (a gz-sensors
``depth_camera`` bridged by ros_gz_bridge): **1280x720**, horizontal FOV **60 deg**
(the colour camera's intrinsics, so ``/oak/stereo/camera_info`` fits both), **30 Hz**, depth
**1.0-12.0 m**. Images are ``32FC1``, metres along the optical axis (REP 118, what the
bridge makes of Gazebo's ``R_FLOAT32``), in ``oak_rgb_camera_optical_frame``. As gz-sensors
and REP 117 report them: ``+inf`` where nothing is seen or the depth is at or beyond
``max_depth``, ``-inf`` where it is at or below ``min_depth``.

Noise: a stereo matcher's, Gaussian in disparity: ``disparity_stddev`` pixels of disparity
error, i.e. inverse depth off by ``disparity_stddev / (stereo_focal_px * baseline)`` (1/m),
a depth error of about ``z**2 * disparity_stddev / (f B)``; plus an optional constant Gaussian
``noise_stddev`` (m) on the depth (see :meth:`DepthCamera.frame`). The
defaults are the OAK-D Pro's stereo pair (OV9282, 1280x800, 72 deg horizontal FOV:
``f = 881 px``; baseline 7.5 cm) with a 0.1 px matching error, and no constant term:
sigma = 1.5 mm at 1 m, 24 mm at 4 m, 0.22 m at 12 m. (Husarion's description writes a 0.2 m
Gaussian and the 1-12 m clip in a ``<depth_camera>`` element beside ``<camera>``, where
gz-sensors reads neither; posekit applies the clip as the description intends and the
stereo model for the noise.) The noise of frame ``k`` (its time on the sensor's rate grid) is
a window of one bank of standard normals drawn once from ``seed``, at an offset drawn from
``(seed, k)`` (as the colour camera's noise: a crop costs nothing, a million draws ~10 ms): a
seed gives the same frame at the same time however many frames were skipped; consecutive
frames' noise fields are shifted copies of each other, which a single frame cannot show.

Point clouds (:func:`depth_points`, :func:`depth_cloud`): organised (``height`` rows of
``width``), points ``(x, y, z) = z ((u - cx)/fx, (v - cy)/fy, 1)`` in the optical frame
(x right, y down, z forward, REP 103), NaN where the depth is not finite (``is_dense``
false), fields ``x, y, z, rgb`` float32 at offsets 0, 4, 8, 16 with ``point_step`` 32, the
layout of gz-sensors' depth camera; ``rgb`` is white (the depth camera has no colour).
"""

from __future__ import annotations

import math
from copy import copy
from dataclasses import dataclass
from typing import Protocol

import numpy as np
import numpy.typing as npt

from posekit.msgs.image import numpy_to_image
from posekit.msgs.point_cloud2 import xyz_fields
from posekit.msgs.sensor_msgs import Image, PointCloud2
from posekit.msgs.std_msgs import Header
from posekit.worlds import World, box_half_extents
from posekit.worlds.obstacles import WallSegments

__all__ = [
    "DEFAULT_DEPTH",
    "CameraIntrinsics",
    "DepthCamera",
    "DepthParams",
    "SceneQuads",
    "clip_near",
    "depth_cloud",
    "depth_image_msg",
    "depth_points",
    "ground_inverse_depth",
    "rasterize",
]

F64Array = npt.NDArray[np.float64]
F32Array = npt.NDArray[np.float32]
I32Array = npt.NDArray[np.int32]

#: Quads are clipped to this distance in front of the camera (m) before projection.
_CLIP_Z = 1e-3
#: Extra rows and columns of the noise bank (the range of a frame's window offset).
_BANK_PAD = 64
#: White, as the float32 whose bits are 0x00FFFFFF (PCL's packed rgb).
_WHITE_RGB = np.array([0x00FFFFFF], dtype=np.uint32).view(np.float32)[0]


class CameraIntrinsics(Protocol):
    """A pinhole camera: image size (pixels), focal lengths and principal point (pixels)."""

    @property
    def width(self) -> int:
        """Image width (pixels)."""
        ...
    @property
    def height(self) -> int:
        """Image height (pixels)."""
        ...
    @property
    def fx(self) -> float:
        """Focal length along x (pixels)."""
        ...
    @property
    def fy(self) -> float:
        """Focal length along y (pixels)."""
        ...
    @property
    def cx(self) -> float:
        """Principal point x (pixels)."""
        ...
    @property
    def cy(self) -> float:
        """Principal point y (pixels)."""
        ...


@dataclass(frozen=True, slots=True)
class SceneQuads:
    """Planar convex quads, the surfaces a depth camera sees.

    ``corners`` (N, 4, 3) world m, in order around the quad; ``normals`` (N, 3) unit, outward;
    ``two_sided`` (N,) bool (walls are seen from both sides, box faces only from outside);
    ``is_wall`` (N,) bool.
    """

    corners: F64Array
    normals: F64Array
    two_sided: npt.NDArray[np.bool_]
    is_wall: npt.NDArray[np.bool_]

    def __len__(self) -> int:
        return int(self.corners.shape[0])

    @classmethod
    def empty(cls) -> SceneQuads:
        """No quads."""
        return cls(np.zeros((0, 4, 3)), np.zeros((0, 3)), np.zeros(0, dtype=bool),
                   np.zeros(0, dtype=bool))

    @classmethod
    def boxes(cls, T_world_boxes: npt.ArrayLike, half_extents: npt.ArrayLike) -> SceneQuads:
        """The six faces of each box: poses (M, 4, 4) of the box centres, half sides (M, 3) m."""
        T = np.asarray(T_world_boxes, dtype=np.float64).reshape(-1, 4, 4)
        half = np.asarray(half_extents, dtype=np.float64).reshape(-1, 3)
        if T.shape[0] == 0:
            return cls.empty()
        corners, normals = [], []
        for axis in range(3):
            i, j = (axis + 1) % 3, (axis + 2) % 3
            for sign in (1.0, -1.0):
                n_box = np.zeros(3)
                n_box[axis] = sign
                local = np.zeros((T.shape[0], 4, 3))
                local[:, :, axis] = sign * half[:, None, axis]
                for k, (a, b) in enumerate(((1, 1), (1, -1), (-1, -1), (-1, 1))):
                    local[:, k, i] = a * half[:, i]
                    local[:, k, j] = b * half[:, j]
                R, t = T[:, :3, :3], T[:, :3, 3]
                corners.append(np.einsum("mij,mkj->mki", R, local) + t[:, None, :])
                normals.append(R @ n_box)
        n = len(corners)
        return cls(
            np.concatenate(corners), np.concatenate(normals),
            np.zeros(n * T.shape[0], dtype=bool), np.zeros(n * T.shape[0], dtype=bool),
        )

    @classmethod
    def walls(cls, walls: WallSegments) -> SceneQuads:
        """Each wall face as a vertical quad from the ground to its height."""
        if len(walls) == 0:
            return cls.empty()
        a, b, h = walls.starts, walls.ends, walls.heights
        zero = np.zeros_like(h)
        corners = np.stack([
            np.column_stack([a, zero]), np.column_stack([b, zero]),
            np.column_stack([b, h]), np.column_stack([a, h]),
        ], axis=1)
        e = b - a
        normals = np.column_stack([e[:, 1], -e[:, 0], zero])
        length = np.linalg.norm(normals, axis=1)
        keep = length > 0.0
        normals = normals[keep] / length[keep, None]
        n = int(keep.sum())
        return cls(corners[keep], normals, np.ones(n, dtype=bool), np.ones(n, dtype=bool))

    @classmethod
    def from_world(cls, world: World) -> SceneQuads:
        """Every box face and wall face of ``world``."""
        parts = [cls.walls(WallSegments.from_world(world))]
        if world.boxes:
            parts.append(cls.boxes(np.stack([b.T_world_box for b in world.boxes]),
                                   [box_half_extents(b) for b in world.boxes]))
        return cls.concat(parts)

    @classmethod
    def concat(cls, parts: list[SceneQuads]) -> SceneQuads:
        """All quads of ``parts``, in order."""
        parts = [p for p in parts if len(p)]
        if not parts:
            return cls.empty()
        return cls(
            np.concatenate([p.corners for p in parts]),
            np.concatenate([p.normals for p in parts]),
            np.concatenate([p.two_sided for p in parts]),
            np.concatenate([p.is_wall for p in parts]),
        )


def clip_near(poly: F64Array, near: float) -> F64Array:
    """Sutherland-Hodgman clip of a polygon (K x 3, optical frame) to ``z >= near``."""
    out: list[F64Array] = []
    n = len(poly)
    for k in range(n):
        a, b = poly[k], poly[(k + 1) % n]
        a_in, b_in = a[2] >= near, b[2] >= near
        if a_in:
            out.append(a)
        if a_in != b_in:
            out.append(a + (near - a[2]) / (b[2] - a[2]) * (b - a))
    return np.array(out) if out else np.zeros((0, 3))


def rasterize(
    camera: CameraIntrinsics,
    T_world_optical: npt.ArrayLike,
    quads: SceneQuads,
    *,
    max_depth: float = math.inf,
    inverse_depth: F32Array | None = None,
    index: I32Array | None = None,
) -> tuple[F32Array, I32Array]:
    """Z-buffer ``quads`` seen from ``T_world_optical`` (4x4, optical frame in the world).

    Args:
        camera: image size and intrinsics (pixels).
        T_world_optical: pose of the optical frame (x right, y down, z forward).
        quads: the geometry.
        max_depth: quads wholly farther than this along the optical axis are skipped (m).
        inverse_depth: ``(H, W)`` float32 buffer to draw into (``1/z``, 0 = nothing);
            a new zero buffer when ``None``.
        index: ``(H, W)`` int32 buffer of the winning quad (-1 = none), drawn with it.

    Returns:
        ``(inverse_depth, index)``: ``1/z`` (1/m) of the nearest quad at each pixel and
        that quad's index in ``quads``.
    """
    W, H = int(camera.width), int(camera.height)
    fx, fy, cx, cy = float(camera.fx), float(camera.fy), float(camera.cx), float(camera.cy)
    if inverse_depth is None:
        inverse_depth = np.zeros((H, W), dtype=np.float32)
    if index is None:
        index = np.full((H, W), -1, dtype=np.int32)
    if len(quads) == 0:
        return inverse_depth, index
    T = np.asarray(T_world_optical, dtype=np.float64)
    R, t = T[:3, :3], T[:3, 3]
    P = (quads.corners - t) @ R  # (N, 4, 3) optical: R^T (p - t)
    n_o = quads.normals @ R
    c = np.einsum("nk,nk->n", n_o, P[:, 0])  # plane n . p = c
    z = P[:, :, 2]
    visible = (z.max(axis=1) > _CLIP_Z) & (z.min(axis=1) <= max_depth) & (np.abs(c) > 1e-12)
    # One-sided faces: the camera (origin) must be outside, n . (0 - p0) > 0, i.e. c < 0.
    visible &= quads.two_sided | (c < 0.0)
    # Frustum: drop quads wholly left/right/above/below the image (all corners in front).
    with np.errstate(divide="ignore", invalid="ignore"):
        u = fx * P[:, :, 0] / z + cx
        v = fy * P[:, :, 1] / z + cy
    in_front = z.min(axis=1) > _CLIP_Z
    outside = ((u.max(axis=1) < -0.5) | (u.min(axis=1) > W - 0.5)
               | (v.max(axis=1) < -0.5) | (v.min(axis=1) > H - 0.5))
    visible &= ~(in_front & outside)
    # Nearest first: a quad whose nearest point is behind everything already drawn over its
    # bounding box is skipped after one pass over that box (occlusion cull).
    candidates = np.flatnonzero(visible)
    for q in candidates[np.argsort(z[candidates].min(axis=1), kind="stable")]:
        poly = P[q] if in_front[q] else clip_near(P[q], _CLIP_Z)
        if len(poly) < 3:
            continue
        pu = fx * poly[:, 0] / poly[:, 2] + cx
        pv = fy * poly[:, 1] / poly[:, 2] + cy
        x0, x1 = max(math.ceil(pu.min()), 0), min(math.floor(pu.max()) + 1, W)
        y0, y1 = max(math.ceil(pv.min()), 0), min(math.floor(pv.max()) + 1, H)
        if x1 <= x0 or y1 <= y0:
            continue
        if float(inverse_depth[y0:y1, x0:x1].min()) > 1.0 / float(poly[:, 2].min()):
            continue
        us = np.arange(x0, x1, dtype=np.float32)
        vs = np.arange(y0, y1, dtype=np.float32)
        # Coverage: the pixel centre is on the inner side of every edge (either winding).
        area2 = float(np.dot(pu, np.roll(pv, -1)) - np.dot(pv, np.roll(pu, -1)))
        if area2 == 0.0:
            continue
        s = 1.0 if area2 > 0.0 else -1.0
        inside = np.ones((y1 - y0, x1 - x0), dtype=bool)
        for k in range(len(pu)):
            ax, ay = pu[k], pv[k]
            bx, by = pu[(k + 1) % len(pu)], pv[(k + 1) % len(pu)]
            # (b - a) x (p - a) >= 0 for a counter-clockwise (in u, v) polygon.
            ev = np.float32(s * (bx - ax)) * (vs - np.float32(ay))
            eu = np.float32(-s * (by - ay)) * (us - np.float32(ax))
            inside &= np.add.outer(ev, eu) >= np.float32(-1e-6)
        n = n_o[q] if c[q] < 0.0 else -n_o[q]
        cq = c[q] if c[q] < 0.0 else -c[q]
        # 1/z = (n_x (u - cx)/fx + n_y (v - cy)/fy + n_z) / c
        wu = (np.float32(n[0] / (fx * cq)) * (us - np.float32(cx)))
        wv = (np.float32(n[1] / (fy * cq)) * (vs - np.float32(cy))) + np.float32(n[2] / cq)
        w = np.add.outer(wv, wu)
        roi = inverse_depth[y0:y1, x0:x1]
        win = inside & (w > roi)
        roi[win] = w[win]
        index[y0:y1, x0:x1][win] = q
    return inverse_depth, index


def ground_inverse_depth(camera: CameraIntrinsics, T_world_optical: npt.ArrayLike) -> F32Array:
    """``(H, W)`` inverse depth (1/m) of the ground plane ``z = 0``; 0 where a ray misses it.

    In the optical frame the ground is ``n . p = -t_z`` with ``n = R^T e_z`` (``t_z`` the
    camera height); a camera at or below the ground sees none.
    """
    T = np.asarray(T_world_optical, dtype=np.float64)
    W, H = int(camera.width), int(camera.height)
    height = float(T[2, 3])
    if height <= 0.0:
        return np.zeros((H, W), dtype=np.float32)
    n = T[2, :3]  # world z axis in optical coordinates (row 2 of R)
    cq = -height
    us = np.arange(W, dtype=np.float32) - np.float32(camera.cx)
    vs = np.arange(H, dtype=np.float32) - np.float32(camera.cy)
    w: F32Array = np.add.outer(np.float32(n[1] / (camera.fy * cq)) * vs + np.float32(n[2] / cq),
                               np.float32(n[0] / (camera.fx * cq)) * us)
    np.maximum(w, np.float32(0.0), out=w)
    return w


@dataclass(frozen=True, slots=True)
class DepthParams:
    """A depth camera: its frame, rate, image size, field of view, range and noise.

    ``frame_id``, ``rate_hz`` (Hz), image ``width`` x ``height`` (px), ``hfov`` (rad; fx = fy =
    (W/2)/tan(hfov/2), cx = W/2, cy = H/2 as gz-sensors derives them),
    ``min_depth``/``max_depth`` (m), noise (module doc): ``noise_stddev`` (m),
    ``disparity_stddev`` (px), ``stereo_focal_px`` (px), ``baseline`` (m).
    """

    frame_id: str = "oak_rgb_camera_optical_frame"
    rate_hz: float = 30.0
    width: int = 1280
    height: int = 720
    hfov: float = math.radians(60.0)
    min_depth: float = 1.0
    max_depth: float = 12.0
    noise_stddev: float = 0.0
    disparity_stddev: float = 0.1
    stereo_focal_px: float = 640.0 / math.tan(math.radians(36.0))
    baseline: float = 0.075

    def __post_init__(self) -> None:
        if self.width < 1 or self.height < 1:
            raise ValueError(f"depth image size must be positive, got {self.width}x{self.height}")
        if not 0.0 < self.hfov < math.pi:
            raise ValueError(f"depth hfov must be in (0, pi) rad, got {self.hfov}")
        if not 0.0 <= self.min_depth < self.max_depth:
            raise ValueError(f"need 0 <= min_depth < max_depth, got {self.min_depth}, "
                             f"{self.max_depth}")
        if not (self.rate_hz > 0.0 and self.noise_stddev >= 0.0 and self.disparity_stddev >= 0.0
                and self.stereo_focal_px > 0.0 and self.baseline > 0.0):
            raise ValueError("depth rate_hz, stereo_focal_px and baseline must be > 0 and the "
                             "noise terms >= 0")

    @property
    def fx(self) -> float:
        """Focal length along u (px)."""
        return (self.width / 2.0) / math.tan(self.hfov / 2.0)

    @property
    def fy(self) -> float:
        """Focal length along v (px): square pixels."""
        return self.fx

    @property
    def cx(self) -> float:
        """Principal point u (px)."""
        return self.width / 2.0

    @property
    def cy(self) -> float:
        """Principal point v (px)."""
        return self.height / 2.0

    def noise_sigma(self, depth: npt.ArrayLike) -> npt.NDArray[np.floating]:
        """Standard deviation (m) of the depth noise at ``depth`` (m)."""
        z = np.asarray(depth)
        k = self.disparity_stddev / (self.stereo_focal_px * self.baseline)
        out: npt.NDArray[np.floating] = self.noise_stddev + k * z * z
        return out


#: The ROSbot's OAK-D depth as Husarion's description configures it (module doc).
DEFAULT_DEPTH = DepthParams()


class DepthCamera:
    """Depth frames of ``world`` (see the module doc); ``seed`` fixes the noise."""

    def __init__(self, world: World, params: DepthParams = DEFAULT_DEPTH, *, seed: int = 0,
                 ground: bool = True) -> None:
        self.params = params
        self.seed = int(seed)
        self.ground = ground
        self.quads = SceneQuads.from_world(world)
        self._bank: F32Array | None = None

    def _normals(self, frame_index: int) -> F32Array:
        """(H, W) standard normals of frame ``frame_index``.

        A window of one seeded bank at an offset drawn from ``(seed, frame_index)`` (a crop
        instead of a million draws).
        """
        p = self.params
        if self._bank is None:
            rng = np.random.default_rng(self.seed)
            self._bank = rng.standard_normal((p.height + _BANK_PAD, p.width + _BANK_PAD),
                                             dtype=np.float32)
        dy, dx = (int(v) for v in np.random.default_rng((self.seed, frame_index)).integers(
            0, _BANK_PAD, size=2))
        return self._bank[dy : dy + p.height, dx : dx + p.width]

    def true_inverse_depth(self, T_world_optical: npt.ArrayLike) -> F32Array:
        """Noise-free inverse depth (H, W) float32, 1/m.

        0 where nothing is seen within the cull distance (twice ``max_depth``).
        """
        p = self.params
        w = ground_inverse_depth(p, T_world_optical) if self.ground else None
        w, _ = rasterize(p, T_world_optical, self.quads, max_depth=2.0 * p.max_depth,
                         inverse_depth=w)
        return w

    def true_depth(self, T_world_optical: npt.ArrayLike) -> F32Array:
        """Noise-free depth (H, W) float32, m along the optical axis.

        ``inf`` where nothing is seen within the cull distance (twice ``max_depth``).
        """
        with np.errstate(divide="ignore"):
            depth: F32Array = np.divide(np.float32(1.0), self.true_inverse_depth(T_world_optical),
                                        dtype=np.float32)
        return depth

    def frame(self, T_world_optical: npt.ArrayLike, frame_index: int) -> F32Array:
        """The reported depth image of frame number ``frame_index``.

        float32 metres with noise, ``+inf`` for no return or at/beyond ``max_depth``, ``-inf``
        at/below ``min_depth``.

        The stereo term is drawn in disparity: ``1/z' = 1/z - n sigma_d / (f B)`` with one
        standard normal ``n`` per pixel, and the constant term adds ``noise_stddev n`` to
        ``z'`` (the same ``n``: the deviations add, sigma = noise_stddev + z^2 sigma_d / (f B)
        to first order). A disparity pushed to or past zero is beyond range (+inf).
        """
        p = self.params
        w = self.true_inverse_depth(T_world_optical)
        hit = w > 0.0
        n: F32Array | None = None
        if p.noise_stddev > 0.0 or p.disparity_stddev > 0.0:
            n = self._normals(int(frame_index))
            if p.disparity_stddev > 0.0:
                k = np.float32(p.disparity_stddev / (p.stereo_focal_px * p.baseline))
                noisy = np.multiply(n, -k, dtype=np.float32)
                noisy += w
                np.copyto(noisy, np.float32(0.0), where=~hit)
                w = noisy
        with np.errstate(divide="ignore"):
            z: F32Array = np.divide(np.float32(1.0), w, dtype=np.float32)
        if n is not None and p.noise_stddev > 0.0:
            z += np.float32(p.noise_stddev) * n
        z[(w <= np.float32(1.0 / p.max_depth)) | (z >= p.max_depth)] = np.inf
        z[hit & (z <= p.min_depth)] = -np.inf
        return z


#: Rows of the cloud written per block: 8 x 1280 points x 32 bytes = 320 KiB stays in a core's
#: cache while all of a point's fields are written.
_BLOCK_ROWS = 8


def _fill_points(out: F32Array, depth: F32Array, camera: CameraIntrinsics,
                 point: F32Array | None = None) -> bool:
    """Write x, y, z of ``depth`` into channels 0-2 of ``out`` (H, W, C); True if all finite.

    NaN where the depth is not finite. With ``point`` (C,), every point is first set to it
    (the constant fields and padding; copied from a row of it, which numpy does far faster
    than broadcasting one point). Written in blocks of :data:`_BLOCK_ROWS` rows, each
    finished while in cache: every byte of ``out`` goes to memory once.
    """
    H, W = depth.shape
    xs = (np.arange(W, dtype=np.float32) - np.float32(camera.cx)) / np.float32(camera.fx)
    ys = (np.arange(H, dtype=np.float32) - np.float32(camera.cy)) / np.float32(camera.fy)
    row = None if point is None else np.tile(point, (W, 1))
    dense = True
    for r0 in range(0, H, _BLOCK_ROWS):
        r1 = min(r0 + _BLOCK_ROWS, H)
        block, z = out[r0:r1], depth[r0:r1]
        finite = np.isfinite(z)
        if not finite.all():
            dense = False
            z = np.where(finite, z, np.float32(np.nan))
        if row is not None:
            block[...] = row
        np.multiply(z, xs[None, :], out=block[:, :, 0])
        np.multiply(z, ys[r0:r1, None], out=block[:, :, 1])
        block[:, :, 2] = z
    return dense


def depth_points(depth: npt.ArrayLike, camera: CameraIntrinsics) -> F32Array:
    """``(H, W, 3)`` float32 points (m, optical frame) of a depth image.

    NaN where the depth is not finite.
    """
    z = np.asarray(depth, dtype=np.float32)
    out = np.empty((*z.shape, 3), dtype=np.float32)
    _fill_points(out, z, camera)
    return out


#: The cloud's fields: x, y, z, rgb float32 at 0, 4, 8, 16; 32 bytes a point.
_CLOUD_FIELDS = xyz_fields(rgb=True)
_CLOUD_STEP = 32
#: One point before its x, y, z are written: rgb white, padding zero.
_CLOUD_POINT = np.zeros(_CLOUD_STEP // 4, dtype=np.float32)
_CLOUD_POINT[4] = _WHITE_RGB


def depth_cloud(depth: npt.ArrayLike, camera: CameraIntrinsics, header: Header) -> PointCloud2:
    """The organised PointCloud2 (x, y, z, rgb; point_step 32) of a depth image.

    A new buffer per cloud: the published array is handed to the subscribers (the in-process
    bus freezes and shares it), so it is never reused.
    """
    z = np.asarray(depth, dtype=np.float32)
    H, W = z.shape
    buf = np.empty((H, W, _CLOUD_STEP // 4), dtype=np.float32)
    dense = _fill_points(buf, z, camera, _CLOUD_POINT)
    return PointCloud2(
        header=header, height=H, width=W, fields=[copy(f) for f in _CLOUD_FIELDS],
        is_bigendian=False, point_step=_CLOUD_STEP, row_step=_CLOUD_STEP * W,
        data=buf.reshape(-1).view(np.uint8), is_dense=dense,
    )


def depth_image_msg(depth: F32Array, header: Header) -> Image:
    """A ``32FC1`` Image (metres) of a float32 depth image."""
    return numpy_to_image(np.asarray(depth, dtype=np.float32), "32FC1", header)
