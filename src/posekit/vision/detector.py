"""ArUco detection and marker pose by PnP (``SOLVEPNP_IPPE_SQUARE``), as in the course, plus
both IPPE solutions with their reprojection errors.

Conventions
-----------
* Image points: ``cv2.aruco.ArucoDetector.detectMarkers`` corners, pixels, order TL, TR, BR,
  BL of the marker as printed (not as it appears rotated in the image).
* Object points: ``[-L/2, L/2, 0], [L/2, L/2, 0], [L/2, -L/2, 0], [-L/2, -L/2, 0]`` — the
  order ``SOLVEPNP_IPPE_SQUARE`` requires. The marker frame has its origin at the marker's
  centre, x right, y up, z out of the marker towards a viewer.
* Poses are ``T_camera_marker``: marker coordinates to camera *optical* coordinates (x right,
  y down, z forward), i.e. the transform a TF message ``camera_optical_frame ->
  aruco_marker_<id>`` carries. Translation in metres (the unit of ``marker_size``),
  quaternions ``(x, y, z, w)`` with ``w >= 0``.

IPPE ambiguity: a small or distant square seen nearly head-on has two poses, mirrored about
the line of sight, that reproject almost equally well; OpenCV's ``solvePnP`` silently returns
the one with the lower error. :class:`MarkerDetection` keeps both (``pose`` and
``alternative``) and ``ambiguity_ratio = pose error / alternative error``: near 0 the choice
is clear, near 1 the two are indistinguishable and the orientation may flip between frames
(the translation is affected much less).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

from posekit.geometry import Rotation, Transform
from posekit.msgs.sensor_msgs import CameraInfo
from posekit.vision.errors import CameraModelError, InvalidImageError
from posekit.worlds import marker_corners_local

__all__ = [
    "ArucoMarkerDetector",
    "MarkerDetection",
    "PoseCandidate",
    "as_detector_image",
    "draw_detections",
]

F64Array = npt.NDArray[np.float64]
U8Array = npt.NDArray[np.uint8]


@dataclass(frozen=True, slots=True)
class PoseCandidate:
    """One PnP solution ``T_camera_marker``.

    Attributes:
        rvec: rotation as an axis-angle vector (3,), radians (OpenCV's ``rvec``).
        translation: marker centre in the camera optical frame (3,), metres (``tvec``).
        quaternion_xyzw: rotation as a unit quaternion (x, y, z, w), ``w >= 0``.
        reprojection_error: RMS over the 8 corner coordinates (u and v of 4 corners) of
            detected minus reprojected, pixels, as OpenCV's ``solvePnPGeneric`` reports it
            (the per-corner RMS distance is sqrt(2) times larger).
    """

    rvec: F64Array
    translation: F64Array
    quaternion_xyzw: F64Array
    reprojection_error: float

    @property
    def rotation_matrix(self) -> F64Array:
        """3x3 rotation ``R_camera_marker``."""
        R, _ = cv2.Rodrigues(self.rvec)
        return np.asarray(R, dtype=np.float64)

    @property
    def T_camera_marker(self) -> F64Array:
        """4x4 homogeneous ``T_camera_marker``."""
        return Transform(Rotation.from_quat(self.quaternion_xyzw), self.translation).as_matrix()


@dataclass(frozen=True, slots=True)
class MarkerDetection:
    """One detected marker and its pose.

    Attributes:
        marker_id: ArUco id.
        corners: detected corners (4, 2), pixels, TL TR BR BL.
        marker_size: side length used for the pose, metres.
        pose: the IPPE solution with the lower reprojection error (what ``cv2.solvePnP``
            with ``SOLVEPNP_IPPE_SQUARE`` returns).
        alternative: the other IPPE solution, or ``None`` if OpenCV returned only one.
    """

    marker_id: int
    corners: F64Array
    marker_size: float
    pose: PoseCandidate
    alternative: PoseCandidate | None

    @property
    def translation(self) -> F64Array:
        """Marker centre in the camera optical frame, metres (``pose.translation``)."""
        return self.pose.translation

    @property
    def quaternion_xyzw(self) -> F64Array:
        """Marker orientation in the camera optical frame, (x, y, z, w)."""
        return self.pose.quaternion_xyzw

    @property
    def rvec(self) -> F64Array:
        """Marker orientation as OpenCV's axis-angle ``rvec``."""
        return self.pose.rvec

    @property
    def reprojection_error(self) -> float:
        """RMS reprojection error of ``pose``, pixels."""
        return self.pose.reprojection_error

    @property
    def T_camera_marker(self) -> F64Array:
        """4x4 ``T_camera_marker`` of ``pose``."""
        return self.pose.T_camera_marker

    @property
    def ambiguity_ratio(self) -> float:
        """``pose.reprojection_error / alternative.reprojection_error`` in [0, 1].

        Near 1: both IPPE solutions explain the corners equally well (pose-flip risk).
        ``nan`` when there is no alternative; 0 when the alternative's error is infinite.
        """
        if self.alternative is None:
            return math.nan
        alt = self.alternative.reprojection_error
        if alt <= 0.0:
            return 1.0
        return self.pose.reprojection_error / alt if math.isfinite(alt) else 0.0


def as_detector_image(image: Any) -> U8Array:
    """Validate an image for detection: a non-empty uint8 array, (H, W), (H, W, 1|3|4).

    Three-channel images are used as they are (OpenCV converts with BGR weights; for rgb8
    input this only changes the grey weighting of colours, not the geometry); four-channel
    images are converted to grey.

    Raises:
        InvalidImageError: not a numpy array, empty, wrong dtype or shape.
    """
    if not isinstance(image, np.ndarray):
        raise InvalidImageError(f"image must be a numpy.ndarray, got {type(image).__name__}")
    if image.dtype != np.uint8:
        raise InvalidImageError(f"image dtype must be uint8, got {image.dtype}")
    if image.ndim not in (2, 3) or (image.ndim == 3 and image.shape[2] not in (1, 3, 4)):
        raise InvalidImageError(
            f"image shape must be (H, W) or (H, W, 1|3|4), got {image.shape}"
        )
    if image.shape[0] == 0 or image.shape[1] == 0:
        raise InvalidImageError(f"image is empty, shape {image.shape}")
    if image.ndim == 3 and image.shape[2] == 1:
        return image[:, :, 0]
    if image.ndim == 3 and image.shape[2] == 4:
        return np.asarray(cv2.cvtColor(image, cv2.COLOR_BGRA2GRAY), dtype=np.uint8)
    return image


_DEGENERATE_ERROR_PX = 1.0
_NUDGE = np.array([[1e-3, 0.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0]], dtype=np.float32)


def _dictionary_id(dictionary: str | int) -> int:
    if isinstance(dictionary, int):
        return dictionary
    value = getattr(cv2.aruco, dictionary, None)
    if not isinstance(value, int) or not dictionary.startswith("DICT_"):
        raise ValueError(f"unknown ArUco dictionary {dictionary!r} (expected e.g. 'DICT_5X5_250')")
    return value


class ArucoMarkerDetector:
    """Detects ArUco markers and estimates each one's pose in the camera optical frame.

    Args:
        camera_matrix: 3x3 intrinsics ``K`` (pixels), e.g. ``CameraInfo.k`` reshaped.
        dist_coeffs: distortion coefficients (OpenCV order), ``None`` for none.
        marker_size: side length of every marker, metres (the black square incl. its border).
        marker_sizes: per-id side lengths overriding ``marker_size``, metres.
        dictionary: OpenCV predefined dictionary name (``"DICT_5X5_250"``) or constant.
        refine_subpixel: refine corners with ``CORNER_REFINE_SUBPIX`` (default off, as in
            the course).
        detector_parameters: a ``cv2.aruco.DetectorParameters`` to start from.

    Raises:
        CameraModelError: malformed camera matrix or distortion.
        ValueError: unknown dictionary or non-positive marker size.
    """

    def __init__(
        self,
        camera_matrix: npt.ArrayLike,
        dist_coeffs: npt.ArrayLike | None = None,
        *,
        marker_size: float = 0.2,
        marker_sizes: Mapping[int, float] | None = None,
        dictionary: str | int = "DICT_5X5_250",
        refine_subpixel: bool = False,
        detector_parameters: Any | None = None,
    ) -> None:
        K = np.asarray(camera_matrix, dtype=np.float64)
        if K.size != 9:
            raise CameraModelError(f"camera_matrix must have 9 elements, got {K.size}")
        K = K.reshape(3, 3)
        if not np.all(np.isfinite(K)) or K[0, 0] <= 0.0 or K[1, 1] <= 0.0 or K[2, 2] != 1.0:
            raise CameraModelError(f"camera_matrix is not a valid intrinsic matrix: {K.tolist()}")
        d = np.zeros(0) if dist_coeffs is None else np.asarray(dist_coeffs, dtype=np.float64)
        d = d.reshape(-1)
        if not np.all(np.isfinite(d)) or d.size not in (0, 4, 5, 8, 12, 14):
            raise CameraModelError(f"dist_coeffs must be 0/4/5/8/12/14 finite values, got {d}")
        self.camera_matrix = K
        self.dist_coeffs = d
        sizes = {int(k): float(v) for k, v in (marker_sizes or {}).items()}
        for marker_id, size in [(-1, marker_size), *sizes.items()]:
            if not (math.isfinite(size) and size > 0.0):
                raise ValueError(f"marker size must be positive (id {marker_id}), got {size}")
        self.marker_size = float(marker_size)
        self.marker_sizes = sizes
        self.refine_subpixel = bool(refine_subpixel)
        params = detector_parameters if detector_parameters is not None else (
            cv2.aruco.DetectorParameters()
        )
        if self.refine_subpixel:
            params.cornerRefinementMethod = cv2.aruco.CORNER_REFINE_SUBPIX
        self._dictionary = cv2.aruco.getPredefinedDictionary(_dictionary_id(dictionary))
        self._detector = cv2.aruco.ArucoDetector(self._dictionary, params)
        self._object_points: dict[float, npt.NDArray[np.float32]] = {}

    @classmethod
    def from_camera_info(cls, msg: CameraInfo, **kwargs: Any) -> ArucoMarkerDetector:
        """Detector using ``msg.k`` and ``msg.d`` (as the course's nodes cache them)."""
        return cls(np.asarray(msg.k, dtype=np.float64), np.asarray(msg.d, dtype=np.float64),
                   **kwargs)

    def size_of(self, marker_id: int) -> float:
        """Side length used for ``marker_id``, metres."""
        return self.marker_sizes.get(int(marker_id), self.marker_size)

    def object_points(self, marker_size: float) -> npt.NDArray[np.float32]:
        """Object points (4x3 float32) of a marker: TL, TR, BR, BL at z = 0 (IPPE_SQUARE order)."""
        pts = self._object_points.get(marker_size)
        if pts is None:
            pts = marker_corners_local(marker_size).astype(np.float32)
            self._object_points[marker_size] = pts
        return pts

    def detect_corners(self, image: Any) -> tuple[list[int], list[F64Array]]:
        """Marker ids and their corners (4x2 float64 each), detection only.

        Raises:
            InvalidImageError: see :func:`as_detector_image`.
        """
        img = as_detector_image(image)
        corners, ids, _ = self._detector.detectMarkers(img)
        if ids is None or len(ids) == 0:
            return [], []
        return ([int(i) for i in ids.reshape(-1)],
                [np.asarray(c, dtype=np.float64).reshape(4, 2) for c in corners])

    def estimate_pose(
        self, corners: npt.ArrayLike, marker_size: float
    ) -> tuple[PoseCandidate, PoseCandidate | None] | None:
        """Both IPPE_SQUARE solutions for one marker's corners (best first), ``None`` on failure."""
        image_points = np.asarray(corners, dtype=np.float32).reshape(4, 2)
        object_points = self.object_points(marker_size)
        candidates = self._solve(object_points, image_points)
        if not candidates or candidates[0].reprojection_error > _DEGENERATE_ERROR_PX:
            # On an exactly fronto-parallel square (integer corners of a head-on marker can
            # be one) OpenCV's IPPE returns the identity rotation with tens of pixels of error
            # or a NaN rvec, and still reports success. A 1e-3 px nudge breaks the tie.
            retry = self._solve(object_points, image_points + _NUDGE)
            if retry and (not candidates or retry[0].reprojection_error
                          < candidates[0].reprojection_error):
                candidates = retry
        if not candidates:
            return None
        return candidates[0], (candidates[1] if len(candidates) > 1 else None)

    def _solve(self, object_points: npt.NDArray[np.float32],
               image_points: npt.NDArray[np.float32]) -> list[PoseCandidate]:
        """Finite IPPE_SQUARE solutions, lowest reprojection error first."""
        n, rvecs, tvecs, errors = cv2.solvePnPGeneric(
            object_points, image_points, self.camera_matrix, self.dist_coeffs,
            flags=cv2.SOLVEPNP_IPPE_SQUARE,
        )
        errs = np.asarray(errors, dtype=np.float64).reshape(-1).tolist() if n else []
        candidates: list[PoseCandidate] = []
        for k in range(int(n)):
            rvec = rvecs[k].reshape(3).astype(np.float64)
            tvec = tvecs[k].reshape(3).astype(np.float64)
            err = errs[k] if k < len(errs) else math.inf
            # a NaN anywhere makes the sum NaN (one scalar check instead of two array scans)
            if not math.isfinite(float(rvec.sum() + tvec.sum()) + err):
                continue
            candidates.append(
                PoseCandidate(
                    rvec=rvec,
                    translation=tvec,
                    quaternion_xyzw=Rotation.from_rotvec(rvec).as_quat(canonical=True),
                    reprojection_error=err,
                )
            )
        candidates.sort(key=lambda c: c.reprojection_error)
        return candidates

    def detect(self, image: Any) -> list[MarkerDetection]:
        """Detect every marker and estimate its pose; empty list when none is found.

        Raises:
            InvalidImageError: see :func:`as_detector_image`.
        """
        ids, all_corners = self.detect_corners(image)
        out: list[MarkerDetection] = []
        for marker_id, corners in zip(ids, all_corners, strict=True):
            size = self.size_of(marker_id)
            solved = self.estimate_pose(corners, size)
            if solved is None:
                continue
            best, alt = solved
            out.append(MarkerDetection(marker_id, corners, size, best, alt))
        return out


def draw_detections(
    image: U8Array,
    detections: Sequence[MarkerDetection],
    camera_matrix: npt.ArrayLike,
    dist_coeffs: npt.ArrayLike | None = None,
    *,
    axis_ratio: float = 0.5,
    thickness: int = 2,
) -> U8Array:
    """Debug image: a 3-channel copy with marker outlines, ids and pose axes.

    Axes are drawn with ``cv2.drawFrameAxes`` at ``axis_ratio * marker_size`` (the course
    uses half the marker size); x red, y green, z blue when the image is shown as BGR.

    Raises:
        InvalidImageError: see :func:`as_detector_image`.
    """
    as_detector_image(image)
    if image.ndim == 2 or image.shape[2] == 1:
        canvas = cv2.cvtColor(image.reshape(image.shape[:2]), cv2.COLOR_GRAY2BGR)
    elif image.shape[2] == 4:
        canvas = cv2.cvtColor(image, cv2.COLOR_BGRA2BGR)
    else:
        canvas = image.copy()
    if not detections:
        return np.asarray(canvas, dtype=np.uint8)
    K = np.asarray(camera_matrix, dtype=np.float64).reshape(3, 3)
    d = np.zeros(0) if dist_coeffs is None else np.asarray(dist_coeffs, dtype=np.float64)
    corners = [det.corners.reshape(1, 4, 2).astype(np.float32) for det in detections]
    ids = np.array([[det.marker_id] for det in detections], dtype=np.int32)
    cv2.aruco.drawDetectedMarkers(canvas, corners, ids)
    for det in detections:
        cv2.drawFrameAxes(canvas, K, d, det.pose.rvec, det.pose.translation,
                          det.marker_size * axis_ratio, thickness)
    return np.asarray(canvas, dtype=np.uint8)
