"""ROS 2's mapping onto DDS, as pure functions (no cyclonedds import).

Names, user data, the discovery configuration and the ``ros_discovery_info`` graph messages.

What rmw_fastrtps and rmw_cyclonedds (ROS 2 Jazzy) do, and what this module reproduces:

* Topics: a ROS topic ``/robot1/odom`` is the DDS topic ``rt/robot1/odom``; services use
  ``rq/<service>Request`` and ``rr/<service>Reply``. Other DDS topics (``ros_discovery_info``,
  DDS built-ins) are not ROS topics.
* Types: ``geometry_msgs/msg/Twist`` is the DDS type ``geometry_msgs::msg::dds_::Twist_``
  (:func:`posekit.transport.zenoh_wire.dds_type_name`, one owner for both transports).
* Payloads: ROS 2's CDR (XCDR1 little endian with the 4-byte encapsulation header), exactly
  the bytes :func:`posekit.msgs.cdr.to_cdr` produces.
* USER_DATA: a participant carries ``enclave=/;``, every reader and writer
  ``typehash=RIHS01_<sha256>;`` (REP-2011 type hash, Jazzy and later).
* Discovery: ``ROS_AUTOMATIC_DISCOVERY_RANGE`` (``LOCALHOST``, ``SUBNET``, ``OFF``,
  ``SYSTEM_DEFAULT``) and ``ROS_STATIC_PEERS`` (``;``-separated addresses) become Cyclone DDS
  configuration as rmw_cyclonedds builds it. posekit's default when the variable is unset is
  ``LOCALHOST`` (stay on this machine), and for LOCALHOST without static peers it also binds
  Cyclone to the loopback interface so not even unicast leaves the host.
* The ROS graph: every participant publishes ``rmw_dds_common/msg/ParticipantEntitiesInfo``
  on ``ros_discovery_info`` (reliable, transient local, keep last 1): its GID and, per node,
  namespace, name and the GIDs of the node's readers and writers. A GID is the entity's
  16-byte DDS GUID.
"""

from __future__ import annotations

import enum
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from xml.sax.saxutils import quoteattr

import numpy as np

from posekit.transport.zenoh_wire import EntityKind, WireQoS, dds_type_name, ros_type_name

__all__ = [
    "DISCOVERY_TOPIC",
    "DISCOVERY_TYPE",
    "DdsEndpoint",
    "DiscoveryOptions",
    "DiscoveryRange",
    "NodeEntities",
    "ParticipantEntities",
    "cyclone_config",
    "dds_topic_name",
    "dds_type_name",
    "decode_participant_entities",
    "encode_participant_entities",
    "format_gid",
    "parse_user_data",
    "ros_topic_name",
    "ros_type_name",
    "user_data_type_hash",
]

#: rmw_dds_common's graph topic (no ``rt/`` prefix: it is not a ROS topic) and its type.
DISCOVERY_TOPIC = "ros_discovery_info"
DISCOVERY_TYPE = "rmw_dds_common/msg/ParticipantEntitiesInfo"

_TOPIC_PREFIX = "rt"
ENV_RANGE = "ROS_AUTOMATIC_DISCOVERY_RANGE"
ENV_PEERS = "ROS_STATIC_PEERS"
ENV_DOMAIN = "ROS_DOMAIN_ID"


# ---------------------------------------------------------------------------------------
# Names


def dds_topic_name(topic: str) -> str:
    """``/robot1/odom`` -> ``rt/robot1/odom`` (fully qualified ROS topic in)."""
    if not topic.startswith("/") or topic == "/":
        raise ValueError(f"expected a fully qualified ROS topic name, got {topic!r}")
    return _TOPIC_PREFIX + topic


def ros_topic_name(dds_topic: str) -> str | None:
    """``rt/robot1/odom`` -> ``/robot1/odom``; None for DDS topics that are not ROS topics."""
    if dds_topic.startswith(_TOPIC_PREFIX + "/") and len(dds_topic) > 3:
        return dds_topic[len(_TOPIC_PREFIX):]
    return None


def format_gid(gid: bytes) -> str:
    """``01.0f.a3...`` as ``ros2 topic info -v`` prints a GID."""
    return ".".join(f"{b:02x}" for b in gid)


# ---------------------------------------------------------------------------------------
# USER_DATA


