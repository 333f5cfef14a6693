"""geometry_msgs: points, vectors, quaternions (x, y, z, w; w defaults to 1), poses, twists.

Field names and defaults are those of ROS 2 Jazzy, so code written for rclpy messages (and
messages from rosbags) works by duck typing. Covariances are 36-element row-major float64
numpy arrays (6x6 over x, y, z, rotation about X, Y, Z).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np
import numpy.typing as npt

from posekit.msgs._base import array_aware_eq
from posekit.msgs.std_msgs import Header

__all__ = [
    "Point",
    "PointStamped",
    "Pose",
    "PoseStamped",
    "PoseWithCovariance",
    "PoseWithCovarianceStamped",
    "Quaternion",
    "Transform",
    "TransformStamped",
    "Twist",
    "TwistStamped",
    "TwistWithCovariance",
    "Vector3",
    "Vector3Stamped",
]


def _zero_covariance() -> npt.NDArray[np.float64]:
    return np.zeros(36, dtype=np.float64)


@dataclass(slots=True)
class Vector3:
    """geometry_msgs/msg/Vector3: a free vector (directions, velocities), metres or per second."""

    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    __msgtype__: ClassVar[str] = "geometry_msgs/msg/Vector3"


@dataclass(slots=True)
class Point:
    """geometry_msgs/msg/Point: a position in metres."""

    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    __msgtype__: ClassVar[str] = "geometry_msgs/msg/Point"


@dataclass(slots=True)
class Quaternion:
    """geometry_msgs/msg/Quaternion, stored in ROS order (x, y, z, w); the default is identity."""

    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    w: float = 1.0
    __msgtype__: ClassVar[str] = "geometry_msgs/msg/Quaternion"


@dataclass(slots=True)
class Pose:
    """geometry_msgs/msg/Pose: position and orientation of a body in some frame."""

    position: Point = field(default_factory=Point)
    orientation: Quaternion = field(default_factory=Quaternion)
    __msgtype__: ClassVar[str] = "geometry_msgs/msg/Pose"


@dataclass(slots=True)
class PoseStamped:
    """geometry_msgs/msg/PoseStamped."""

    header: Header = field(default_factory=Header)
    pose: Pose = field(default_factory=Pose)
    __msgtype__: ClassVar[str] = "geometry_msgs/msg/PoseStamped"


@dataclass(slots=True)
class PointStamped:
    """geometry_msgs/msg/PointStamped."""

    header: Header = field(default_factory=Header)
    point: Point = field(default_factory=Point)
    __msgtype__: ClassVar[str] = "geometry_msgs/msg/PointStamped"


@dataclass(slots=True)
class Vector3Stamped:
    """geometry_msgs/msg/Vector3Stamped."""

    header: Header = field(default_factory=Header)
    vector: Vector3 = field(default_factory=Vector3)
    __msgtype__: ClassVar[str] = "geometry_msgs/msg/Vector3Stamped"


@dataclass(slots=True)
class Transform:
    """geometry_msgs/msg/Transform: maps child-frame coordinates into the parent frame."""

    translation: Vector3 = field(default_factory=Vector3)
    rotation: Quaternion = field(default_factory=Quaternion)
    __msgtype__: ClassVar[str] = "geometry_msgs/msg/Transform"


@dataclass(slots=True)
class TransformStamped:
    """geometry_msgs/msg/TransformStamped: T_parent_child with parent ``header.frame_id``."""

    header: Header = field(default_factory=Header)
    child_frame_id: str = ""
    transform: Transform = field(default_factory=Transform)
    __msgtype__: ClassVar[str] = "geometry_msgs/msg/TransformStamped"


@dataclass(slots=True)
class Twist:
    """geometry_msgs/msg/Twist: linear (m/s) and angular (rad/s) velocity."""

    linear: Vector3 = field(default_factory=Vector3)
    angular: Vector3 = field(default_factory=Vector3)
    __msgtype__: ClassVar[str] = "geometry_msgs/msg/Twist"


@dataclass(slots=True)
class TwistStamped:
    """geometry_msgs/msg/TwistStamped (the ROSbot's ``/cmd_vel`` type)."""

    header: Header = field(default_factory=Header)
    twist: Twist = field(default_factory=Twist)
    __msgtype__: ClassVar[str] = "geometry_msgs/msg/TwistStamped"


@dataclass(slots=True, eq=False)
class PoseWithCovariance:
    """geometry_msgs/msg/PoseWithCovariance: covariance is float64[36], row-major 6x6."""

    pose: Pose = field(default_factory=Pose)
    covariance: npt.NDArray[np.float64] = field(default_factory=_zero_covariance)
    __msgtype__: ClassVar[str] = "geometry_msgs/msg/PoseWithCovariance"

    __eq__ = array_aware_eq


@dataclass(slots=True, eq=False)
class PoseWithCovarianceStamped:
    """geometry_msgs/msg/PoseWithCovarianceStamped (RViz2's "2D Pose Estimate" on
    ``initialpose``, robot_localization's ``set_pose``)."""

    header: Header = field(default_factory=Header)
    pose: PoseWithCovariance = field(default_factory=PoseWithCovariance)
    __msgtype__: ClassVar[str] = "geometry_msgs/msg/PoseWithCovarianceStamped"

    __eq__ = array_aware_eq


@dataclass(slots=True, eq=False)
class TwistWithCovariance:
    """geometry_msgs/msg/TwistWithCovariance: covariance is float64[36], row-major 6x6."""

    twist: Twist = field(default_factory=Twist)
    covariance: npt.NDArray[np.float64] = field(default_factory=_zero_covariance)
    __msgtype__: ClassVar[str] = "geometry_msgs/msg/TwistWithCovariance"

    __eq__ = array_aware_eq
