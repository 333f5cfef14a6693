"""rmw_zenoh's wire format, as pure functions (no zenoh import): keys, tokens, QoS, attachments.

Everything here follows ROS 2's rmw_zenoh (Jazzy >= 0.2.4, Kilted, Rolling); section numbers
refer to ``docs/specs/rmw_zenoh.md``.

* Data key (§1): ``<domain>/<topic>/<pkg>::msg::dds_::<Type>_/<RIHS01 hash>``, the topic
  without its leading and trailing ``/`` (inner ``/`` stay chunk separators).
* Liveliness tokens (§2): ``@ros2_lv/<domain>/<zid>/<nid>/<eid>/<kind>/<enclave>/<ns>/<node>``
  plus ``/<topic>/<dds type>/<hash>/<qos>`` for endpoints; every ``/`` inside a chunk becomes
  ``%``.
* QoS chunk (§2.1): ``<rel>:<dur>:<hist>,<depth>:<deadline s>,<ns>:<lifespan s>,<ns>:``
  ``<liveliness>,<lease s>,<ns>``, fields equal to rmw_zenoh's defaults left empty (as
  rmw_zenoh writes them) unless ``explicit=True``.
* Attachment (§3): compact 33 bytes ``<q seq><q source ts ns><0x10><16-byte GID>``, or the legacy
  77-byte keyed form of Jazzy 0.2.0-0.2.3.
* GID: XXH3-128 of the entity's token key expression, low 64 bits first (little endian).
* Type hashes: computed by rosbags from the Jazzy message definitions
  (:func:`posekit.msgs.cdr.type_hash_rihs01`).

Parsing functions raise :class:`WireFormatError` with the reason.
"""

from __future__ import annotations

import enum
import hashlib
import struct
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import lru_cache
from typing import NamedTuple

from posekit.msgs.cdr import type_hash_rihs01
from posekit.runtime.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    LivelinessPolicy,
    QoSProfile,
    ReliabilityPolicy,
)
from posekit.time import Duration

__all__ = [
    "ATTACHMENT_SIZE",
    "DEFAULT_WIRE_QOS",
    "LEGACY_ATTACHMENT_SIZE",
    "LIVELINESS_PREFIX",
    "MAX_GRAPH_TOKENS",
    "Attachment",
    "EntityKind",
    "GraphCache",
    "TokenInfo",
    "WireFormatError",
    "WireQoS",
    "data_key",
    "dds_type_name",
    "decode_attachment",
    "demangle",
    "encode_attachment",
    "encode_attachment_legacy",
    "endpoint_token",
    "entity_gid",
    "mangle",
    "node_token",
    "parse_token",
    "qos_from_keyexpr",
    "qos_to_keyexpr",
    "ros_type_name",
    "topic_chunk",
    "type_hash",
]

LIVELINESS_PREFIX = "@ros2_lv"
ATTACHMENT_SIZE = 33
_COMPACT = struct.Struct("<qqB")
_I64 = struct.Struct("<q")
_LEGACY_SEQ = b"\x0fsequence_number"
_LEGACY_TS = b"\x10source_timestamp"
_LEGACY_GID = b"\x0asource_gid\x10"
LEGACY_ATTACHMENT_SIZE = len(_LEGACY_SEQ) + 8 + len(_LEGACY_TS) + 8 + len(_LEGACY_GID) + 16


class WireFormatError(ValueError):
    """A key expression, token, QoS chunk or attachment that does not follow rmw_zenoh."""


# ---------------------------------------------------------------------------------------
# Names


def dds_type_name(ros_type: str) -> str:
    """``tf2_msgs/msg/TFMessage`` -> ``tf2_msgs::msg::dds_::TFMessage_`` (Fast-CDR typesupport)."""
    parts = ros_type.strip("/").split("/")
    if len(parts) == 2:
        parts = [parts[0], "msg", parts[1]]
    if len(parts) != 3 or not all(parts):
        raise WireFormatError(f"malformed ROS type name {ros_type!r} (expected 'pkg/msg/Type')")
    pkg, kind, name = parts
    return f"{pkg}::{kind}::dds_::{name}_"


