"""sensor_msgs: the sensor messages the system uses.

Image, CameraInfo, Imu, JointState, LaserScan, PointCloud2, PointField, RegionOfInterest.

Bulk fields are numpy arrays, never per-element Python lists: ``Image.data`` is a 1-D uint8
array (or bytes), covariances and the camera matrices are float64 arrays of the ROS length,
``LaserScan.ranges`` and ``intensities`` are float32 arrays, ``PointCloud2.data`` a uint8
array (:mod:`posekit.msgs.point_cloud2` reads and builds clouds as numpy structured arrays).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np
import numpy.typing as npt

from posekit.msgs._base import array_aware_eq
from posekit.msgs.geometry_msgs import Quaternion, Vector3
from posekit.msgs.std_msgs import Header

__all__ = [
    "CameraInfo",
    "Image",
    "Imu",
    "JointState",
    "LaserScan",
    "PointCloud2",
    "PointField",
    "RegionOfInterest",
]


def _f64(n: int) -> npt.NDArray[np.float64]:
    return np.zeros(n, dtype=np.float64)


def _empty_f64() -> npt.NDArray[np.float64]:
    return np.zeros(0, dtype=np.float64)


def _empty_f32() -> npt.NDArray[np.float32]:
    return np.zeros(0, dtype=np.float32)


def _empty_u8() -> npt.NDArray[np.uint8]:
    return np.zeros(0, dtype=np.uint8)


@dataclass(slots=True, eq=False)
class Image:
    """sensor_msgs/msg/Image: ``data`` holds ``height * step`` bytes as a uint8 array."""

    header: Header = field(default_factory=Header)
    height: int = 0
    width: int = 0
    encoding: str = ""
    is_bigendian: int = 0
    step: int = 0
    data: npt.NDArray[np.uint8] = field(default_factory=_empty_u8)
    __msgtype__: ClassVar[str] = "sensor_msgs/msg/Image"
    __eq__ = array_aware_eq


@dataclass(slots=True)
class RegionOfInterest:
    """sensor_msgs/msg/RegionOfInterest."""

    x_offset: int = 0
    y_offset: int = 0
    height: int = 0
    width: int = 0
    do_rectify: bool = False
    __msgtype__: ClassVar[str] = "sensor_msgs/msg/RegionOfInterest"


@dataclass(slots=True, eq=False)
class CameraInfo:
    """sensor_msgs/msg/CameraInfo: intrinsics ``k`` (3x3), ``r`` (3x3), ``p`` (3x4), row-major."""

    header: Header = field(default_factory=Header)
    height: int = 0
    width: int = 0
    distortion_model: str = ""
    d: npt.NDArray[np.float64] = field(default_factory=_empty_f64)
    k: npt.NDArray[np.float64] = field(default_factory=lambda: _f64(9))
    r: npt.NDArray[np.float64] = field(default_factory=lambda: _f64(9))
    p: npt.NDArray[np.float64] = field(default_factory=lambda: _f64(12))
    binning_x: int = 0
    binning_y: int = 0
    roi: RegionOfInterest = field(default_factory=RegionOfInterest)
    __msgtype__: ClassVar[str] = "sensor_msgs/msg/CameraInfo"
    __eq__ = array_aware_eq


@dataclass(slots=True, eq=False)
class Imu:
    """sensor_msgs/msg/Imu: orientation, angular velocity (rad/s), linear acceleration (m/s²)."""

    header: Header = field(default_factory=Header)
    orientation: Quaternion = field(default_factory=Quaternion)
    orientation_covariance: npt.NDArray[np.float64] = field(default_factory=lambda: _f64(9))
    angular_velocity: Vector3 = field(default_factory=Vector3)
    angular_velocity_covariance: npt.NDArray[np.float64] = field(default_factory=lambda: _f64(9))
    linear_acceleration: Vector3 = field(default_factory=Vector3)
    linear_acceleration_covariance: npt.NDArray[np.float64] = field(
        default_factory=lambda: _f64(9)
    )
    __msgtype__: ClassVar[str] = "sensor_msgs/msg/Imu"
    __eq__ = array_aware_eq


@dataclass(slots=True, eq=False)
class JointState:
    """sensor_msgs/msg/JointState: positions (rad), velocities (rad/s), efforts per joint name."""

    header: Header = field(default_factory=Header)
    name: list[str] = field(default_factory=list)
    position: npt.NDArray[np.float64] = field(default_factory=_empty_f64)
    velocity: npt.NDArray[np.float64] = field(default_factory=_empty_f64)
    effort: npt.NDArray[np.float64] = field(default_factory=_empty_f64)
    __msgtype__: ClassVar[str] = "sensor_msgs/msg/JointState"
    __eq__ = array_aware_eq


@dataclass(slots=True, eq=False)
class LaserScan:
    """sensor_msgs/msg/LaserScan: one sweep of a planar range finder in ``header.frame_id``.

    Angles (rad) are about the frame's +z axis, counter-clockwise, 0 along +x; ``ranges[i]``
    (m) is at ``angle_min + i * angle_increment``. ``time_increment`` is the time between
    two beams and ``scan_time`` the time between scans (s). Per REP 117 a beam with no
    return is ``+inf``, one closer than ``range_min`` is ``-inf`` and an erroneous one NaN.
    """

    header: Header = field(default_factory=Header)
    angle_min: float = 0.0
    angle_max: float = 0.0
    angle_increment: float = 0.0
    time_increment: float = 0.0
    scan_time: float = 0.0
    range_min: float = 0.0
    range_max: float = 0.0
    ranges: npt.NDArray[np.float32] = field(default_factory=_empty_f32)
    intensities: npt.NDArray[np.float32] = field(default_factory=_empty_f32)
    __msgtype__: ClassVar[str] = "sensor_msgs/msg/LaserScan"
    __eq__ = array_aware_eq


@dataclass(slots=True)
class PointField:
    """sensor_msgs/msg/PointField: one field of a point.

    ``name``, byte ``offset`` in the point, ``datatype`` (one of the constants below) and
    ``count`` elements.
    """

    INT8: ClassVar[int] = 1
    UINT8: ClassVar[int] = 2
    INT16: ClassVar[int] = 3
    UINT16: ClassVar[int] = 4
    INT32: ClassVar[int] = 5
    UINT32: ClassVar[int] = 6
    FLOAT32: ClassVar[int] = 7
    FLOAT64: ClassVar[int] = 8

    name: str = ""
    offset: int = 0
    datatype: int = 0
    count: int = 0
    __msgtype__: ClassVar[str] = "sensor_msgs/msg/PointField"


@dataclass(slots=True, eq=False)
class PointCloud2:
    """sensor_msgs/msg/PointCloud2: ``height`` rows of ``width`` points.

    ``height`` is 1 for an unordered cloud; each point is ``point_step`` bytes laid out by
    ``fields``; ``row_step`` bytes per row; ``is_dense`` false when some points are invalid
    (NaN).
    """

    header: Header = field(default_factory=Header)
    height: int = 0
    width: int = 0
    fields: list[PointField] = field(default_factory=list)
    is_bigendian: bool = False
    point_step: int = 0
    row_step: int = 0
    data: npt.NDArray[np.uint8] = field(default_factory=_empty_u8)
    is_dense: bool = False
    __msgtype__: ClassVar[str] = "sensor_msgs/msg/PointCloud2"
    __eq__ = array_aware_eq
