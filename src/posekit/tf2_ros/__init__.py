"""``from posekit.tf2_ros import ...``: tf2_ros's Python names, re-exported.

``Buffer`` and the exceptions come from :mod:`posekit.tf2`; the broadcasters, the listener
and the QoS profiles of tf2's topics live here, on top of :mod:`posekit.runtime` (as
geometry2's tf2_ros_py sits on rclpy and tf2). Submodules mirror tf2_ros
(``posekit.tf2_ros.buffer``, ``.transform_listener``, ``.transform_broadcaster``,
``.static_transform_broadcaster``, ``.qos``).
"""

from __future__ import annotations

from posekit.tf2 import Buffer
from posekit.tf2.exceptions import (
    ConnectivityException,
    ExtrapolationException,
    InvalidArgumentException,
    LookupException,
    TimeoutException,
    TransformException,
    TypeException,
)
from posekit.tf2_ros.qos import (
    DynamicBroadcasterQoS,
    DynamicListenerQoS,
    StaticBroadcasterQoS,
    StaticListenerQoS,
)
from posekit.tf2_ros.static_transform_broadcaster import StaticTransformBroadcaster
from posekit.tf2_ros.transform_broadcaster import TransformBroadcaster
from posekit.tf2_ros.transform_listener import TransformListener

__all__ = [
    "Buffer",
    "ConnectivityException",
    "DynamicBroadcasterQoS",
    "DynamicListenerQoS",
    "ExtrapolationException",
    "InvalidArgumentException",
    "LookupException",
    "StaticBroadcasterQoS",
    "StaticListenerQoS",
    "StaticTransformBroadcaster",
    "TimeoutException",
    "TransformBroadcaster",
    "TransformException",
    "TransformListener",
    "TypeException",
]