def ros_type_name(dds_type: str) -> str:
    """``tf2_msgs::msg::dds_::TFMessage_`` -> ``tf2_msgs/msg/TFMessage``."""
    parts = dds_type.split("::")
    if len(parts) != 4 or parts[2] != "dds_" or not parts[3].endswith("_") or len(parts[3]) < 2:
        raise WireFormatError(
            f"malformed DDS type name {dds_type!r} (expected 'pkg::msg::dds_::Type_')"
        )
    if not parts[0] or not parts[1]:
        raise WireFormatError(f"malformed DDS type name {dds_type!r}")
    return f"{parts[0]}/{parts[1]}/{parts[3][:-1]}"


@lru_cache(maxsize=256)
def type_hash(ros_type: str) -> str:
    """REP-2011 ``RIHS01_<sha256 hex>`` of a ROS 2 Jazzy type, computed by rosbags."""
    return type_hash_rihs01(ros_type)


def topic_chunk(topic: str) -> str:
    """Fully qualified topic ``/robot1/odom`` -> data-key part ``robot1/odom``."""
    chunk = topic.strip("/")
    if not chunk or "//" in chunk:
        raise WireFormatError(f"topic {topic!r} cannot form a key expression")
    if any(c in chunk for c in "*$?#"):
        raise WireFormatError(f"topic {topic!r} contains a zenoh wildcard or reserved character")
    return chunk


def data_key(domain_id: int, topic: str, ros_type: str, type_hash_str: str | None = None) -> str:
    """The data key expression rmw_zenoh publishes ``topic`` on (§1).

    Example: ``data_key(0, "/tf", "tf2_msgs/msg/TFMessage")`` ->
    ``0/tf/tf2_msgs::msg::dds_::TFMessage_/RIHS01_e369...``.
    """
    hash_str = type_hash_str if type_hash_str is not None else type_hash(ros_type)
    return f"{int(domain_id)}/{topic_chunk(topic)}/{dds_type_name(ros_type)}/{hash_str}"


def mangle(name: str) -> str:
    """Token chunk of a ROS name: every ``/`` becomes ``%`` (``/robot1/tf`` -> ``%robot1%tf``)."""
    return name.replace("/", "%")


def demangle(chunk: str) -> str:
    """Inverse of :func:`mangle`."""
    return chunk.replace("%", "/")


# ---------------------------------------------------------------------------------------
# QoS chunk (§2.1). Enum values are rmw's (rmw/types.h), identical to rclpy's policies.

_INF_S, _INF_NS = 9223372036, 854775807


@dataclass(frozen=True, slots=True)
class WireQoS:
    """QoS as rmw_zenoh encodes it; enum fields hold rmw's integer values.

    reliability 1 RELIABLE / 2 BEST_EFFORT; durability 1 TRANSIENT_LOCAL / 2 VOLATILE;
    history 1 KEEP_LAST / 2 KEEP_ALL; liveliness 1 AUTOMATIC / 3 MANUAL_BY_TOPIC. Durations
    are (seconds, nanoseconds); ``(9223372036, 854775807)`` means infinite.
    """

    reliability: int = 1
    durability: int = 2
    history: int = 1
    depth: int = 42
    deadline: tuple[int, int] = (_INF_S, _INF_NS)
    lifespan: tuple[int, int] = (_INF_S, _INF_NS)
    liveliness: int = 1
    liveliness_lease: tuple[int, int] = (_INF_S, _INF_NS)

    @property
    def transient_local(self) -> bool:
        """True for TRANSIENT_LOCAL durability."""
        return self.durability == 1

    @property
    def reliable(self) -> bool:
        """True unless BEST_EFFORT."""
        return self.reliability != 2

    def to_profile(self, *, exact: bool = False) -> QoSProfile:
        """The rclpy profile of this QoS: every policy, durations included.

        An infinite duration stays rmw's infinite, 2**63 - 1 ns (rclpy prints ``Infinite``).
        A history other than KEEP_ALL is KEEP_LAST with depth >= 1 (a profile to request
        with), unless ``exact``: then history and depth are the announced ones (DDS discovery
        carries none: UNKNOWN, 0), as ``get_publishers_info_by_topic`` reports them.
        """
        if exact and self.history in (0, 3):
            return self.to_profile().with_(history=HistoryPolicy(self.history),
                                           depth=max(0, self.depth))
        keep_all = self.history == 2

        def duration(value: tuple[int, int]) -> Duration:
            return Duration(nanoseconds=min(value[0] * 1_000_000_000 + value[1], 2**63 - 1))

        return QoSProfile(
            history=HistoryPolicy.KEEP_ALL if keep_all else HistoryPolicy.KEEP_LAST,
            depth=0 if keep_all else max(1, self.depth),
            reliability=ReliabilityPolicy.RELIABLE if self.reliable
            else ReliabilityPolicy.BEST_EFFORT,
            durability=DurabilityPolicy.TRANSIENT_LOCAL if self.transient_local
            else DurabilityPolicy.VOLATILE,
            lifespan=duration(self.lifespan),
            deadline=duration(self.deadline),
            liveliness=self.liveliness if self.liveliness in (1, 3)
            else LivelinessPolicy.SYSTEM_DEFAULT,
            liveliness_lease_duration=duration(self.liveliness_lease),
        )


