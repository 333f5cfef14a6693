"""Quality-of-service profiles with rclpy's names, defaults and (mutable) objects.

A :class:`QoSProfile` says how a publisher or subscription treats its message history:

* ``history`` / ``depth``: KEEP_LAST keeps at most ``depth`` undelivered messages per
  subscription (the oldest is dropped when a callback falls behind); KEEP_ALL keeps them all.
  A depth of 0 with SYSTEM_DEFAULT history (``qos_profile_system_default``) is the
  middleware's default: 10 in process (:data:`SYSTEM_DEFAULT_DEPTH`), 42 on Zenoh (rmw_zenoh's),
  1 on DDS (Cyclone's).
* ``reliability``: RELIABLE or BEST_EFFORT. A BEST_EFFORT publisher does not connect to a
  RELIABLE subscription (incompatible offer, as in DDS and rmw_zenoh); the reverse works.
  In-process no link loses messages, so the two deliver the same messages (docs/runtime.md).
* ``durability``: VOLATILE or TRANSIENT_LOCAL. A TRANSIENT_LOCAL publisher keeps its last
  ``depth`` messages and hands them to TRANSIENT_LOCAL subscriptions that join later (the
  "latched" /tf_static). A VOLATILE publisher does not connect to a TRANSIENT_LOCAL
  subscription (incompatible offer).
* ``lifespan``: a :class:`posekit.time.Duration`, 0 (the default) = infinite. A
  TRANSIENT_LOCAL publisher's history forgets messages older than this (wall time since
  publishing), so a late subscription receives only recent ones (``/rosout`` keeps 10 s, as
  rcl does).
* ``deadline``, ``liveliness``, ``liveliness_lease_duration``,
  ``avoid_ros_namespace_conventions``: stored, compared and printed as rclpy does, but not
  enforced by posekit's transports (no deadline or liveliness events; docs/ros2-users.md).

As in rclpy a profile is a mutable object (``profile.depth = 3``), the module's presets are
shared objects (changing ``qos_profile_sensor_data.depth`` changes it for every later user in
the process), and profiles compare by value but are unhashable. An endpoint keeps a snapshot
of the profile it was created with (:class:`EndpointInfo
<posekit.runtime.transport.EndpointInfo>` copies it), so changing a profile afterwards does
not change existing publishers or subscriptions: rclpy hands rcl a C copy too. As in rclpy,
``publisher.qos_profile`` is the object the publisher was created with.

Everywhere a profile is accepted, an ``int`` means ``QoSProfile(depth=n)`` (rclpy's shorthand).
"""

from __future__ import annotations

import enum
from typing import Any

from posekit.time import Duration

__all__ = [
    "SYSTEM_DEFAULT_DEPTH",
    "DeadlineBestAvailable",
    "DurabilityPolicy",
    "HistoryPolicy",
    "InvalidQoSProfileException",
    "LivelinessLeaseDurationeBestAvailable",
    "LivelinessPolicy",
    "OfferMatch",
    "QoSCompatibility",
    "QoSDurabilityPolicy",
    "QoSHistoryPolicy",
    "QoSLivelinessPolicy",
    "QoSPolicyEnum",
    "QoSPolicyKind",
    "QoSPresetProfiles",
    "QoSProfile",
    "QoSReliabilityPolicy",
    "ReliabilityPolicy",
    "match_offer",
    "qos_check_compatible",
    "qos_policy_name_from_kind",
    "qos_profile_action_status_default",
    "qos_profile_best_available",
    "qos_profile_clock",
    "qos_profile_default",
    "qos_profile_parameter_events",
    "qos_profile_parameters",
    "qos_profile_sensor_data",
    "qos_profile_services_default",
    "qos_profile_system_default",
    "qos_profile_unknown",
    "to_qos_profile",
]

#: Queue depth posekit's in-process bus uses for a depth of 0 (SYSTEM_DEFAULT history).
SYSTEM_DEFAULT_DEPTH = 10

#: rmw's "infinite" duration (9223372036 s 854775807 ns).
_INFINITE_NS = 9223372036 * 1_000_000_000 + 854775807