def parse_user_data(data: bytes) -> dict[str, str]:
    """``b"enclave=/;typehash=RIHS01_ab..;"`` -> ``{"enclave": "/", "typehash": ...}``.

    Tolerates Fast DDS's trailing NUL and entries without ``=``; never raises.
    """
    out: dict[str, str] = {}
    text = data.rstrip(b"\x00").decode("utf-8", errors="replace")
    for item in text.split(";"):
        key, sep, value = item.partition("=")
        if sep and key:
            out[key.strip()] = value
    return out


def user_data_type_hash(ros_type: str, type_hash: str) -> bytes:
    """An endpoint's USER_DATA as rmw writes it: ``typehash=RIHS01_<hex>;``."""
    del ros_type  # the hash already names the type; kept for call-site clarity
    return f"typehash={type_hash};".encode()


# ---------------------------------------------------------------------------------------
# Discovery configuration


class DiscoveryRange(enum.Enum):
    """ROS 2's ``ROS_AUTOMATIC_DISCOVERY_RANGE`` values."""

    LOCALHOST = "LOCALHOST"
    SUBNET = "SUBNET"
    OFF = "OFF"
    SYSTEM_DEFAULT = "SYSTEM_DEFAULT"


@dataclass(frozen=True, slots=True)
class DiscoveryOptions:
    """Domain id, automatic discovery range and static peers (ROS 2 Jazzy semantics)."""

    domain_id: int = 0
    range: DiscoveryRange = DiscoveryRange.LOCALHOST
    static_peers: tuple[str, ...] = ()
    extra_config: str = ""

    @classmethod
    def from_env(cls, env: Mapping[str, str] | None = None) -> DiscoveryOptions:
        """The options the ROS environment variables give; bad values raise ValueError.

        From ``ROS_DOMAIN_ID``, ``ROS_AUTOMATIC_DISCOVERY_RANGE``, ``ROS_STATIC_PEERS`` and
        ``CYCLONEDDS_URI`` (appended, as rmw_cyclonedds does).
        """
        env = os.environ if env is None else env
        domain_text = env.get(ENV_DOMAIN, "").strip() or "0"
        try:
            domain_id = int(domain_text, 10)
        except ValueError:
            raise ValueError(f"{ENV_DOMAIN}={domain_text!r} is not an integer") from None
        if not 0 <= domain_id <= 232:
            raise ValueError(f"{ENV_DOMAIN}={domain_id} is outside 0..232")
        range_text = env.get(ENV_RANGE, "").strip().upper() or "LOCALHOST"
        try:
            rng = DiscoveryRange(range_text)
        except ValueError:
            known = ", ".join(r.value for r in DiscoveryRange)
            raise ValueError(f"{ENV_RANGE}={range_text!r}: expected one of {known}") from None
        peers = tuple(p.strip() for p in env.get(ENV_PEERS, "").split(";") if p.strip())
        return cls(domain_id, rng, peers, env.get("CYCLONEDDS_URI", "").strip())


def cyclone_config(options: DiscoveryOptions) -> str:
    """Cyclone DDS configuration (XML, plus ``CYCLONEDDS_URI`` after a comma) for ``options``.

    LOCALHOST: no multicast, localhost and the static peers probed by unicast; without static
    peers Cyclone is also bound to the loopback interface (with them, to its default
    interface, so the peers can be reached). SUBNET: Cyclone's default interface with
    multicast, plus the static peers.
    OFF: no multicast, no peers and a process-unique domain tag, so nothing is discovered.
    SYSTEM_DEFAULT: Cyclone's own defaults. The participant-index settings are
    rmw_cyclonedds's (32 participants per host are probed by unicast).
    """
    rng = options.range
    parts: list[str] = []
    general: list[str] = []
    if rng is DiscoveryRange.LOCALHOST and not options.static_peers:
        general.append('<Interfaces><NetworkInterface address="127.0.0.1"/></Interfaces>')
    if rng in (DiscoveryRange.LOCALHOST, DiscoveryRange.OFF):
        general.append("<AllowMulticast>false</AllowMulticast>")
    # Large samples (a 1280x720 image is 2.7 MB) arrive whole with room in the socket buffer.
    internal = '<Internal><SocketReceiveBufferSize min="default" max="8MB"/></Internal>'
    if rng is not DiscoveryRange.SYSTEM_DEFAULT:
        discovery: list[str] = []
        if rng is DiscoveryRange.OFF:
            discovery.append("<ParticipantIndex>none</ParticipantIndex>")
            discovery.append(f"<Tag>ros_discovery_off_{os.getpid()}</Tag>")
        else:
            discovery.append("<ParticipantIndex>auto</ParticipantIndex>")
            discovery.append("<MaxAutoParticipantIndex>32</MaxAutoParticipantIndex>")
            peers = (["localhost"] if rng is DiscoveryRange.LOCALHOST else []) + list(
                options.static_peers
            )
            if peers:
                discovery.append(
                    "<Peers>"
                    + "".join(f"<Peer address={quoteattr(p)}/>" for p in peers)
                    + "</Peers>"
                )
        parts.append(
            "<CycloneDDS><Domain>"
            + (f"<General>{''.join(general)}</General>" if general else "")
            + f"<Discovery>{''.join(discovery)}</Discovery>{internal}"
            + "</Domain></CycloneDDS>"
        )
    if options.extra_config:
        parts.append(options.extra_config)
    return ",".join(parts)


