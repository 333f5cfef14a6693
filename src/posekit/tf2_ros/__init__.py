"""``from posekit.tf2_ros import ...``: tf2_ros's Python names, re-exported.

``Buffer`` and the exceptions come from :mod:`posekit.tf2`; the broadcasters and the
listener from :mod:`posekit.runtime.tf2_ros`. Submodules mirror tf2_ros
(``posekit.tf2_ros.buffer``, ``.transform_listener``, ``.transform_broadcaster``,
``.static_transform_broadcaster``).
"""

from __future__ import annotations

from posekit.runtime.tf2_ros import (
    DynamicBroadcasterQoS,
    DynamicListenerQoS,
    StaticBroadcasterQoS,
    StaticListenerQoS,
    StaticTransformBroadcaster,
    TransformBroadcaster,
    TransformListener,
)
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