class QoSPolicyKind(enum.IntEnum):
    """rmw_qos_policy_kind_t (rclpy.qos.QoSPolicyKind)."""

    INVALID = 1 << 0
    DURABILITY = 1 << 1
    DEADLINE = 1 << 2
    LIVELINESS = 1 << 3
    RELIABILITY = 1 << 4
    HISTORY = 1 << 5
    LIFESPAN = 1 << 6
    DEPTH = 1 << 7
    LIVELINESS_LEASE_DURATION = 1 << 8
    AVOID_ROS_NAMESPACE_CONVENTIONS = 1 << 9


def qos_policy_name_from_kind(policy_kind: QoSPolicyKind | int) -> str:
    """The name of a :class:`QoSPolicyKind` (``16`` -> ``'RELIABILITY'``)."""
    return QoSPolicyKind(policy_kind).name


class InvalidQoSProfileException(Exception):  # noqa: N818 (rclpy's name)
    """rclpy's exception for an invalid profile (importable; posekit raises ValueError)."""

    def __init__(self, *args: object) -> None:
        Exception.__init__(self, "Invalid QoSProfile", *args)


class QoSPolicyEnum(enum.IntEnum):
    """Base of the policy enums: rclpy's short (lower-case) keys, as ``ros2 ... --qos-*``."""

    @classmethod
    def short_keys(cls) -> list[str]:
        """The members' names in lower case (``['system_default', 'reliable', ...]``)."""
        return [k.lower() for k in cls.__members__]

    @classmethod
    def get_from_short_key(cls, name: str) -> int:
        """The value (an int, as rclpy) of the member ``name``, case-insensitive."""
        return int(cls[name.upper()].value)

    @property
    def short_key(self) -> str:
        """This member's name in lower case (``BEST_EFFORT`` -> ``best_effort``)."""
        return self.name.lower()


class HistoryPolicy(QoSPolicyEnum):
    """rmw_qos_history_policy_t."""

    SYSTEM_DEFAULT = 0
    KEEP_LAST = 1
    KEEP_ALL = 2
    UNKNOWN = 3


class ReliabilityPolicy(QoSPolicyEnum):
    """rmw_qos_reliability_policy_t."""

    SYSTEM_DEFAULT = 0
    RELIABLE = 1
    BEST_EFFORT = 2
    UNKNOWN = 3
    BEST_AVAILABLE = 4


class DurabilityPolicy(QoSPolicyEnum):
    """rmw_qos_durability_policy_t."""

    SYSTEM_DEFAULT = 0
    TRANSIENT_LOCAL = 1
    VOLATILE = 2
    UNKNOWN = 3
    BEST_AVAILABLE = 4


class LivelinessPolicy(QoSPolicyEnum):
    """rmw_qos_liveliness_policy_t (stored, not enforced by posekit)."""

    SYSTEM_DEFAULT = 0
    AUTOMATIC = 1
    MANUAL_BY_TOPIC = 3
    UNKNOWN = 4
    BEST_AVAILABLE = 5


# rclpy's older names, still importable there
QoSHistoryPolicy = HistoryPolicy
QoSReliabilityPolicy = ReliabilityPolicy
QoSDurabilityPolicy = DurabilityPolicy
QoSLivelinessPolicy = LivelinessPolicy

#: rmw's RMW_QOS_DEADLINE_BEST_AVAILABLE.
DeadlineBestAvailable = Duration(nanoseconds=_INFINITE_NS - 1)
#: rmw's RMW_QOS_LIVELINESS_LEASE_DURATION_BEST_AVAILABLE (rclpy's spelling).
LivelinessLeaseDurationeBestAvailable = Duration(nanoseconds=_INFINITE_NS - 1)

_ZERO = Duration()


def _duration(name: str, value: Any) -> Any:
    if not hasattr(value, "nanoseconds"):
        raise TypeError(f"QoSProfile {name} must be a Duration, got {value!r}")
    return value