DEFAULT_WIRE_QOS = WireQoS()


def qos_to_keyexpr(qos: WireQoS, *, explicit: bool = False) -> str:
    """Encode ``qos`` as rmw_zenoh's token chunk.

    By default fields equal to rmw_zenoh's defaults are left empty, exactly as rmw_zenoh
    writes them (tf2's ``/tf`` publisher: ``::,100:,:,:,,``). ``explicit=True`` writes
    reliability, durability, history and depth always (``1:2:1,100:,:,:,,``), which older
    Jazzy releases (<= 0.2.2, TRANSIENT_LOCAL default) parse identically.
    """
    d = DEFAULT_WIRE_QOS

    def num(value: int, default: int, force: bool = False) -> str:
        return str(value) if force or value != default else ""

    def dur(value: tuple[int, int], default: tuple[int, int]) -> str:
        return "," if value == default else f"{value[0]},{value[1]}"

    rel = num(qos.reliability, d.reliability, explicit)
    dura = num(qos.durability, d.durability, explicit)
    hist = num(qos.history, d.history, explicit) + "," + num(qos.depth, d.depth, explicit)
    live = num(qos.liveliness, d.liveliness) + "," + dur(qos.liveliness_lease, d.liveliness_lease)
    return (
        f"{rel}:{dura}:{hist}:{dur(qos.deadline, d.deadline)}:"
        f"{dur(qos.lifespan, d.lifespan)}:{live}"
    )


def qos_from_keyexpr(chunk: str) -> WireQoS:
    """Parse rmw_zenoh's QoS chunk; empty fields take rmw_zenoh's defaults."""
    fields = chunk.split(":")
    if len(fields) != 6:
        raise WireFormatError(f"QoS chunk {chunk!r} has {len(fields)} ':' fields, expected 6")
    d = DEFAULT_WIRE_QOS

    def num(text: str, default: int) -> int:
        if text == "":
            return default
        try:
            return int(text, 10)
        except ValueError:
            raise WireFormatError(f"QoS chunk {chunk!r}: {text!r} is not a number") from None

    def parts(text: str, n: int, what: str) -> list[str]:
        out = text.split(",")
        if len(out) != n:
            raise WireFormatError(f"QoS chunk {chunk!r}: {what} needs {n} ',' parts")
        return out

    hist = parts(fields[2], 2, "history")
    deadline = parts(fields[3], 2, "deadline")
    lifespan = parts(fields[4], 2, "lifespan")
    live = parts(fields[5], 3, "liveliness")
    return WireQoS(
        reliability=num(fields[0], d.reliability),
        durability=num(fields[1], d.durability),
        history=num(hist[0], d.history),
        depth=num(hist[1], d.depth),
        deadline=(num(deadline[0], d.deadline[0]), num(deadline[1], d.deadline[1])),
        lifespan=(num(lifespan[0], d.lifespan[0]), num(lifespan[1], d.lifespan[1])),
        liveliness=num(live[0], d.liveliness),
        liveliness_lease=(num(live[1], d.liveliness_lease[0]), num(live[2], d.liveliness_lease[1])),
    )


# ---------------------------------------------------------------------------------------
# Liveliness tokens (§2)


class EntityKind(enum.Enum):
    """Entity kinds of rmw_zenoh's liveliness tokens."""

    NODE = "NN"
    PUBLISHER = "MP"
    SUBSCRIPTION = "MS"
    SERVICE = "SS"
    CLIENT = "SC"


