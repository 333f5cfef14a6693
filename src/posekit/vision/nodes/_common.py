"""Helpers shared by the vision nodes: image decoding with named rejections, intrinsics from
``CameraInfo``, per-id marker sizes, TF messages from PnP results and poses."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

from posekit.geometry import Transform
from posekit.msgs.builtin_interfaces import Time as TimeMsg
from posekit.msgs.errors import ImageConversionError
from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.image import image_to_numpy
from posekit.time import NS_PER_S

__all__ = [
    "DETECTABLE_ENCODINGS",
    "NS",
    "ImageRejectedError",
    "bgr_canvas",
    "camera_matrix_from_info",
    "decode_for_detection",
    "parse_marker_sizes",
    "pose_from_chain",
    "transform_msg",
]

NS = NS_PER_S
F64Array = npt.NDArray[np.float64]
U8Array = npt.NDArray[np.uint8]

#: Encodings the detectors accept (8-bit; colour orders are converted for the debug image).
DETECTABLE_ENCODINGS = ("rgb8", "bgr8", "mono8", "rgba8", "bgra8", "8UC1", "8UC3", "8UC4")


class ImageRejectedError(ValueError):
    """An image the detectors cannot use; the message says why (logged, then skipped)."""


def decode_for_detection(msg: Any) -> U8Array:
    """The pixels of an Image message as the detector takes them: ``(H, W)`` or ``(H, W, 3)``
    uint8, a view of ``msg.data`` when possible (read-only if published; draw on
    :func:`bgr_canvas`). Four-channel images become grey.

    Raises:
        ImageRejectedError: unsupported encoding, empty image, or sizes inconsistent with data.
    """
    encoding = str(msg.encoding)
    if encoding not in DETECTABLE_ENCODINGS:
        raise ImageRejectedError(
            f"unsupported image encoding {encoding!r}; the detector takes "
            f"{', '.join(DETECTABLE_ENCODINGS)}"
        )
    if int(msg.width) <= 0 or int(msg.height) <= 0:
        raise ImageRejectedError(f"empty image ({msg.width}x{msg.height}, encoding {encoding})")
    try:
        array = image_to_numpy(msg)
    except ImageConversionError as exc:
        raise ImageRejectedError(f"malformed image: {exc}") from exc
    if array.ndim == 3 and array.shape[2] == 4:
        code = cv2.COLOR_RGBA2GRAY if encoding == "rgba8" else cv2.COLOR_BGRA2GRAY
        return np.asarray(cv2.cvtColor(array, code), dtype=np.uint8)
    return np.asarray(array, dtype=np.uint8)


def bgr_canvas(array: U8Array, encoding: str) -> U8Array:
    """A new writable BGR image of ``array`` (decoded with ``encoding``) to draw on."""
    if array.ndim == 2:
        return np.asarray(cv2.cvtColor(array, cv2.COLOR_GRAY2BGR), dtype=np.uint8)
    if encoding == "rgb8":
        return np.asarray(cv2.cvtColor(array, cv2.COLOR_RGB2BGR), dtype=np.uint8)
    return array.copy()


def camera_matrix_from_info(msg: Any) -> tuple[F64Array, F64Array]:
    """``(K 3x3, d)`` of a CameraInfo, validated.

    Raises:
        ValueError: ``k`` is not 9 finite values with positive focal lengths and k[8] = 1,
            or ``d`` is not finite.
    """
    k = np.asarray(msg.k, dtype=np.float64).reshape(-1)
    d = np.asarray(msg.d, dtype=np.float64).reshape(-1)
    if k.size != 9 or not np.all(np.isfinite(k)) or k[0] <= 0.0 or k[4] <= 0.0 or k[8] != 1.0:
        raise ValueError(f"CameraInfo.k is not a valid intrinsic matrix: {k.tolist()}")
    if not np.all(np.isfinite(d)) or d.size not in (0, 4, 5, 8, 12, 14):
        raise ValueError(f"CameraInfo.d must hold 0/4/5/8/12/14 finite values, got {d.tolist()}")
    return k.reshape(3, 3).copy(), d.copy()


def parse_marker_sizes(text: str) -> dict[int, float]:
    """Per-id marker sizes from ``"id:size,id:size"`` (metres), e.g. ``"4:0.2,7:0.1"``.

    Raises:
        ValueError: malformed entry, duplicate id, or a size that is not a positive number.
    """
    sizes: dict[int, float] = {}
    for item in (s.strip() for s in str(text).split(",")):
        if not item:
            continue
        key, sep, value = item.partition(":")
        try:
            marker_id, size = int(key), float(value)
        except ValueError:
            marker_id, size = -1, math.nan
        if not sep or marker_id < 0 or not (math.isfinite(size) and size > 0.0):
            raise ValueError(
                f"marker_sizes entry {item!r} is not 'id:size' with id >= 0 and size > 0 m"
            )
        if marker_id in sizes:
            raise ValueError(f"marker_sizes lists id {marker_id} twice")
        sizes[marker_id] = size
    return sizes


def transform_msg(parent: str, child: str, stamp: Any, translation: Iterable[float],
                  quaternion_xyzw: Iterable[float]) -> TransformStamped:
    """``TransformStamped`` T_parent_child (translation in metres, quaternion x, y, z, w)."""
    t = TransformStamped()
    t.header.stamp = TimeMsg(sec=int(stamp.sec), nanosec=int(stamp.nanosec))
    t.header.frame_id = parent
    t.child_frame_id = child
    tr, q = t.transform.translation, t.transform.rotation
    tr.x, tr.y, tr.z = (float(v) for v in translation)
    q.x, q.y, q.z, q.w = (float(v) for v in quaternion_xyzw)
    return t


def pose_from_chain(
    joints: Iterable[tuple[str, str, Sequence[float], Sequence[float]]], root: str, frame: str
) -> F64Array:
    """``T_root_frame`` composed along fixed joints ``(parent, child, xyz, rpy)``.

    Raises:
        KeyError: ``frame`` is not below ``root`` in the joint tree.
    """
    parent_of = {child: (parent, xyz, rpy) for parent, child, xyz, rpy in joints}
    T = Transform.identity()
    current = frame
    seen = set()
    while current != root:
        if current not in parent_of or current in seen:
            raise KeyError(f"frame {frame!r} is not below {root!r} in the robot description")
        seen.add(current)
        parent, xyz, rpy = parent_of[current]
        T = Transform.from_xyz_rpy(xyz, rpy) * T
        current = parent
    return T.as_matrix()