class QoSProfile:
    """A QoS profile (rclpy.qos.QoSProfile): keyword construction, mutable fields.

    ``QoSProfile(depth=10)`` is rclpy's default: KEEP_LAST 10, RELIABLE, VOLATILE, durations
    0 (infinite), liveliness SYSTEM_DEFAULT. SYSTEM_DEFAULT / BEST_AVAILABLE reliability and
    durability resolve to RELIABLE and VOLATILE. A field set to a wrong type raises
    TypeError (rclpy: AssertionError).
    """

    __slots__ = (  # noqa: RUF023 (rclpy's order, which str() prints)
        "_history",
        "_depth",
        "_reliability",
        "_durability",
        "_lifespan",
        "_deadline",
        "_liveliness",
        "_liveliness_lease_duration",
        "_avoid_ros_namespace_conventions",
    )

    def __init__(
        self,
        *,
        history: HistoryPolicy | int = HistoryPolicy.KEEP_LAST,
        depth: int = 10,
        reliability: ReliabilityPolicy | int = ReliabilityPolicy.RELIABLE,
        durability: DurabilityPolicy | int = DurabilityPolicy.VOLATILE,
        lifespan: Duration = _ZERO,
        deadline: Duration = _ZERO,
        liveliness: LivelinessPolicy | int = LivelinessPolicy.SYSTEM_DEFAULT,
        liveliness_lease_duration: Duration = _ZERO,
        avoid_ros_namespace_conventions: bool = False,
    ) -> None:
        self.history = history
        self.depth = depth
        self.reliability = reliability
        self.durability = durability
        self.lifespan = lifespan
        self.deadline = deadline
        self.liveliness = liveliness
        self.liveliness_lease_duration = liveliness_lease_duration
        self.avoid_ros_namespace_conventions = avoid_ros_namespace_conventions

    # -- fields (validated on every assignment) --------------------------------------------
    @property
    def history(self) -> HistoryPolicy:
        """KEEP_LAST (``depth`` messages), KEEP_ALL or SYSTEM_DEFAULT."""
        return self._history

    @history.setter
    def history(self, value: HistoryPolicy | int) -> None:
        self._history = HistoryPolicy(value)

    @property
    def depth(self) -> int:
        """Messages kept with KEEP_LAST; >= 1 then (0 only with another history)."""
        return self._depth

    @depth.setter
    def depth(self, value: int) -> None:
        if isinstance(value, bool) or not isinstance(value, int):
            raise TypeError(f"QoSProfile depth must be an int, got {value!r}")
        if value < 0:
            raise ValueError(f"QoSProfile depth must be >= 0, got {value}")
        if self._history == HistoryPolicy.KEEP_LAST and value == 0:
            raise ValueError("QoSProfile with KEEP_LAST history needs depth >= 1")
        self._depth = value

    @property
    def reliability(self) -> ReliabilityPolicy:
        """RELIABLE, BEST_EFFORT, SYSTEM_DEFAULT or BEST_AVAILABLE."""
        return self._reliability

    @reliability.setter
    def reliability(self, value: ReliabilityPolicy | int) -> None:
        self._reliability = ReliabilityPolicy(value)

    @property
    def durability(self) -> DurabilityPolicy:
        """VOLATILE, TRANSIENT_LOCAL, SYSTEM_DEFAULT or BEST_AVAILABLE."""
        return self._durability

    @durability.setter
    def durability(self, value: DurabilityPolicy | int) -> None:
        self._durability = DurabilityPolicy(value)

    @property
    def lifespan(self) -> Duration:
        """How long a kept message stays deliverable; 0 = infinite."""
        return self._lifespan

    @lifespan.setter
    def lifespan(self, value: Duration) -> None:
        self._lifespan: Duration = _duration("lifespan", value)

    @property
    def deadline(self) -> Duration:
        """Expected maximum period between messages (stored only; 0 = none)."""
        return self._deadline

    @deadline.setter
    def deadline(self, value: Duration) -> None:
        self._deadline: Duration = _duration("deadline", value)

    @property
    def liveliness(self) -> LivelinessPolicy:
        """Liveliness policy (stored only)."""
        return self._liveliness

    @liveliness.setter
    def liveliness(self, value: LivelinessPolicy | int) -> None:
        self._liveliness = LivelinessPolicy(value)

    @property
    def liveliness_lease_duration(self) -> Duration:
        """Liveliness lease (stored only; 0 = infinite)."""
        return self._liveliness_lease_duration

    @liveliness_lease_duration.setter
    def liveliness_lease_duration(self, value: Duration) -> None:
        self._liveliness_lease_duration: Duration = _duration(
            "liveliness_lease_duration", value)

    @property
    def avoid_ros_namespace_conventions(self) -> bool:
        """rmw's flag for raw DDS topic names (stored only)."""
        return self._avoid_ros_namespace_conventions

    @avoid_ros_namespace_conventions.setter
    def avoid_ros_namespace_conventions(self, value: bool) -> None:
        if not isinstance(value, bool):
            raise TypeError(f"avoid_ros_namespace_conventions must be a bool, got {value!r}")
        self._avoid_ros_namespace_conventions = value

    # -- value semantics, as rclpy ----------------------------------------------------------
    def __eq__(self, other: object) -> bool:
        if not isinstance(other, QoSProfile):
            return False
        return all(getattr(self, s) == getattr(other, s) for s in self.__slots__)

    __hash__ = None  # type: ignore[assignment]  # mutable, as rclpy's

    def __str__(self) -> str:
        # rclpy's text: the policies as ints (Python 3.11's IntEnum str), durations by str()
        return f"{type(self).__name__}(" + ", ".join(
            f"{slot[1:]}={_field_text(getattr(self, slot))}" for slot in self.__slots__
        ) + ")"

    __repr__ = __str__

    def __copy__(self) -> QoSProfile:
        new = QoSProfile.__new__(QoSProfile)
        for slot in self.__slots__:
            object.__setattr__(new, slot, getattr(self, slot))
        return new

    def copy(self) -> QoSProfile:
        """An independent copy (posekit's; ``copy.copy`` does the same)."""
        return self.__copy__()

    def with_(self, **changes: Any) -> QoSProfile:
        """A copy with some fields changed (validated as assignments); posekit's."""
        unknown = [name for name in changes if "_" + name not in self.__slots__]
        if unknown:
            raise TypeError(f"QoSProfile has no field {unknown[0]!r}")
        new = self.__copy__()
        for slot in self.__slots__:  # history before depth, whatever the keywords' order
            if slot[1:] in changes:
                setattr(new, slot[1:], changes[slot[1:]])
        return new

    # -- what posekit's transports read ------------------------------------------------------
    @property
    def lifespan_ns(self) -> int | None:
        """The lifespan in nanoseconds, None when infinite (0 or >= rmw's infinity)."""
        ns = int(self._lifespan.nanoseconds)
        return None if ns <= 0 or ns >= _INFINITE_NS else ns

    @property
    def resolved_reliability(self) -> ReliabilityPolicy:
        """RELIABLE or BEST_EFFORT after resolving SYSTEM_DEFAULT / BEST_AVAILABLE."""
        if self._reliability == ReliabilityPolicy.BEST_EFFORT:
            return ReliabilityPolicy.BEST_EFFORT
        return ReliabilityPolicy.RELIABLE

    @property
    def resolved_durability(self) -> DurabilityPolicy:
        """TRANSIENT_LOCAL or VOLATILE after resolving SYSTEM_DEFAULT / BEST_AVAILABLE."""
        if self._durability == DurabilityPolicy.TRANSIENT_LOCAL:
            return DurabilityPolicy.TRANSIENT_LOCAL
        return DurabilityPolicy.VOLATILE

    @property
    def queue_limit(self) -> int | None:
        """Max messages kept per subscription queue (None = unbounded, KEEP_ALL).

        A depth of 0 (SYSTEM_DEFAULT history) is :data:`SYSTEM_DEFAULT_DEPTH`.
        """
        if self._history == HistoryPolicy.KEEP_ALL:
            return None
        return self._depth or SYSTEM_DEFAULT_DEPTH