def _chunk(value: str, what: str) -> str:
    out = mangle(value)
    if not out:
        raise WireFormatError(f"token {what} must not be empty")
    return out


def node_token(
    domain_id: int, zid: str, node_id: int, namespace: str, node_name: str, enclave: str = "/"
) -> str:
    """Liveliness key expression announcing a node (``eid == nid``)."""
    return (
        f"{LIVELINESS_PREFIX}/{int(domain_id)}/{zid}/{int(node_id)}/{int(node_id)}/NN/"
        f"{_chunk(enclave, 'enclave')}/{_chunk(namespace, 'namespace')}/"
        f"{_chunk(node_name, 'node name')}"
    )


def endpoint_token(
    domain_id: int,
    zid: str,
    node_id: int,
    entity_id: int,
    kind: EntityKind,
    namespace: str,
    node_name: str,
    topic: str,
    ros_type: str,
    qos: WireQoS,
    *,
    enclave: str = "/",
    type_hash_str: str | None = None,
    explicit_qos: bool = False,
) -> str:
    """Liveliness key expression announcing a publisher/subscription/service/client."""
    if kind is EntityKind.NODE:
        raise WireFormatError("use node_token() for nodes")
    hash_str = type_hash_str if type_hash_str is not None else type_hash(ros_type)
    return (
        f"{LIVELINESS_PREFIX}/{int(domain_id)}/{zid}/{int(node_id)}/{int(entity_id)}/"
        f"{kind.value}/{_chunk(enclave, 'enclave')}/{_chunk(namespace, 'namespace')}/"
        f"{_chunk(node_name, 'node name')}/{_chunk(topic, 'topic')}/"
        f"{dds_type_name(ros_type)}/{_chunk(hash_str, 'type hash')}/"
        f"{qos_to_keyexpr(qos, explicit=explicit_qos)}"
    )


@dataclass(frozen=True, slots=True)
class TokenInfo:
    """A parsed liveliness token: one ROS graph entity (names demangled)."""

    domain_id: int
    zid: str
    node_id: int
    entity_id: int
    kind: EntityKind
    enclave: str
    namespace: str
    node_name: str
    topic: str | None = None
    ros_type: str | None = None
    type_hash: str | None = None
    qos: WireQoS | None = None
    keyexpr: str = field(default="", compare=False)

    @property
    def node_fqn(self) -> str:
        """``/namespace/node`` as ``ros2 node list`` prints it."""
        ns = self.namespace.rstrip("/")
        return f"{ns}/{self.node_name}"

    @property
    def gid(self) -> bytes:
        """The 16-byte GID rmw_zenoh derives from this entity's token (:func:`entity_gid`)."""
        return entity_gid(self.keyexpr) if self.keyexpr else b""

    @property
    def data_key(self) -> str | None:
        """The data key this endpoint publishes/subscribes on (None for nodes)."""
        if self.topic is None or self.ros_type is None or self.type_hash is None:
            return None
        return data_key(self.domain_id, self.topic, self.ros_type, self.type_hash)


def parse_token(keyexpr: str) -> TokenInfo:
    """Parse a liveliness token announced by rmw_zenoh (or posekit)."""
    chunks = keyexpr.split("/")
    if len(chunks) < 9 or chunks[0] != LIVELINESS_PREFIX:
        raise WireFormatError(f"not an rmw_zenoh liveliness token: {keyexpr!r}")
    if any(not c for c in chunks):
        raise WireFormatError(f"liveliness token with an empty chunk: {keyexpr!r}")
    try:
        domain, nid, eid = int(chunks[1]), int(chunks[3]), int(chunks[4])
    except ValueError:
        raise WireFormatError(f"token domain/node/entity ids not numeric: {keyexpr!r}") from None
    try:
        kind = EntityKind(chunks[5])
    except ValueError:
        raise WireFormatError(f"unknown entity kind {chunks[5]!r} in {keyexpr!r}") from None
    common = {
        "domain_id": domain,
        "zid": chunks[2],
        "node_id": nid,
        "entity_id": eid,
        "kind": kind,
        "enclave": demangle(chunks[6]),
        "namespace": demangle(chunks[7]),
        "node_name": demangle(chunks[8]),
        "keyexpr": keyexpr,
    }
    if kind is EntityKind.NODE:
        if len(chunks) != 9:
            raise WireFormatError(f"node token needs 9 chunks, has {len(chunks)}: {keyexpr!r}")
        return TokenInfo(**common)  # type: ignore[arg-type]
    if len(chunks) != 13:
        raise WireFormatError(f"endpoint token needs 13 chunks, has {len(chunks)}: {keyexpr!r}")
    return TokenInfo(
        **common,  # type: ignore[arg-type]
        topic=demangle(chunks[9]),
        ros_type=ros_type_name(chunks[10]),
        type_hash=demangle(chunks[11]),
        qos=qos_from_keyexpr(chunks[12]),
    )


