"""Point clouds for the page's PointCloud2 display, compact: float32 points, no padding.

A ``sensor_msgs/PointCloud2`` is laid out for its producer (the simulated OAK-D's is 1280x720
points of 32 bytes: 29.5 MB). :func:`compact_point_cloud` turns it into a
:class:`CompactCloud` the display feed sends as packed arrays: the finite points' ``x, y,
z`` as one float32 array (12 bytes a point), with the ``intensity`` field as float32 and an
``rgb``/``rgba`` field as three uint8 per point when the cloud has them; at most
``max_points`` points, an organised cloud thinned by taking every ``stride``-th row and
column (its image structure kept), an unordered one every ``stride``-th point.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from posekit.msgs.point_cloud2 import PointCloudError, read_points
from posekit.msgs.sensor_msgs import PointCloud2
from posekit.msgs.std_msgs import Header

__all__ = ["MAX_CLOUD_POINTS", "CompactCloud", "compact_point_cloud"]

#: Points sent per cloud at most (1.2 MB of float32 x, y, z).
MAX_CLOUD_POINTS = 100_000


def _empty_f32() -> npt.NDArray[np.float32]:
    return np.zeros(0, dtype=np.float32)


def _empty_u8() -> npt.NDArray[np.uint8]:
    return np.zeros(0, dtype=np.uint8)


@dataclass(slots=True)
class CompactCloud:
    """What the PointCloud2 display draws: ``points`` (3N float32 x, y, z, m, in
    ``header.frame_id``), ``intensity`` (N float32, empty if the cloud has none), ``rgb``
    (3N uint8, empty if none); ``total`` points in the message, ``stride`` of the thinning,
    ``fields`` of the message (names)."""

    header: Header = field(default_factory=Header)
    total: int = 0
    stride: int = 1
    fields: list[str] = field(default_factory=list)
    points: npt.NDArray[np.float32] = field(default_factory=_empty_f32)
    intensity: npt.NDArray[np.float32] = field(default_factory=_empty_f32)
    rgb: npt.NDArray[np.uint8] = field(default_factory=_empty_u8)


def compact_point_cloud(msg: PointCloud2, max_points: int = MAX_CLOUD_POINTS) -> CompactCloud:
    """The finite points of ``msg`` (at most ``max_points``), see the module docstring.

    Raises:
        posekit.msgs.point_cloud2.PointCloudError: an inconsistent layout, or no x, y, z.
    """
    names = [str(f.name) for f in msg.fields]
    missing = [n for n in ("x", "y", "z") if n not in names]
    if missing:
        raise PointCloudError(f"the cloud has no {', '.join(missing)} field (it has {names})")
    cloud = read_points(msg)
    h, w = int(msg.height), int(msg.width)
    total = h * w
    if h > 1:  # organised: every stride-th row and column
        stride = max(1, math.ceil(math.sqrt(total / max_points)))
        cloud = cloud.reshape(h, w)[::stride, ::stride].reshape(-1)
    else:
        stride = max(1, math.ceil(total / max_points))
        cloud = cloud[::stride]
    xyz = np.empty((cloud.shape[0], 3), dtype=np.float32)
    for i, n in enumerate(("x", "y", "z")):
        xyz[:, i] = cloud[n]
    keep = np.isfinite(xyz).all(axis=1)
    out = CompactCloud(header=msg.header, total=total, stride=stride, fields=names,
                       points=np.ascontiguousarray(xyz[keep]).reshape(-1))
    if "intensity" in names:
        out.intensity = np.asarray(cloud["intensity"], dtype=np.float32)[keep]
    colour = "rgb" if "rgb" in names else "rgba" if "rgba" in names else None
    if colour is not None:
        packed = np.ascontiguousarray(cloud[colour][keep]).view(np.uint32)
        out.rgb = np.stack([(packed >> 16) & 0xFF, (packed >> 8) & 0xFF, packed & 0xFF],
                           axis=1).astype(np.uint8).reshape(-1)
    return out