def _field_text(value: object) -> str:
    if isinstance(value, enum.IntEnum):
        return str(int(value))
    if isinstance(value, Duration):
        return f"{value.nanoseconds} nanoseconds"
    return str(value)


def to_qos_profile(qos: QoSProfile | int) -> QoSProfile:
    """rclpy's ``QoSProfile | int`` argument as a profile; anything else is a TypeError.

    A profile is returned as it is (rclpy's ``publisher.qos_profile`` is the caller's
    object); what a transport keeps is a copy (``EndpointInfo``).
    """
    if isinstance(qos, QoSProfile):
        return qos
    if isinstance(qos, int) and not isinstance(qos, bool):
        return QoSProfile(depth=qos)
    raise TypeError(f"expected a QoSProfile or an int history depth, got {qos!r}")


class OfferMatch(enum.Enum):
    """Result of matching an offered (publisher) and a requested (subscription) profile."""

    OK = "ok"
    INCOMPATIBLE_RELIABILITY = "RELIABILITY"
    INCOMPATIBLE_DURABILITY = "DURABILITY"


def match_offer(offered: QoSProfile, requested: QoSProfile) -> OfferMatch:
    """DDS request/offer matching for the two policies the in-process bus models."""
    if (
        offered.resolved_reliability == ReliabilityPolicy.BEST_EFFORT
        and requested.resolved_reliability == ReliabilityPolicy.RELIABLE
    ):
        return OfferMatch.INCOMPATIBLE_RELIABILITY
    if (
        offered.resolved_durability == DurabilityPolicy.VOLATILE
        and requested.resolved_durability == DurabilityPolicy.TRANSIENT_LOCAL
    ):
        return OfferMatch.INCOMPATIBLE_DURABILITY
    return OfferMatch.OK


