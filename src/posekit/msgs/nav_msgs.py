"""nav_msgs: Odometry."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

from posekit.msgs.geometry_msgs import PoseWithCovariance, TwistWithCovariance
from posekit.msgs.std_msgs import Header

__all__ = ["Odometry"]


@dataclass(slots=True)
class Odometry:
    """nav_msgs/msg/Odometry: pose in ``header.frame_id``, twist in ``child_frame_id``."""

    header: Header = field(default_factory=Header)
    child_frame_id: str = ""
    pose: PoseWithCovariance = field(default_factory=PoseWithCovariance)
    twist: TwistWithCovariance = field(default_factory=TwistWithCovariance)
    __msgtype__: ClassVar[str] = "nav_msgs/msg/Odometry"
