"""Quality-of-service profiles with rclpy's names and defaults.

A :class:`QoSProfile` says how a publisher or subscription treats its message history:

* ``history`` / ``depth``: KEEP_LAST keeps at most ``depth`` undelivered messages per
  subscription (the oldest is dropped when a callback falls behind); KEEP_ALL keeps them all.
* ``reliability``: RELIABLE or BEST_EFFORT. A BEST_EFFORT publisher does not connect to a
  RELIABLE subscription (incompatible offer, as in DDS and rmw_zenoh); the reverse works.
  In-process no link loses messages, so the two deliver the same messages (docs/runtime.md).
* ``durability``: VOLATILE or TRANSIENT_LOCAL. A TRANSIENT_LOCAL publisher keeps its last
  ``depth`` messages and hands them to TRANSIENT_LOCAL subscriptions that join later (the
  "latched" /tf_static). A VOLATILE publisher does not connect to a TRANSIENT_LOCAL
  subscription (incompatible offer).
* ``lifespan``: a :class:`posekit.time.Duration` (None: infinite). A TRANSIENT_LOCAL
  publisher's history forgets messages older than this (wall time since publishing), so a
  late subscription receives only recent ones (``/rosout`` keeps 10 s, as rcl does).

Everywhere a profile is accepted, an ``int`` means ``QoSProfile(depth=n)`` (rclpy's shorthand).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, replace
from typing import Any

__all__ = [
    "DurabilityPolicy",
    "HistoryPolicy",
    "QoSCompatibility",
    "QoSProfile",
    "ReliabilityPolicy",
    "check_qos_compatibility",
    "qos_profile_clock",
    "qos_profile_parameter_events",
    "qos_profile_parameters",
    "qos_profile_sensor_data",
    "qos_profile_services_default",
    "qos_profile_system_default",
    "qos_profile_unknown",
    "to_qos_profile",
]


class HistoryPolicy(enum.IntEnum):
    """rmw_qos_history_policy_t."""

    SYSTEM_DEFAULT = 0
    KEEP_LAST = 1
    KEEP_ALL = 2
    UNKNOWN = 3


class ReliabilityPolicy(enum.IntEnum):
    """rmw_qos_reliability_policy_t."""

    SYSTEM_DEFAULT = 0
    RELIABLE = 1
    BEST_EFFORT = 2
    UNKNOWN = 3
    BEST_AVAILABLE = 4


class DurabilityPolicy(enum.IntEnum):
    """rmw_qos_durability_policy_t."""

    SYSTEM_DEFAULT = 0
    TRANSIENT_LOCAL = 1
    VOLATILE = 2
    UNKNOWN = 3
    BEST_AVAILABLE = 4


@dataclass(frozen=True, slots=True)
class QoSProfile:
    """A QoS profile. Keyword construction as rclpy; ``depth`` is required with KEEP_LAST.

    ``QoSProfile(depth=10)`` is rclpy's default: KEEP_LAST 10, RELIABLE, VOLATILE.
    SYSTEM_DEFAULT / BEST_AVAILABLE policies resolve to RELIABLE and VOLATILE.
    """

    history: HistoryPolicy = HistoryPolicy.KEEP_LAST
    depth: int = 10
    reliability: ReliabilityPolicy = ReliabilityPolicy.RELIABLE
    durability: DurabilityPolicy = DurabilityPolicy.VOLATILE
    lifespan: Any = None  # posekit.time.Duration, None = infinite

    def __post_init__(self) -> None:
        object.__setattr__(self, "history", HistoryPolicy(self.history))
        object.__setattr__(self, "reliability", ReliabilityPolicy(self.reliability))
        object.__setattr__(self, "durability", DurabilityPolicy(self.durability))
        if isinstance(self.depth, bool) or not isinstance(self.depth, int):
            raise TypeError(f"QoSProfile depth must be an int, got {self.depth!r}")
        if self.depth < 0:
            raise ValueError(f"QoSProfile depth must be >= 0, got {self.depth}")
        if self.history == HistoryPolicy.KEEP_LAST and self.depth == 0:
            raise ValueError("QoSProfile with KEEP_LAST history needs depth >= 1")
        if self.lifespan is not None and not hasattr(self.lifespan, "nanoseconds"):
            raise TypeError(f"QoSProfile lifespan must be a Duration, got {self.lifespan!r}")

    @property
    def lifespan_ns(self) -> int | None:
        """The lifespan in nanoseconds, None when infinite (unset or >= rmw's infinity)."""
        if self.lifespan is None:
            return None
        ns = int(self.lifespan.nanoseconds)
        return None if ns <= 0 or ns >= _INFINITE_NS else ns

    @property
    def resolved_reliability(self) -> ReliabilityPolicy:
        """RELIABLE or BEST_EFFORT after resolving SYSTEM_DEFAULT / BEST_AVAILABLE."""
        if self.reliability == ReliabilityPolicy.BEST_EFFORT:
            return ReliabilityPolicy.BEST_EFFORT
        return ReliabilityPolicy.RELIABLE

    @property
    def resolved_durability(self) -> DurabilityPolicy:
        """TRANSIENT_LOCAL or VOLATILE after resolving SYSTEM_DEFAULT / BEST_AVAILABLE."""
        if self.durability == DurabilityPolicy.TRANSIENT_LOCAL:
            return DurabilityPolicy.TRANSIENT_LOCAL
        return DurabilityPolicy.VOLATILE

    @property
    def queue_limit(self) -> int | None:
        """Max messages kept per subscription queue (None = unbounded, KEEP_ALL)."""
        if self.history == HistoryPolicy.KEEP_ALL:
            return None
        return self.depth

    def with_(self, **changes: object) -> QoSProfile:
        """A copy with some fields changed."""
        return replace(self, **changes)  # type: ignore[arg-type]


def to_qos_profile(qos: QoSProfile | int) -> QoSProfile:
    """Accept a profile or rclpy's ``int`` depth shorthand; anything else is a TypeError."""
    if isinstance(qos, QoSProfile):
        return qos
    if isinstance(qos, int) and not isinstance(qos, bool):
        return QoSProfile(depth=qos)
    raise TypeError(f"expected a QoSProfile or an int history depth, got {qos!r}")


#: rmw's "infinite" duration (9223372036 s 854775807 ns).
_INFINITE_NS = 9223372036 * 1_000_000_000 + 854775807


class QoSCompatibility(enum.Enum):
    """Result of matching an offered (publisher) and a requested (subscription) profile."""

    OK = "ok"
    INCOMPATIBLE_RELIABILITY = "RELIABILITY"
    INCOMPATIBLE_DURABILITY = "DURABILITY"


def check_qos_compatibility(offered: QoSProfile, requested: QoSProfile) -> QoSCompatibility:
    """DDS request/offer matching for the two policies the in-process bus models."""
    if (
        offered.resolved_reliability == ReliabilityPolicy.BEST_EFFORT
        and requested.resolved_reliability == ReliabilityPolicy.RELIABLE
    ):
        return QoSCompatibility.INCOMPATIBLE_RELIABILITY
    if (
        offered.resolved_durability == DurabilityPolicy.VOLATILE
        and requested.resolved_durability == DurabilityPolicy.TRANSIENT_LOCAL
    ):
        return QoSCompatibility.INCOMPATIBLE_DURABILITY
    return QoSCompatibility.OK


#: rclpy's qos_profile_sensor_data: KEEP_LAST 5, BEST_EFFORT, VOLATILE.
qos_profile_sensor_data = QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT)
#: rclpy's qos_profile_system_default.
qos_profile_system_default = QoSProfile(
    history=HistoryPolicy.SYSTEM_DEFAULT,
    depth=10,
    reliability=ReliabilityPolicy.SYSTEM_DEFAULT,
    durability=DurabilityPolicy.SYSTEM_DEFAULT,
)
#: rclpy's qos_profile_parameters: KEEP_LAST 1000, RELIABLE, VOLATILE.
qos_profile_parameters = QoSProfile(depth=1000)
#: rclpy's qos_profile_parameter_events (/parameter_events): KEEP_LAST 1000, RELIABLE, VOLATILE.
qos_profile_parameter_events = QoSProfile(depth=1000)
#: rclpy's qos_profile_services_default: KEEP_LAST 10, RELIABLE, VOLATILE.
qos_profile_services_default = QoSProfile(depth=10)
#: Subscription QoS of rclpy's TimeSource on /clock: KEEP_LAST 1, BEST_EFFORT.
qos_profile_clock = QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT)
#: Placeholder for "unknown" (graph introspection of foreign endpoints).
qos_profile_unknown = QoSProfile(
    history=HistoryPolicy.UNKNOWN,
    depth=1,
    reliability=ReliabilityPolicy.UNKNOWN,
    durability=DurabilityPolicy.UNKNOWN,
)
