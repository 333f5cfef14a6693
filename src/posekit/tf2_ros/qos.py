"""tf2_ros.qos: the QoS profiles of tf2's topics (docs/specs/tf2.md §9).

Dynamic ``/tf``: KEEP_LAST 100, RELIABLE, VOLATILE. Static ``/tf_static``: RELIABLE,
TRANSIENT_LOCAL (latched); the broadcaster keeps depth 1 (one cumulative message), the
listener depth 100.
"""

from __future__ import annotations

from posekit.runtime.qos import DurabilityPolicy, HistoryPolicy, QoSProfile

__all__ = [
    "DynamicBroadcasterQoS",
    "DynamicListenerQoS",
    "StaticBroadcasterQoS",
    "StaticListenerQoS",
]


def DynamicListenerQoS(depth: int = 100) -> QoSProfile:
    """tf2_ros::DynamicListenerQoS: KEEP_LAST depth, RELIABLE, VOLATILE."""
    return QoSProfile(depth=depth)


def DynamicBroadcasterQoS(depth: int = 100) -> QoSProfile:
    """tf2_ros::DynamicBroadcasterQoS: KEEP_LAST depth, RELIABLE, VOLATILE."""
    return QoSProfile(depth=depth)


def StaticListenerQoS(depth: int = 100) -> QoSProfile:
    """tf2_ros::StaticListenerQoS: KEEP_LAST depth, RELIABLE, TRANSIENT_LOCAL."""
    return QoSProfile(
        depth=depth, history=HistoryPolicy.KEEP_LAST, durability=DurabilityPolicy.TRANSIENT_LOCAL
    )


def StaticBroadcasterQoS(depth: int = 1) -> QoSProfile:
    """tf2_ros::StaticBroadcasterQoS: KEEP_LAST depth (1), RELIABLE, TRANSIENT_LOCAL."""
    return QoSProfile(
        depth=depth, history=HistoryPolicy.KEEP_LAST, durability=DurabilityPolicy.TRANSIENT_LOCAL
    )