# ---------------------------------------------------------------------------------------
# GID and attachment (§3)


def entity_gid(token_keyexpr: str) -> bytes:
    """The 16-byte GID rmw_zenoh derives for an entity: XXH3-128 of its token, LE halves.

    Uses the ``xxhash`` package; without it, a BLAKE2b-128 digest (equally stable, so still
    valid for ROS receivers, which never check GIDs against tokens) is returned instead.
    """
    try:
        import xxhash
    except ImportError:
        return hashlib.blake2b(token_keyexpr.encode(), digest_size=16).digest()
    digest: int = xxhash.xxh3_128(token_keyexpr.encode()).intdigest()
    return digest.to_bytes(16, "little")


class Attachment(NamedTuple):
    """Per-sample metadata: publisher sequence number (from 1), source time (ns), GID.

    A named tuple (immutable, cheap to build: one per received sample).
    """

    sequence_number: int
    source_timestamp: int
    gid: bytes
    legacy: bool = False


#: ``Attachment`` built from a 4-tuple without the Python-level ``__new__`` of a NamedTuple.
_new_attachment: Callable[[type[Attachment], tuple[int, int, bytes, bool]], Attachment] = (
    tuple.__new__
)


def encode_attachment(seq: int, timestamp_ns: int, gid: bytes) -> bytes:
    """Compact 33-byte attachment (Jazzy >= 0.2.4, Kilted, Rolling)."""
    if len(gid) != 16:
        raise WireFormatError(f"a GID has 16 bytes, got {len(gid)}")
    return _COMPACT.pack(seq, timestamp_ns, 16) + gid


def encode_attachment_legacy(seq: int, timestamp_ns: int, gid: bytes) -> bytes:
    """Legacy 77-byte keyed attachment (Jazzy rmw_zenoh 0.2.0 .. 0.2.3)."""
    if len(gid) != 16:
        raise WireFormatError(f"a GID has 16 bytes, got {len(gid)}")
    return b"".join(
        (_LEGACY_SEQ, _I64.pack(seq), _LEGACY_TS, _I64.pack(timestamp_ns), _LEGACY_GID, gid)
    )


def decode_attachment(data: bytes) -> Attachment:
    """Decode either attachment format (detected by the legacy label); trailing bytes ignored."""
    if (type(data) is bytes and len(data) == ATTACHMENT_SIZE and data[16] == 16
            and not data.startswith(_LEGACY_SEQ)):
        # the compact form, exactly (every sample from a current rmw_zenoh or posekit)
        seq, ts, _ = _COMPACT.unpack_from(data, 0)
        return _new_attachment(Attachment, (seq, ts, data[17:], False))
    if len(data) >= 16 and data[:16] == _LEGACY_SEQ:
        if len(data) < LEGACY_ATTACHMENT_SIZE:
            raise WireFormatError(
                f"legacy attachment of {len(data)} bytes, expected {LEGACY_ATTACHMENT_SIZE}"
            )
        ts_at, gid_at = 24, 24 + len(_LEGACY_TS) + 8
        if data[ts_at : ts_at + len(_LEGACY_TS)] != _LEGACY_TS or (
            data[gid_at : gid_at + len(_LEGACY_GID)] != _LEGACY_GID
        ):
            raise WireFormatError("legacy attachment with unexpected labels")
        seq = _I64.unpack_from(data, 16)[0]
        ts = _I64.unpack_from(data, ts_at + len(_LEGACY_TS))[0]
        gid_start = gid_at + len(_LEGACY_GID)
        return Attachment(seq, ts, bytes(data[gid_start : gid_start + 16]), legacy=True)
    if len(data) < ATTACHMENT_SIZE:
        raise WireFormatError(f"attachment of {len(data)} bytes, expected {ATTACHMENT_SIZE}")
    seq, ts, gid_len = _COMPACT.unpack_from(data, 0)
    if gid_len != 16:
        raise WireFormatError(f"attachment GID length byte is {gid_len:#04x}, expected 0x10")
    return Attachment(seq, ts, data[17:33] if type(data) is bytes else bytes(data[17:33]))


