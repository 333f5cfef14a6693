"""rclpy.topic_endpoint_info: what ``Node.get_publishers_info_by_topic`` returns.

:class:`TopicEndpointInfo` (node name and namespace, type, type hash, endpoint kind, GID, QoS)
prints as rclpy's does, which is the block ``ros2 topic info -v`` shows.
:func:`endpoint_info_from_record` turns a transport's graph record (the in-process bus's
:class:`~posekit.runtime.transport.GraphEndpoint`, Zenoh's ``TokenInfo``, DDS's
``DdsEndpoint``: ``node_name``, ``namespace``, ``ros_type``, ``type_hash``, ``qos``, ``gid``)
into one.
"""

from __future__ import annotations

import enum
from typing import Any

from posekit.runtime.qos import HistoryPolicy, LivelinessPolicy, QoSProfile, qos_profile_unknown
from posekit.time import Duration

__all__ = ["TopicEndpointInfo", "TopicEndpointTypeEnum", "TypeHash", "endpoint_info_from_record"]

#: rmw's infinite duration, what middlewares report for an unset (0) duration.
_INFINITE = Duration(nanoseconds=2**63 - 1)


class TopicEndpointTypeEnum(enum.IntEnum):
    """rmw_endpoint_type_t."""

    INVALID = 0
    PUBLISHER = 1
    SUBSCRIPTION = 2


class TypeHash:
    """A REP-2011 type hash: ``version`` (1 for RIHS01) and 32 bytes ``value``."""

    _TYPE_HASH_SIZE = 32
    __slots__ = ("_value", "_version")

    def __init__(self, version: int = -1, value: bytes = bytes(_TYPE_HASH_SIZE)) -> None:
        self._version = version
        self._value = value

    @classmethod
    def from_text(cls, text: str | None) -> TypeHash:
        """From ``RIHS01_<64 hex>`` (None or anything else: the invalid hash)."""
        if text and text.startswith("RIHS") and "_" in text:
            version, _, hexdigits = text[4:].partition("_")
            try:
                return cls(int(version), bytes.fromhex(hexdigits))
            except ValueError:
                pass
        return cls()

    @property
    def version(self) -> int:
        """The RIHS version (-1: none)."""
        return self._version

    @property
    def value(self) -> bytes:
        """The hash bytes."""
        return self._value

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, TypeHash):
            return False
        return (self._version, self._value) == (other._version, other._value)

    __hash__ = None  # type: ignore[assignment]  # as rclpy's

    def __str__(self) -> str:
        if self._version <= 0 or len(self._value) != self._TYPE_HASH_SIZE:
            return "INVALID"
        return f"RIHS{self._version:02}_{self._value.hex()}"


class TopicEndpointInfo:
    """One publisher or subscription on a topic (rclpy's class, keyword construction)."""

    __slots__ = ("endpoint_gid", "endpoint_type", "node_name", "node_namespace", "qos_profile",
                 "topic_type", "topic_type_hash")

    def __init__(
        self,
        *,
        node_name: str = "",
        node_namespace: str = "",
        topic_type: str = "",
        topic_type_hash: TypeHash | None = None,
        endpoint_type: TopicEndpointTypeEnum | int = TopicEndpointTypeEnum.INVALID,
        endpoint_gid: list[int] | None = None,
        qos_profile: QoSProfile | None = None,
    ) -> None:
        #: The endpoint's node.
        self.node_name = node_name
        #: The namespace of the endpoint's node ('/' for the root).
        self.node_namespace = node_namespace
        #: The ROS type name, e.g. 'std_msgs/msg/String'.
        self.topic_type = topic_type
        #: The type's REP-2011 hash (INVALID when the middleware gave none).
        self.topic_type_hash = topic_type_hash if topic_type_hash is not None else TypeHash()
        #: PUBLISHER or SUBSCRIPTION.
        self.endpoint_type = TopicEndpointTypeEnum(endpoint_type)
        #: The endpoint's GID (16 bytes) as a list of ints.
        self.endpoint_gid = list(endpoint_gid or [])
        #: The QoS the endpoint announced, as the middleware reports it.
        self.qos_profile = qos_profile if qos_profile is not None else qos_profile_unknown.copy()

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, TopicEndpointInfo):
            return False
        return all(getattr(self, s) == getattr(other, s) for s in self.__slots__)

    __hash__ = None  # type: ignore[assignment]  # as rclpy's

    def __str__(self) -> str:
        gid = ".".join(format(x, "02x") for x in self.endpoint_gid)
        q = self.qos_profile
        history = (q.history.name if q.history != HistoryPolicy.KEEP_LAST
                   else f"{q.history.name} ({q.depth})")
        return "\n".join([
            f"Node name: {self.node_name}",
            f"Node namespace: {self.node_namespace}",
            f"Topic type: {self.topic_type}",
            f"Topic type hash: {self.topic_type_hash}",
            f"Endpoint type: {self.endpoint_type.name}",
            f"GID: {gid}",
            "QoS profile:",
            f"  Reliability: {q.reliability.name}",
            f"  History (Depth): {history}",
            f"  Durability: {q.durability.name}",
            f"  Lifespan: {q.lifespan}",
            f"  Deadline: {q.deadline}",
            f"  Liveliness: {q.liveliness.name}",
            f"  Liveliness lease duration: {q.liveliness_lease_duration}",
        ])


def _as_reported(profile: QoSProfile) -> QoSProfile:
    """A profile as a middleware reports it: unset (0) durations infinite, liveliness AUTOMATIC."""
    reported = profile.copy()
    for name in ("lifespan", "deadline", "liveliness_lease_duration"):
        if getattr(reported, name).nanoseconds == 0:
            setattr(reported, name, _INFINITE)
    if reported.liveliness == LivelinessPolicy.SYSTEM_DEFAULT:
        reported.liveliness = LivelinessPolicy.AUTOMATIC
    return reported


def endpoint_info_from_record(
    record: Any, endpoint_type: TopicEndpointTypeEnum
) -> TopicEndpointInfo:
    """rclpy's TopicEndpointInfo of a transport's graph record (see the module docstring).

    ``record.qos`` is a :class:`QoSProfile` (in process) or a wire QoS with
    ``to_profile(exact=True)`` (the history and depth as announced).
    """
    qos = record.qos
    if qos is None:
        profile = qos_profile_unknown.copy()
    else:
        profile = _as_reported(
            qos if isinstance(qos, QoSProfile) else qos.to_profile(exact=True))
    gid = getattr(record, "gid", b"") or b""
    return TopicEndpointInfo(
        node_name=record.node_name,
        node_namespace=record.namespace,
        topic_type=record.ros_type or "",
        topic_type_hash=TypeHash.from_text(record.type_hash),
        endpoint_type=endpoint_type,
        endpoint_gid=list(gid),
        qos_profile=profile,
    )
