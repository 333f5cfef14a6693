"""ROS 2 message types as light dataclasses (numpy only), laid out as ROS 2 Jazzy defines them.

Import paths mirror ROS packages: ``from posekit.msgs.geometry_msgs import TransformStamped``.
Every class has ``__msgtype__`` (e.g. ``"geometry_msgs/msg/TransformStamped"``), is
constructible with no arguments (ROS defaults) or by keyword, and has assignable fields.
CDR serialization lives in :mod:`posekit.msgs.cdr` and loads rosbags only when used.
"""

from __future__ import annotations

from posekit.msgs import (
    builtin_interfaces,
    geometry_msgs,
    nav_msgs,
    rosgraph_msgs,
    sensor_msgs,
    std_msgs,
    tf2_msgs,
)

__all__ = [
    "builtin_interfaces",
    "geometry_msgs",
    "nav_msgs",
    "rosgraph_msgs",
    "sensor_msgs",
    "std_msgs",
    "tf2_msgs",
]
