"""ROS 2's mapping onto DDS, as pure functions (no cyclonedds import).

Names, user data, the discovery configuration and the ``ros_discovery_info`` graph messages.

What rmw_fastrtps and rmw_cyclonedds (ROS 2 Jazzy) do, and what this module reproduces:

* Topics: a ROS topic ``/robot1/odom`` is the DDS topic ``rt/robot1/odom``; services use
  ``rq/<service>Request`` and ``rr/<service>Reply``. Other DDS topics (``ros_discovery_info``,
  DDS built-ins) are not ROS topics.
* Services, as rmw_cyclonedds maps them: a server reads requests on ``rq/<service>Request``
  (type ``<pkg>::srv::dds_::<Srv>_Request_``) and writes replies on ``rr/<service>Reply``
  (``<Srv>_Response_``); a client does the reverse. Each payload is the CDR encapsulation,
  then a 16-byte request header (the client's id as a uint64 and the request's sequence
  number as an int64, in the encapsulation's byte order), then the message's own fields. The
  header is 16 bytes, a multiple of 8 (CDR's largest alignment), so the message body starts
  aligned exactly as it would at offset 0: its bytes are those of the message serialized
  alone (:func:`encode_service_payload`, :func:`decode_service_payload`). The server copies
  the header into its reply. Every service reader and writer also carries
  ``serviceid=<id>;`` (a server's pair) or ``clientid=<id>;`` (a client's pair) in its
  USER_DATA, so the two endpoints of one server or client can be paired.
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
import struct
from collections.abc import Mapping
from dataclasses import dataclass, field
from xml.sax.saxutils import quoteattr

import numpy as np

from posekit.transport.zenoh_wire import EntityKind, WireQoS, dds_type_name, ros_type_name

__all__ = [
    "DISCOVERY_TOPIC",
    "DISCOVERY_TYPE",
    "REQUEST_HEADER_SIZE",
    "DdsEndpoint",
    "DdsNode",
    "DiscoveryOptions",
    "DiscoveryRange",
    "NodeEntities",
    "ParticipantEntities",
    "client_service_id",
    "cyclone_config",
    "dds_topic_name",
    "dds_type_name",
    "decode_participant_entities",
    "decode_service_payload",
    "encode_participant_entities",
    "encode_service_payload",
    "format_client_service_id",
    "format_gid",
    "parse_user_data",
    "ros_service_name",
    "ros_service_type",
    "ros_topic_name",
    "ros_type_name",
    "service_topic_names",
    "user_data_type_hash",
]

#: rmw_dds_common's graph topic (no ``rt/`` prefix: it is not a ROS topic) and its type.
DISCOVERY_TOPIC = "ros_discovery_info"
DISCOVERY_TYPE = "rmw_dds_common/msg/ParticipantEntitiesInfo"

_TOPIC_PREFIX = "rt"
_REQUEST_PREFIX = "rq"
_REPLY_PREFIX = "rr"
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


def service_topic_names(service: str) -> tuple[str, str]:
    """``/add_two_ints`` -> (``rq/add_two_intsRequest``, ``rr/add_two_intsReply``)."""
    if not service.startswith("/") or service == "/":
        raise ValueError(f"expected a fully qualified ROS service name, got {service!r}")
    return f"{_REQUEST_PREFIX}{service}Request", f"{_REPLY_PREFIX}{service}Reply"


def ros_service_name(dds_topic: str) -> tuple[str, bool] | None:
    """``rq/flipRequest`` -> (``/flip``, True), ``rr/flipReply`` -> (``/flip``, False).

    None for a DDS topic that is neither a service's request nor its reply topic.
    """
    for prefix, suffix, request in ((_REQUEST_PREFIX, "Request", True),
                                    (_REPLY_PREFIX, "Reply", False)):
        if dds_topic.startswith(prefix + "/") and dds_topic.endswith(suffix):
            service = dds_topic[len(prefix):-len(suffix)]
            if len(service) > 1:
                return service, request
    return None


def ros_service_type(dds_type: str) -> str | None:
    """``std_srvs::srv::dds_::SetBool_Request_`` (or ``_Response_``) -> ``std_srvs/srv/SetBool``.

    None for a type name that is not a service's request or response type.
    """
    try:
        ros_type = ros_type_name(dds_type)
    except ValueError:
        return None
    for suffix in ("_Request", "_Response"):
        if ros_type.endswith(suffix) and len(ros_type.rsplit("/", 1)[-1]) > len(suffix):
            return ros_type[:-len(suffix)]
    return None


def client_service_id(participant_gid: bytes, counter: int) -> bytes:
    """The 16-byte id pairing a server's (or client's) reader and writer, as rmw_cyclonedds.

    The participant's GUID prefix (12 bytes) and a per-participant counter (big endian).
    """
    return bytes(participant_gid[:12]).ljust(12, b"\x00") + (counter & 0xFFFFFFFF).to_bytes(
        4, "big")


def format_client_service_id(csid: bytes) -> str:
    """The id as rmw_cyclonedds writes it into USER_DATA: hex bytes joined by dots.

    The first byte has two digits, the others no leading zero (``01.f.a3.0...``).
    """
    return ".".join(f"{b:02x}" if i == 0 else f"{b:x}" for i, b in enumerate(csid))


#: Bytes of rmw_cyclonedds's request header (client id uint64 + sequence number int64).
REQUEST_HEADER_SIZE = 16


def encode_service_payload(cdr: bytes, client_id: int, sequence_number: int) -> bytes:
    """Put the request header between the encapsulation and the body of a message's CDR.

    ``cdr`` is the message serialized alone (encapsulation included, as
    :func:`posekit.msgs.cdr.to_cdr` gives it); the header uses its byte order.
    """
    if len(cdr) < 4:
        raise ValueError(f"{len(cdr)} bytes is shorter than the CDR encapsulation")
    order = "<" if cdr[1] & 1 else ">"
    return (cdr[:4] + struct.pack(order + "Qq", client_id & 0xFFFFFFFFFFFFFFFF, sequence_number)
            + cdr[4:])


def decode_service_payload(data: bytes) -> tuple[int, int, bytes]:
    """Split a service payload into (client id, sequence number, the message's own CDR).

    Raises ValueError when the payload is shorter than encapsulation and header or its
    encapsulation is not plain CDR (``00 00`` / ``00 01``).
    """
    if len(data) < 4 + REQUEST_HEADER_SIZE:
        raise ValueError(f"{len(data)} bytes is shorter than the CDR encapsulation and the "
                         f"{REQUEST_HEADER_SIZE}-byte request header")
    if data[0] != 0 or data[1] > 1:
        raise ValueError(f"unsupported CDR encapsulation {bytes(data[:2]).hex(' ')}")
    order = "<" if data[1] else ">"
    client_id, sequence_number = struct.unpack_from(order + "Qq", data, 4)
    return client_id, sequence_number, bytes(data[:4]) + bytes(data[4 + REQUEST_HEADER_SIZE:])


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
    """A ROS publisher, subscription, service server or client seen on DDS.

    From the built-in discovery topics. Attribute names follow
    :class:`posekit.transport.zenoh_wire.TokenInfo` so the command-line tools print either
    transport's endpoints the same way. A service server (kind ``SERVICE``) or client
    (``CLIENT``) is the record of its reader (on the request or the reply topic); its
    ``topic`` is the service name, its ``ros_type`` the service type (``std_srvs/srv/SetBool``).
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


@dataclass(frozen=True, slots=True)
class DdsNode:
    """A ROS node seen on DDS (announced on ``ros_discovery_info``), as a graph record.

    The node counterpart of :class:`DdsEndpoint`: ``kind`` is ``NODE``, ``topic`` and
    ``ros_type`` are None (as a Zenoh node token's).
    """

    participant_gid: bytes
    namespace: str
    node_name: str
    kind: EntityKind = EntityKind.NODE
    topic: str | None = None
    ros_type: str | None = None

    @property
    def node_fqn(self) -> str:
        """``/namespace/node``."""
        return f"{self.namespace.rstrip('/')}/{self.node_name}"