# ---------------------------------------------------------------------------------------
# ros_discovery_info


@dataclass(slots=True)
class NodeEntities:
    """One node of a participant: its name and the GIDs of its readers and writers."""

    namespace: str
    name: str
    reader_gids: list[bytes] = field(default_factory=list)
    writer_gids: list[bytes] = field(default_factory=list)

    @property
    def fqn(self) -> str:
        """``/namespace/name`` as ``ros2 node list`` prints it."""
        return f"{self.namespace.rstrip('/')}/{self.name}"


@dataclass(slots=True)
class ParticipantEntities:
    """``rmw_dds_common/msg/ParticipantEntitiesInfo``: a participant and its nodes."""

    gid: bytes
    nodes: list[NodeEntities] = field(default_factory=list)


@dataclass(slots=True)
class _Gid:
    data: np.ndarray


@dataclass(slots=True)
class _Node:
    node_namespace: str
    node_name: str
    reader_gid_seq: list[_Gid]
    writer_gid_seq: list[_Gid]


@dataclass(slots=True)
class _Participant:
    gid: _Gid
    node_entities_info_seq: list[_Node]


def _gid(raw: bytes) -> _Gid:
    padded = bytes(raw[:16]).ljust(16, b"\x00")
    return _Gid(np.frombuffer(padded, dtype=np.uint8).copy())


def encode_participant_entities(info: ParticipantEntities) -> bytes:
    """The CDR payload of ``info`` (the bytes rmw publishes on ``ros_discovery_info``)."""
    from posekit.msgs.cdr import to_cdr

    msg = _Participant(
        _gid(info.gid),
        [
            _Node(n.namespace, n.name, [_gid(g) for g in n.reader_gids],
                  [_gid(g) for g in n.writer_gids])
            for n in info.nodes
        ],
    )
    return to_cdr(msg, DISCOVERY_TYPE)


def decode_participant_entities(data: bytes) -> ParticipantEntities:
    """Decode a ``ros_discovery_info`` payload; raises ``CdrError`` when it does not decode."""
    from posekit.msgs.cdr import from_cdr

    msg = from_cdr(data, DISCOVERY_TYPE)
    return ParticipantEntities(
        bytes(msg.gid.data),
        [
            NodeEntities(
                n.node_namespace,
                n.node_name,
                [bytes(g.data) for g in n.reader_gid_seq],
                [bytes(g.data) for g in n.writer_gid_seq],
            )
            for n in msg.node_entities_info_seq
        ],
    )


# ---------------------------------------------------------------------------------------
# Graph entities


@dataclass(frozen=True, slots=True)
class DdsEndpoint:
    """A ROS publisher or subscription seen on DDS (from the built-in discovery topics).

    Attribute names follow :class:`posekit.transport.zenoh_wire.TokenInfo` so the command-line
    tools print either transport's endpoints the same way.
    """

    kind: EntityKind
    gid: bytes
    participant_gid: bytes
    topic: str
    ros_type: str
    type_hash: str | None
    qos: WireQoS
    node_name: str = "_NODE_NAME_UNKNOWN_"
    namespace: str = "_NODE_NAMESPACE_UNKNOWN_"
    keyexpr: str = ""

    @property
    def node_fqn(self) -> str:
        """``/namespace/node``."""
        return f"{self.namespace.rstrip('/')}/{self.node_name}"
