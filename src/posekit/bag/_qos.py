"""QoS between posekit's runtime and rosbag2 metadata (``offered_qos_profiles``).

rosbag2 stores, per topic, the QoS every publisher *offered* when the recorder discovered it
(what the offers are and the profile the recorder subscribes with are the passive observer's:
:mod:`posekit.runtime.observe`); the player publishes with a profile derived from the recorded
offers (rosbag2's adaptive QoS).

Durations (deadline, lifespan, liveliness lease) are not modelled by posekit's runtime; they
are written as rmw's "infinite" (9223372036 s 854775807 ns), as ROS 2 records default
publishers. Liveliness is written as AUTOMATIC.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from posekit.runtime.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    QoSProfile,
    ReliabilityPolicy,
)

__all__ = [
    "INFINITE_NSEC",
    "INFINITE_SEC",
    "from_rosbags_qos",
    "playback_qos",
    "to_rosbags_qos",
]

#: rmw's RMW_DURATION_INFINITE split as ROS 2 writes it into bag metadata.
INFINITE_SEC = 9223372036
INFINITE_NSEC = 854775807
#: Upper bound of the late-joiner history the player keeps per transient-local topic.
_MAX_LATCHED = 1000


def to_rosbags_qos(profile: QoSProfile) -> Any:
    """The rosbags ``Qos`` record of ``profile`` with policies resolved as a publisher offers
    them (SYSTEM_DEFAULT / BEST_AVAILABLE become RELIABLE and VOLATILE; KEEP_ALL has depth 0).
    """
    from rosbags.interfaces import (
        Qos,
        QosDurability,
        QosHistory,
        QosLiveliness,
        QosReliability,
        QosTime,
    )

    infinite = QosTime(INFINITE_SEC, INFINITE_NSEC)
    keep_all = profile.history == HistoryPolicy.KEEP_ALL
    return Qos(
        history=QosHistory.KEEP_ALL if keep_all else QosHistory.KEEP_LAST,
        depth=0 if keep_all else profile.depth,
        reliability=QosReliability(int(profile.resolved_reliability)),
        durability=QosDurability(int(profile.resolved_durability)),
        deadline=infinite,
        lifespan=infinite,
        liveliness=QosLiveliness.AUTOMATIC,
        liveliness_lease_duration=infinite,
        avoid_ros_namespace_conventions=False,
    )


def _value(policy: Any) -> int:
    return int(getattr(policy, "value", policy))


def from_rosbags_qos(qos: Any) -> QoSProfile:
    """posekit's profile for a recorded rosbags ``Qos`` (unknown policies: ROS defaults)."""
    try:
        history = HistoryPolicy(_value(qos.history))
    except ValueError:
        history = HistoryPolicy.KEEP_LAST
    if history not in (HistoryPolicy.KEEP_LAST, HistoryPolicy.KEEP_ALL):
        history = HistoryPolicy.KEEP_LAST
    depth = int(qos.depth)
    if history == HistoryPolicy.KEEP_LAST and depth < 1:
        depth = 10  # ROS 2 graph reports depth 0 for foreign publishers; use rclpy's default
    reliability = (
        ReliabilityPolicy.BEST_EFFORT
        if _value(qos.reliability) == int(ReliabilityPolicy.BEST_EFFORT)
        else ReliabilityPolicy.RELIABLE
    )
    durability = (
        DurabilityPolicy.TRANSIENT_LOCAL
        if _value(qos.durability) == int(DurabilityPolicy.TRANSIENT_LOCAL)
        else DurabilityPolicy.VOLATILE
    )
    return QoSProfile(
        history=history, depth=max(depth, 0), reliability=reliability, durability=durability
    )


def playback_qos(offered: Sequence[QoSProfile], message_count: int) -> QoSProfile:
    """Publisher profile for playing a topic back.

    Reliable unless a recorded publisher was best effort; transient local when every recorded
    publisher was. A transient-local topic keeps up to ``message_count`` messages (at most
    1000) for late subscribers, so a bag holding several static broadcasters' /tf_static
    messages hands *all* of them to a listener that starts late (a single depth-1 publisher
    would keep only the last broadcaster's transforms).
    """
    if not offered:
        offered = [QoSProfile(depth=10)]
    transient = all(p.resolved_durability == DurabilityPolicy.TRANSIENT_LOCAL for p in offered)
    best_effort = any(p.resolved_reliability == ReliabilityPolicy.BEST_EFFORT for p in offered)
    depth = max([p.depth for p in offered if p.history == HistoryPolicy.KEEP_LAST] + [1])
    depth = max(depth, min(message_count, _MAX_LATCHED)) if transient else max(depth, 10)
    return QoSProfile(
        depth=depth,
        reliability=ReliabilityPolicy.BEST_EFFORT if best_effort else ReliabilityPolicy.RELIABLE,
        durability=(
            DurabilityPolicy.TRANSIENT_LOCAL if transient else DurabilityPolicy.VOLATILE
        ),
    )