class QoSCompatibility(enum.IntEnum):
    """rclpy's verdict on a publisher and a subscription profile (:func:`qos_check_compatible`)."""

    OK = 0
    WARNING = 1
    ERROR = 2


def _unknown(policy: QoSPolicyEnum) -> bool:
    return policy.name in ("SYSTEM_DEFAULT", "UNKNOWN")


def _duration_errors(what: str, offered: Duration, requested: Duration, less: str) -> list[str]:
    """A requested deadline or lease the offer cannot meet (0: none)."""
    p_ns, s_ns = offered.nanoseconds, requested.nanoseconds
    if p_ns == 0 and s_ns != 0:
        return [f"Subscription has {what}, but publisher does not"]
    if p_ns != 0 and s_ns != 0 and s_ns < p_ns:
        return [less]
    return []


def qos_check_compatible(publisher_qos: QoSProfile, subscription_qos: QoSProfile
                         ) -> tuple[QoSCompatibility, str]:
    """rclpy's ``qos_check_compatible``: ``(verdict, reason)`` as rmw_dds_common words it.

    ERROR for a request the offer cannot meet: reliability, durability, deadline, liveliness
    and its lease duration, every such reason joined. Without an error, WARNING where a
    policy is ``system_default`` or unknown on a side that decides it. Each reason ends with
    ``;``. Independent of what posekit's bus connects (:func:`match_offer`).
    """
    pub, sub = publisher_qos, subscription_qos
    errors = []
    if (pub.reliability == ReliabilityPolicy.BEST_EFFORT
            and sub.reliability == ReliabilityPolicy.RELIABLE):
        errors.append("Best effort publisher and reliable subscription")
    if (pub.durability == DurabilityPolicy.VOLATILE
            and sub.durability == DurabilityPolicy.TRANSIENT_LOCAL):
        errors.append("Volatile publisher and transient local subscription")
    errors += _duration_errors("a deadline", pub.deadline, sub.deadline,
                               "Subscription deadline is less than publisher deadline")
    if (pub.liveliness == LivelinessPolicy.AUTOMATIC
            and sub.liveliness == LivelinessPolicy.MANUAL_BY_TOPIC):
        errors.append("Publisher's liveliness is automatic and subscription's is manual by topic")
    errors += _duration_errors(
        "a liveliness lease duration", pub.liveliness_lease_duration,
        sub.liveliness_lease_duration,
        "Subscription liveliness lease duration is less than publisher")
    if errors:
        return QoSCompatibility.ERROR, "".join(f"ERROR: {e};" for e in errors)
    warnings = []
    for name, p, s, strong_sub, weak_pub, sub_text, pub_text in (
            ("reliability", pub.reliability, sub.reliability, ReliabilityPolicy.RELIABLE,
             ReliabilityPolicy.BEST_EFFORT, "Reliable subscription, but publisher is {p}",
             "Best effort publisher, but subscription is {s}"),
            ("durability", pub.durability, sub.durability, DurabilityPolicy.TRANSIENT_LOCAL,
             DurabilityPolicy.VOLATILE, "Transient local subscription, but publisher is {p}",
             "Volatile publisher, but subscription is {s}"),
            ("liveliness", pub.liveliness, sub.liveliness, LivelinessPolicy.MANUAL_BY_TOPIC,
             LivelinessPolicy.AUTOMATIC,
             "Subscription's liveliness is manual by topic, but publisher's is {p}",
             "Publisher's liveliness is automatic, but subscription's is {s}")):
        keys = {"p": p.short_key, "s": s.short_key}
        if _unknown(p) and _unknown(s):
            # rmw_dds_common's spelling, "durabilty" included
            label = "durabilty" if name == "durability" else name
            warnings.append(f"Publisher {label} is {keys['p']} and subscription {name} is "
                            f"{keys['s']}")
        elif _unknown(p) and s == strong_sub:
            warnings.append(sub_text.format(**keys))
        elif p == weak_pub and _unknown(s):
            warnings.append(pub_text.format(**keys))
    if warnings:
        return QoSCompatibility.WARNING, "".join(f"WARNING: {w};" for w in warnings)
    return QoSCompatibility.OK, ""