# ---------------------------------------------------------------------------------------
# Graph


#: Liveliness tokens (nodes and endpoints of the whole graph) a :class:`GraphCache` keeps.
MAX_GRAPH_TOKENS = 20_000


class GraphCache:
    """The ROS graph as announced by liveliness tokens (posekit's and real ROS 2 nodes').

    Feed it with :meth:`add` / :meth:`remove` (liveliness PUT / DELETE); malformed tokens
    are ignored and counted in :attr:`rejected`. At most ``max_tokens`` tokens are kept
    (peers choose how many they announce): new ones past that are counted in
    :attr:`overflowed` and ignored until others leave. Not thread-safe by itself: callers
    lock.
    """

    def __init__(self, max_tokens: int | None = None) -> None:
        self._tokens: dict[str, TokenInfo] = {}
        self.max_tokens = MAX_GRAPH_TOKENS if max_tokens is None else int(max_tokens)
        self.rejected = 0
        self.overflowed = 0

    def add(self, keyexpr: str) -> TokenInfo | None:
        """Record a token; returns the parsed entity or None if malformed or over the bound."""
        if keyexpr not in self._tokens and len(self._tokens) >= self.max_tokens:
            self.overflowed += 1
            return None
        try:
            info = parse_token(keyexpr)
        except WireFormatError:
            self.rejected += 1
            return None
        self._tokens[keyexpr] = info
        return info

    def remove(self, keyexpr: str) -> TokenInfo | None:
        """Forget a token (its entity left the graph)."""
        return self._tokens.pop(keyexpr, None)

    def entities(self) -> list[TokenInfo]:
        """Every known entity."""
        return list(self._tokens.values())

    def node_names(self) -> list[str]:
        """Sorted fully qualified node names (``ros2 node list``)."""
        return sorted({t.node_fqn for t in self._tokens.values() if t.kind is EntityKind.NODE})

    def topic_names_and_types(self) -> list[tuple[str, list[str]]]:
        """Sorted topics with their sorted type names (``ros2 topic list -t``)."""
        topics: dict[str, set[str]] = {}
        for t in self._tokens.values():
            if t.kind in (EntityKind.PUBLISHER, EntityKind.SUBSCRIPTION) and t.topic:
                assert t.ros_type is not None
                topics.setdefault(t.topic, set()).add(t.ros_type)
        return [(name, sorted(types)) for name, types in sorted(topics.items())]

    def service_names_and_types(self) -> list[tuple[str, list[str]]]:
        """Sorted services (servers or clients) with their sorted type names.

        What ``ros2 service list -t`` prints.
        """
        services: dict[str, set[str]] = {}
        for t in self._tokens.values():
            if t.kind in (EntityKind.SERVICE, EntityKind.CLIENT) and t.topic:
                assert t.ros_type is not None
                services.setdefault(t.topic, set()).add(t.ros_type)
        return [(name, sorted(types)) for name, types in sorted(services.items())]

    def names_and_types_by_node(
        self, node_name: str, namespace: str, kinds: tuple[EntityKind, ...]
    ) -> list[tuple[str, list[str]]]:
        """Sorted endpoint names of ``kinds`` one node announced, with their types."""
        found: dict[str, set[str]] = {}
        for t in self._tokens.values():
            if t.kind in kinds and t.node_name == node_name and t.namespace == namespace:
                assert t.topic is not None
                assert t.ros_type is not None
                found.setdefault(t.topic, set()).add(t.ros_type)
        return [(name, sorted(types)) for name, types in sorted(found.items())]

    def endpoints(self, topic: str, kind: EntityKind) -> list[TokenInfo]:
        """Endpoints of ``kind`` on a fully qualified topic (or service) name."""
        return [t for t in self._tokens.values() if t.kind is kind and t.topic == topic]