# rmw's predefined profiles (rmw/qos_profiles.h), as rclpy builds them: one object each.
#: Used for initialization; not a profile to use.
qos_profile_unknown = QoSProfile(
    history=HistoryPolicy.UNKNOWN,
    depth=0,
    reliability=ReliabilityPolicy.UNKNOWN,
    durability=DurabilityPolicy.UNKNOWN,
    liveliness=LivelinessPolicy.UNKNOWN,
)
#: rmw's default: KEEP_LAST 10, RELIABLE, VOLATILE.
qos_profile_default = QoSProfile(depth=10)
#: The middleware's defaults: SYSTEM_DEFAULT policies, depth 0 (see the module docstring).
qos_profile_system_default = QoSProfile(
    history=HistoryPolicy.SYSTEM_DEFAULT,
    depth=0,
    reliability=ReliabilityPolicy.SYSTEM_DEFAULT,
    durability=DurabilityPolicy.SYSTEM_DEFAULT,
)
#: rclpy's qos_profile_sensor_data: KEEP_LAST 5, BEST_EFFORT, VOLATILE.
qos_profile_sensor_data = QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT)
#: rclpy's qos_profile_services_default: KEEP_LAST 10, RELIABLE, VOLATILE.
qos_profile_services_default = QoSProfile(depth=10)
#: rclpy's qos_profile_parameters: KEEP_LAST 1000, RELIABLE, VOLATILE.
qos_profile_parameters = QoSProfile(depth=1000)
#: rclpy's qos_profile_parameter_events (/parameter_events): KEEP_LAST 1000, RELIABLE, VOLATILE.
qos_profile_parameter_events = QoSProfile(depth=1000)
#: Matches most endpoints: BEST_AVAILABLE reliability, durability, deadline and liveliness.
qos_profile_best_available = QoSProfile(
    depth=10,
    reliability=ReliabilityPolicy.BEST_AVAILABLE,
    durability=DurabilityPolicy.BEST_AVAILABLE,
    deadline=DeadlineBestAvailable,
    liveliness=LivelinessPolicy.BEST_AVAILABLE,
    liveliness_lease_duration=LivelinessLeaseDurationeBestAvailable,
)
#: rcl_action's status topic: KEEP_LAST 1, RELIABLE, TRANSIENT_LOCAL.
qos_profile_action_status_default = QoSProfile(
    depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL
)
#: Subscription QoS of rclpy's TimeSource on /clock: KEEP_LAST 1, BEST_EFFORT (posekit's name).
qos_profile_clock = QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT)


class QoSPresetProfiles(enum.Enum):
    """rclpy's presets by name (``ros2 ... --qos-profile sensor_data``).

    The values are the module's shared profile objects. Equal profiles alias, as in rclpy
    (``PARAMETER_EVENTS`` is ``PARAMETERS``).
    """

    UNKNOWN = qos_profile_unknown
    DEFAULT = qos_profile_default
    SYSTEM_DEFAULT = qos_profile_system_default
    SENSOR_DATA = qos_profile_sensor_data
    SERVICES_DEFAULT = qos_profile_services_default
    PARAMETERS = qos_profile_parameters
    PARAMETER_EVENTS = qos_profile_parameter_events
    ACTION_STATUS_DEFAULT = qos_profile_action_status_default
    BEST_AVAILABLE = qos_profile_best_available

    @classmethod
    def short_keys(cls) -> list[str]:
        """The preset names in lower case."""
        return [k.lower() for k in cls.__members__]

    @classmethod
    def get_from_short_key(cls, name: str) -> QoSProfile:
        """The preset profile ``name`` (case-insensitive), e.g. ``'sensor_data'``."""
        profile: QoSProfile = cls[name.upper()].value
        return profile
