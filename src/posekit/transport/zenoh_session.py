"""Zenoh sessions that speak ROS 2's rmw_zenoh: nodes, publishers, subscriptions, the graph.

Zero configuration on one machine, like rmw_zenoh: the session is a Zenoh *peer* that
connects to ``tcp/127.0.0.1:7447`` and listens on ``tcp/127.0.0.1:<random>`` (loopback
only). When nothing answers on the router endpoint, the process hosts a Zenoh *router*
there itself (a stand-in for ``rmw_zenohd``), so a second posekit process, a plain zenoh
peer or an rmw_zenoh node pointed at that endpoint finds it with nothing started by hand.

``ZENOH_SESSION_CONFIG_URI`` (a JSON5 zenoh config file) replaces these defaults entirely,
and ``ZENOH_CONFIG_OVERRIDE`` (``key/path=json5;key2=value``, as rmw_zenoh reads it) is
applied on top; ``ROS_DOMAIN_ID`` selects the domain.

Messages go out as CDR (``posekit.msgs.to_cdr``) with the compact 33-byte attachment
(sequence number from 1, source time, GID) on the data key; TRANSIENT_LOCAL publishers are
zenoh-ext AdvancedPublishers with a cache of ``depth`` samples, and TRANSIENT_LOCAL
subscriptions AdvancedSubscribers with history and late-publisher detection, as rmw_zenoh
does. Every entity is announced by an rmw_zenoh liveliness token.

A subscription listens on its exact data key, type hash included (rmw_zenoh's key), so a
publisher of another definition of the type never reaches it; the graph names such a
publisher in one warning. Received samples that do not decode (no or malformed
attachment, bad CDR) are dropped and counted in :attr:`WireSubscription.dropped`; each
subscription logs at most one line per second per reason (with how many were suppressed),
whatever GIDs the senders use, and tracks sequence numbers for at most
:data:`MAX_TRACKED_PUBLISHERS` publishers. The graph keeps at most
:data:`~posekit.transport.zenoh_wire.MAX_GRAPH_TOKENS` liveliness tokens. Exceptions from
user callbacks are logged, never propagated into zenoh's threads.
"""

from __future__ import annotations

import atexit
import collections
import itertools
import json
import logging
import os
import socket
import threading
import time
import weakref
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import zenoh
import zenoh.ext as zext

from posekit.msgs.cdr import cdr_decoder, from_cdr, to_cdr
from posekit.msgs.errors import CdrError
from posekit.msgs.registry import normalize_type_name
from posekit.runtime.inbox import Inbox
from posekit.runtime.ratelimit import RateLimitedLog
from posekit.transport.zenoh_wait import ChannelWaiter, PrimaryChannel, on_receive_thread
from posekit.transport.zenoh_wire import (
    LIVELINESS_PREFIX,
    Attachment,
    EntityKind,
    GraphCache,
    TokenInfo,
    WireFormatError,
    WireQoS,
    data_key,
    decode_attachment,
    encode_attachment,
    encode_attachment_legacy,
    endpoint_token,
    entity_gid,
    node_token,
    type_hash,
)

__all__ = [
    "DEFAULT_ROUTER_ENDPOINT",
    "ENV_CONFIG_OVERRIDE",
    "ENV_CONFIG_URI",
    "ENV_DOMAIN_ID",
    "GRAPH_SETTLE_S",
    "GRAPH_SILENT_PEER_S",
    "MAX_TRACKED_PUBLISHERS",
    "NodeEntity",
    "SessionOptions",
    "WirePublisher",
    "WireServiceClient",
    "WireServiceServer",
    "WireSubscription",
    "ZenohGraph",
    "ZenohSession",
    "ZenohSessionError",
    "build_peer_config",
    "build_router_config",
    "open_session",
]

_log = logging.getLogger("posekit.transport.zenoh")
_PUT = zenoh.SampleKind.PUT
_CHANNEL_CAPACITY = 4096
#: Payload bytes an executor takes from one channel per look (see WireSubscription.pull).
_PULL_BYTES = 256 * 1024
#: Publishers (GIDs) whose sequence numbers a subscription tracks for lost-message counts;
#: the least recently heard is forgotten first, so senders cannot grow the table.
MAX_TRACKED_PUBLISHERS = 1024

DEFAULT_ROUTER_ENDPOINT = "tcp/127.0.0.1:7447"
#: :meth:`ZenohSession.sync_graph`: the connected peers must not change for this long (s).
GRAPH_SETTLE_S = 0.05
#: :meth:`ZenohSession.sync_graph`: longest wait (s) for a connected peer's first token.
GRAPH_SILENT_PEER_S = 0.5
ENV_CONFIG_URI = "ZENOH_SESSION_CONFIG_URI"
ENV_CONFIG_OVERRIDE = "ZENOH_CONFIG_OVERRIDE"
ENV_DOMAIN_ID = "ROS_DOMAIN_ID"


class ZenohSessionError(RuntimeError):
    """A Zenoh session, router or entity could not be created (the message says why)."""


@dataclass(frozen=True, slots=True)
class SessionOptions:
    """How to open a session. ``None`` fields come from the environment or rmw defaults.

    Attributes:
        domain_id: ROS domain; default ``$ROS_DOMAIN_ID`` or 0.
        router_endpoint: where the router is (and is hosted if absent); loopback default.
        host_router: host a router on ``router_endpoint`` when nothing answers there.
        config_uri: zenoh JSON5 config file; default ``$ZENOH_SESSION_CONFIG_URI``. When set,
            posekit's defaults (and router hosting) do not apply.
        listen_endpoint: this peer's own listener (must be dialable by other peers).
        enclave: the ROS security enclave written in tokens.
        legacy_attachment: write the 77-byte keyed attachment of Jazzy rmw_zenoh <= 0.2.3.
        explicit_qos: write reliability/durability/history/depth explicitly in tokens.
    """

    domain_id: int | None = None
    router_endpoint: str = DEFAULT_ROUTER_ENDPOINT
    host_router: bool = True
    config_uri: str | None = None
    listen_endpoint: str = "tcp/127.0.0.1:0"
    enclave: str = "/"
    legacy_attachment: bool = False
    explicit_qos: bool = False


def _json(value: Any) -> str:
    return json.dumps(value)


def _apply_overrides(config: zenoh.Config, overrides: str) -> None:
    for item in filter(None, (part.strip() for part in overrides.split(";"))):
        key, sep, value = item.partition("=")
        if not sep:
            raise ZenohSessionError(f"{ENV_CONFIG_OVERRIDE}: {item!r} is not key=value")
        try:
            config.insert_json5(key.strip(), value.strip())
        except Exception as exc:
            raise ZenohSessionError(f"{ENV_CONFIG_OVERRIDE}: cannot set {key!r}: {exc}") from exc


def build_peer_config(options: SessionOptions) -> zenoh.Config:
    """The peer config posekit uses (rmw_zenoh's session defaults, loopback only)."""
    uri = options.config_uri or os.environ.get(ENV_CONFIG_URI)
    if uri:
        try:
            config = zenoh.Config.from_file(uri)
        except Exception as exc:
            raise ZenohSessionError(f"cannot load zenoh config {uri!r}: {exc}") from exc
    else:
        config = zenoh.Config()
        config.insert_json5("mode", _json("peer"))
        config.insert_json5("connect/endpoints", _json([options.router_endpoint]))
        config.insert_json5("listen/endpoints", _json([options.listen_endpoint]))
        config.insert_json5("scouting/multicast/enabled", "false")
        config.insert_json5("scouting/gossip/enabled", "true")
        config.insert_json5("timestamping/enabled", _json({"router": True, "peer": True}))
        config.insert_json5("queries_default_timeout", "60000")
    overrides = os.environ.get(ENV_CONFIG_OVERRIDE)
    if overrides:
        _apply_overrides(config, overrides)
    return config


def build_router_config(endpoint: str) -> zenoh.Config:
    """A router listening on ``endpoint`` only (what ``rmw_zenohd`` is, on loopback)."""
    config = zenoh.Config()
    config.insert_json5("mode", _json("router"))
    config.insert_json5("listen/endpoints", _json([endpoint]))
    config.insert_json5("connect/endpoints", "[]")
    config.insert_json5("scouting/multicast/enabled", "false")
    config.insert_json5("scouting/gossip/enabled", "true")
    config.insert_json5("timestamping/enabled", _json({"router": True, "peer": True}))
    return config


def _tcp_host_port(endpoint: str) -> tuple[str, int] | None:
    proto, _, address = endpoint.partition("/")
    if proto != "tcp" or ":" not in address:
        return None
    host, _, port = address.rpartition(":")
    host = host.strip("[]")
    try:
        return host, int(port.split("#")[0])
    except ValueError:
        return None


def _something_listens(endpoint: str, timeout: float = 0.3) -> bool:
    target = _tcp_host_port(endpoint)
    if target is None:
        return True  # not TCP: cannot probe, assume the user runs it
    try:
        with socket.create_connection(target, timeout=timeout):
            return True
    except OSError:
        return False


def open_router(endpoint: str = DEFAULT_ROUTER_ENDPOINT) -> zenoh.Session:
    """Open a Zenoh router session listening on ``endpoint`` (``posekit router``)."""
    try:
        return zenoh.open(build_router_config(endpoint))
    except Exception as exc:
        raise ZenohSessionError(f"cannot host a zenoh router on {endpoint}: {exc}") from exc


def _domain_from_env() -> int:
    text = os.environ.get(ENV_DOMAIN_ID, "").strip()
    if not text:
        return 0
    try:
        value = int(text)
    except ValueError:
        raise ZenohSessionError(f"{ENV_DOMAIN_ID}={text!r} is not an integer") from None
    if not 0 <= value <= 232:
        raise ZenohSessionError(f"{ENV_DOMAIN_ID}={value} is outside 0..232")
    return value


def open_session(options: SessionOptions | None = None) -> ZenohSession:
    """Open a session (hosting the router first when needed; see the module docstring)."""
    options = options or SessionOptions()
    domain = options.domain_id if options.domain_id is not None else _domain_from_env()
    router = None
    uses_defaults = not (options.config_uri or os.environ.get(ENV_CONFIG_URI))
    if uses_defaults and options.host_router and not _something_listens(options.router_endpoint):
        try:
            router = open_router(options.router_endpoint)
            _log.info("no zenoh router on %s: hosting one in this process", options.router_endpoint)
        except ZenohSessionError as exc:  # another process won the race: use theirs
            _log.debug("%s", exc)
    try:
        session = zenoh.open(build_peer_config(options))
    except Exception as exc:
        if router is not None:
            _quiet(router.close)
        raise ZenohSessionError(f"cannot open a zenoh session: {exc}") from exc
    return ZenohSession(session, router, domain, options)


# ---------------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class NodeEntity:
    """A node announced on the graph."""

    name: str
    namespace: str
    node_id: int
    token_key: str


class ZenohSession:
    """An open rmw_zenoh-compatible session. Thread-safe; close() it (or use ``with``)."""

    def __init__(
        self,
        session: zenoh.Session,
        router: zenoh.Session | None,
        domain_id: int,
        options: SessionOptions,
    ) -> None:
        self.session = session
        self.router = router
        self.domain_id = domain_id
        self.options = options
        self.zid = str(session.info.zid())
        self._ids = itertools.count()
        self._lock = threading.Lock()
        self._tokens: dict[str, Any] = {}
        self._entities: list[
            WirePublisher | WireSubscription | WireServiceServer | WireServiceClient
        ] = []
        self._graph: ZenohGraph | None = None
        self._closed = False
        #: Subscriptions' drain threads: joined after the session closed (see close()).
        self.drainers: list[threading.Thread] = []
        #: Executors' channel waiters (see make_waiter): closed after the session.
        self._waiters: weakref.WeakSet[ChannelWaiter] = weakref.WeakSet()
        _open_sessions.add(self)

    def make_waiter(self) -> ChannelWaiter:
        """The waiter of an executor that reads this session's subscriptions itself."""
        waiter = ChannelWaiter()
        self._waiters.add(waiter)
        return waiter

    @property
    def hosts_router(self) -> bool:
        """True when this process hosts the router on the router endpoint."""
        return self.router is not None

    def __enter__(self) -> ZenohSession:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def next_entity_id(self) -> int:
        """A fresh id, unique within this session (node and entity ids share the counter)."""
        return next(self._ids)

    def _declare_token(self, key: str) -> Any:
        token = self.session.liveliness().declare_token(key)
        with self._lock:
            self._tokens[key] = token
        return token

    def create_node(self, name: str, namespace: str = "/") -> NodeEntity:
        """Announce a node (``NN`` token) and return its handle."""
        namespace = namespace if namespace.startswith("/") else "/" + namespace
        node_id = self.next_entity_id()
        key = node_token(self.domain_id, self.zid, node_id, namespace, name, self.options.enclave)
        self._declare_token(key)
        return NodeEntity(name, namespace, node_id, key)

    def destroy_node(self, node: NodeEntity) -> None:
        """Withdraw a node's ``NN`` token (its endpoints are destroyed separately)."""
        with self._lock:
            token = self._tokens.pop(node.token_key, None)
        if token is not None:
            _quiet(token.undeclare)

    def sync_graph(self, timeout: float = 2.0) -> int:
        """Complete :attr:`graph` with every live token of the domain.

        Returns how many tokens the graph holds.

        A liveliness query alone is not enough: peers find each other by gossip after the
        session opens, and tokens travel over those direct peer links (the router does not
        relay one peer's tokens to another). A query sent before the links are up (the
        first tens of milliseconds, longer on a loaded machine) is answered with nothing
        at all, which made one ``posekit topic list`` in five print an empty graph. So
        this queries, then waits for the graph's liveliness subscriber (which receives
        each peer's tokens as soon as its link is up) until the set of connected peers has
        been stable for :data:`GRAPH_SETTLE_S` and every connected peer has announced
        tokens; a peer without any (a bare zenoh session, a process still starting) is
        waited for at most :data:`GRAPH_SILENT_PEER_S`. Bounded by ``timeout`` seconds.
        """
        graph = self.graph
        start = time.monotonic()
        deadline = start + max(0.05, timeout)
        self._query_tokens(graph, deadline - start)
        stable_since = time.monotonic()
        peers: set[str] = set()
        while True:
            now = time.monotonic()
            current = {str(z) for z in self.session.info.peers_zid()}
            if current != peers:
                peers, stable_since = current, now
            announced = {t.zid for t in graph.entities()}
            silent = peers - announced
            settled = now - stable_since >= GRAPH_SETTLE_S
            if settled and (not silent or now - start >= GRAPH_SILENT_PEER_S):
                break
            if now >= deadline:
                break
            graph.wait_until(lambda _cache: False, min(0.005, deadline - now))
        if silent and peers:  # a late link: ask once more now that it is up
            self._query_tokens(graph, max(0.05, deadline - time.monotonic()))
        return len(graph.entities())

    def _query_tokens(self, graph: ZenohGraph, timeout: float) -> None:
        replies = self.session.liveliness().get(
            f"{LIVELINESS_PREFIX}/{int(self.domain_id)}/**", timeout=max(0.05, timeout)
        )
        for reply in replies:
            ok = reply.ok
            if ok is not None:
                graph.add_remote(str(ok.key_expr))

    def create_publisher(
        self, node: NodeEntity, topic: str, ros_type: str, qos: WireQoS, *,
        remote_only: bool = False,
    ) -> WirePublisher:
        """A publisher of ``ros_type`` on the fully qualified ``topic``.

        ``remote_only``: its samples reach other sessions only, never this session's
        subscribers.
        """
        pub = WirePublisher(self, node, topic, normalize_type_name(ros_type), qos,
                            remote_only=remote_only)
        with self._lock:
            self._entities.append(pub)
        return pub

    def create_subscription(
        self,
        node: NodeEntity,
        topic: str,
        msg_type: str | type[Any],
        qos: WireQoS,
        callback: Callable[[Any, Attachment], None] | Callable[[Any], None],
        *,
        warn: Callable[[str], object] | None = None,
        remote_only: bool = False,
        message_only: bool = False,
    ) -> WireSubscription:
        """Deliver decoded messages on ``topic`` to ``callback``, on the receive thread.

        The subscription's receive thread calls ``callback(msg, attachment)``, or
        ``callback(msg)`` with ``message_only``; ``remote_only``: only samples published by
        other sessions.
        """
        sub = WireSubscription(self, node, topic, msg_type, qos, callback, warn,
                               remote_only=remote_only, message_only=message_only)
        with self._lock:
            self._entities.append(sub)
        return sub

    def create_service_server(
        self,
        node: NodeEntity,
        service: str,
        srv_type: type[Any],
        qos: WireQoS,
        on_request: Callable[[Any, Callable[[Any], None], Attachment], None],
        *,
        warn: Callable[[str], object] | None = None,
    ) -> WireServiceServer:
        """Serve ``service``: ``on_request(request, respond, attachment)`` per query.

        Called on a zenoh thread; ``attachment`` is the query's (the calling client's GID and
        its sequence number for the request). ``respond(response)`` replies, from any thread.
        """
        server = WireServiceServer(self, node, service, srv_type, qos, on_request, warn)
        with self._lock:
            self._entities.append(server)
        return server

    def create_service_client(
        self, node: NodeEntity, service: str, srv_type: type[Any], qos: WireQoS,
        *, warn: Callable[[str], object] | None = None,
    ) -> WireServiceClient:
        """A client of ``service`` (requests are zenoh queries)."""
        client = WireServiceClient(self, node, service, srv_type, qos, warn)
        with self._lock:
            self._entities.append(client)
        return client

    @property
    def graph(self) -> ZenohGraph:
        """The ROS graph of this domain, built from liveliness tokens (created on first use)."""
        with self._lock:
            if self._graph is None:
                self._graph = ZenohGraph(self.session, self.domain_id)
            return self._graph

    def close(self) -> None:
        """Undeclare everything, leave the graph and close the session (and hosted router)."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
            entities, self._entities = self._entities, []
            tokens, self._tokens = list(self._tokens.values()), {}
            graph, self._graph = self._graph, None
        for entity in entities:
            entity.destroy()
        for token in tokens:
            _quiet(token.undeclare)
        if graph is not None:
            graph.close()
        _quiet(self.session.close)
        # The closed session's channels end every drain thread's recv(); wait for them to
        # leave zenoh, since a thread still inside it when the interpreter finalizes aborts
        # the process ("FATAL: exception not rethrown").
        deadline = time.monotonic() + 2.0
        for thread in self.drainers:
            if thread is not threading.current_thread():
                thread.join(timeout=max(0.0, deadline - time.monotonic()))
        for waiter in list(self._waiters):  # executors blocked in a channel, likewise
            waiter.close(timeout=max(0.0, deadline - time.monotonic()))
        if self.router is not None:
            _quiet(self.router.close)


# zenoh-python runs Python callbacks on a non-daemon thread that lives as long as the
# session, and the interpreter joins non-daemon threads before atexit handlers run: a process
# ending without closing its session (no rclpy.shutdown()) would hang forever. Close them
# from threading's own shutdown hook, which runs before that join.
_open_sessions: weakref.WeakSet[ZenohSession] = weakref.WeakSet()


def _close_open_sessions() -> None:
    for session in list(_open_sessions):
        session.close()


_register_shutdown = getattr(threading, "_register_atexit", atexit.register)
_register_shutdown(_close_open_sessions)


def _quiet(fn: Callable[[], Any]) -> None:
    try:
        fn()
    except Exception as exc:  # closing twice or after zenoh shut down
        _log.debug("ignored while closing: %s", exc)


class WirePublisher:
    """Publishes CDR + attachment on the data key; announced by an ``MP`` token."""

    def __init__(
        self, owner: ZenohSession, node: NodeEntity, topic: str, ros_type: str, qos: WireQoS,
        *, remote_only: bool = False,
    ) -> None:
        self.topic = topic
        self.ros_type = ros_type
        self.qos = qos
        self.key = data_key(owner.domain_id, topic, ros_type)
        self.entity_id = owner.next_entity_id()
        self.token_key = endpoint_token(
            owner.domain_id,
            owner.zid,
            node.node_id,
            self.entity_id,
            EntityKind.PUBLISHER,
            node.namespace,
            node.name,
            topic,
            ros_type,
            qos,
            enclave=owner.options.enclave,
            explicit_qos=owner.options.explicit_qos,
        )
        self.gid = entity_gid(self.token_key)
        self._encode = (
            encode_attachment_legacy if owner.options.legacy_attachment else encode_attachment
        )
        self._seq = itertools.count(1)
        reliability = zenoh.Reliability.RELIABLE if qos.reliable else zenoh.Reliability.BEST_EFFORT
        congestion = (
            zenoh.CongestionControl.BLOCK
            if qos.reliable and qos.history == 2
            else zenoh.CongestionControl.DROP
        )
        session = owner.session
        destination = zenoh.Locality.REMOTE if remote_only else zenoh.Locality.ANY
        try:
            if qos.transient_local:
                self._pub: Any = zext.declare_advanced_publisher(
                    session,
                    self.key,
                    cache=zext.CacheConfig(max(1, qos.depth)),
                    publisher_detection=True,
                    sample_miss_detection=(
                        zext.MissDetectionConfig(heartbeat=None, sporadic_heartbeat=0.5)
                        if qos.reliable
                        else None
                    ),
                    reliability=reliability,
                    congestion_control=congestion,
                    allowed_destination=destination,
                )
            else:
                self._pub = session.declare_publisher(
                    self.key, reliability=reliability, congestion_control=congestion,
                    allowed_destination=destination,
                )
            self._token = session.liveliness().declare_token(self.token_key)
        except Exception as exc:
            raise ZenohSessionError(f"cannot declare a publisher on {self.key}: {exc}") from exc
        self._destroyed = False

    def publish(self, msg: Any) -> None:
        """Serialize and send ``msg`` (raises CdrError for an unserializable message)."""
        self.publish_cdr(to_cdr(msg, self.ros_type))

    def publish_cdr(self, payload: bytes) -> None:
        """Send an already serialized CDR payload with the next attachment."""
        if self._destroyed:
            raise ZenohSessionError(f"publisher on {self.topic} was destroyed")
        attachment = self._encode(next(self._seq), time.time_ns(), self.gid)
        self._pub.put(payload, attachment=attachment)

    def destroy(self) -> None:
        """Leave the graph and stop publishing."""
        if self._destroyed:
            return
        self._destroyed = True
        _quiet(self._token.undeclare)
        _quiet(self._pub.undeclare)


class WireSubscription:
    """Receives a topic's samples, validates and decodes them; announced by an ``MS`` token.

    Subscribes on the exact data key, type hash included, as rmw_zenoh does: a publisher of
    another definition of the type (another hash) never reaches it. Such a publisher is
    noticed on the graph instead, with one logged line, rather than silently missing (a
    wildcard hash chunk would also catch its samples, but costs every sample zenoh's key
    matching: about 1.5 us of CPU per message, see docs/performance.md).
    """

    def __init__(
        self,
        owner: ZenohSession,
        node: NodeEntity,
        topic: str,
        msg_type: str | type[Any],
        qos: WireQoS,
        callback: Callable[[Any, Attachment], None] | Callable[[Any], None],
        warn: Callable[[str], object] | None,
        *,
        remote_only: bool = False,
        message_only: bool = False,
    ) -> None:
        ros_type = normalize_type_name(
            msg_type if isinstance(msg_type, str) else msg_type.__msgtype__
        )
        self.topic = topic
        self.ros_type = ros_type
        self.msg_type = msg_type
        self.qos = qos
        self.type_hash = type_hash(ros_type)
        self.key = data_key(owner.domain_id, topic, ros_type)
        self._decode = cdr_decoder(msg_type)
        self._callback: Callable[..., None] = callback
        #: ``callback(msg)`` instead of ``callback(msg, attachment)``.
        self._message_only = message_only
        warn_fn = warn or _log.warning
        # Keyed by posekit's reason, never by what the sender chose (GID, type hash):
        # at most one line per second per reason, with the count of those suppressed.
        self._warn = RateLimitedLog(lambda line: warn_fn(f"dropping samples on {topic}: {line}"))
        #: Dropped samples by reason ("attachment", "cdr", "callback").
        self.dropped: collections.Counter[str] = collections.Counter()
        self.received = 0
        #: Sequence-number gaps seen per publisher GID (ROS's MESSAGE_LOST), for the
        #: :data:`MAX_TRACKED_PUBLISHERS` publishers heard from most recently.
        self.lost: collections.Counter[bytes] = collections.Counter()
        self._last_seq: collections.OrderedDict[bytes, int] = collections.OrderedDict()
        self._recent_gid = b""  # the GID last heard from: already last in _last_seq
        self._destroyed = False
        #: Whether an executor may read this subscription (a channel, not a callback).
        self.pullable = False
        # Pulled mode (pull_into): only the holder of _turn receives from the channel. The
        # drain thread takes it and blocks in recv(). As a *secondary* source it leaves the
        # sample in _head and the turn with the executor (_handed), which takes what else
        # the channel holds and gives the turn back once it is empty. As the *primary* of
        # the executor's ChannelWaiter (see posekit.transport.zenoh_wait) its first sample
        # hands the turn over for good (_executor_reads): the executor then waits in the
        # channel itself until release_pull. One reader at a time keeps the order.
        self._turn = threading.Lock()
        self._mode = threading.RLock()
        self._pulled_by: Inbox | None = None
        self._head: zenoh.Sample | None = None
        self._handed = False
        self._waiter: ChannelWaiter | None = None  # the inbox's waiter, when a Zenoh one
        self._primary = False  # this subscription is that waiter's primary
        self._executor_reads = False
        self._undeclare_on_leave = False  # destroyed while the executor was in the channel
        self._last_size = 0  # bytes of the last payload decoded (pull's byte budget)
        self._zenoh = owner.session
        self._owner = owner
        self._local_ok = not remote_only  # a session-local poke reaches the channel
        self.entity_id = owner.next_entity_id()
        self.token_key = endpoint_token(
            owner.domain_id,
            owner.zid,
            node.node_id,
            self.entity_id,
            EntityKind.SUBSCRIPTION,
            node.namespace,
            node.name,
            topic,
            ros_type,
            qos,
            enclave=owner.options.enclave,
            explicit_qos=owner.options.explicit_qos,
        )
        session = owner.session
        origin = zenoh.Locality.REMOTE if remote_only else zenoh.Locality.ANY
        try:
            if qos.transient_local:
                self._sub: Any = zext.declare_advanced_subscriber(
                    session,
                    self.key,
                    self._on_sample,
                    allowed_origin=origin,
                    history=zext.HistoryConfig(
                        detect_late_publishers=True, max_samples=max(1, qos.depth)
                    ),
                    recovery=(
                        zext.RecoveryConfig(periodic_queries=None, heartbeat=True)
                        if qos.reliable
                        else None
                    ),
                    subscriber_detection=True,
                )
            else:
                # A channel drained by our own thread rather than a callback: see _drain().
                self._sub = session.declare_subscriber(
                    self.key, zenoh.handlers.FifoChannel(_CHANNEL_CAPACITY),
                    allowed_origin=origin,
                )
                self.pullable = True
                drainer = threading.Thread(
                    target=self._drain, name=f"posekit-zenoh {topic}", daemon=True
                )
                owner.drainers[:] = [t for t in owner.drainers if t.is_alive()]
                owner.drainers.append(drainer)
                drainer.start()
            self._token = session.liveliness().declare_token(self.token_key)
        except Exception as exc:
            raise ZenohSessionError(f"cannot subscribe to {self.key}: {exc}") from exc
        self._mismatch_log = RateLimitedLog(warn_fn)
        self._stop_watching = owner.graph.watch_publishers(topic, self._on_publisher)

    def _on_publisher(self, info: TokenInfo) -> None:
        """A publisher announced on our topic: one warning if its samples cannot reach us."""
        if (info.ros_type, info.type_hash) == (self.ros_type, self.type_hash) or self._destroyed:
            return
        # two reasons (another definition, another type), each rate-limited on its own
        if info.ros_type == self.ros_type:
            reason = f"a publisher of another definition of {self.ros_type} on {self.topic}"
            why = (f"announces type hash {info.type_hash}, this subscription's is "
                   f"{self.type_hash}: its messages do not reach it")
        else:
            reason = f"a publisher of another type on {self.topic}"
            why = (f"publishes {info.ros_type}, this subscription takes {self.ros_type}: its "
                   "messages do not reach it")
        self._mismatch_log(reason, f"{info.node_fqn[:160]} {why[:300]}")

    def _drain(self) -> None:
        # Everything that arrived since the last wake-up is handled in one go (zenoh's
        # callback thread takes and drops the GIL around every sample), so a consumer on
        # another thread (the executor) wakes about once per batch rather than per sample:
        # about 25 % less CPU per message through the runtime (benchmarks/transport.py).
        recv, try_recv, handle = self._sub.recv, self._sub.try_recv, self._handle
        turn = self._turn
        while not self._destroyed:
            turn.acquire()  # free unless an executor holds the turn (pulled mode)
            if self._destroyed:
                return
            try:
                sample = recv()
            except Exception:  # the channel closed: undeclared or session closed
                return
            if self._pulled_by is not None and self._hand_over(sample):
                continue  # the executor takes it from here
            while sample is not None:
                try:
                    handle(sample)
                except Exception as exc:  # last line of defence: keep draining
                    self._drop("internal", "?", f"unexpected {type(exc).__name__}: {exc}")
                if self._destroyed:  # the callback destroyed its own subscription
                    return
                try:
                    sample = try_recv()
                except Exception:
                    return
            turn.release()

    def _hand_over(self, sample: zenoh.Sample) -> bool:
        """Drain thread, pulled mode: give ``sample`` and the turn to the executor.

        False when the subscription is no longer pulled (the drain thread handles it). A
        DELETE (a poke for an executor waiting in another channel) hands over no sample.
        """
        with self._mode:
            inbox = self._pulled_by
            if inbox is None:
                return False
            data = sample.kind == _PUT
            if self._primary:  # the executor reads the channel from now on
                self._executor_reads = True
            elif not data:
                self._turn.release()  # nothing to hand over: receive again
                return True
            if data:
                self._head, self._handed = sample, True
            waiter = self._waiter
            secondary = data and not self._primary and self._local_ok
        if waiter is not None:
            if secondary:
                waiter.note_secondary(self)
            waiter.set_from_receiver()  # this thread holds no lock: it may poke at once
        else:
            inbox.wake()
        return True

    # -- an executor reading the channel on its own thread (Executor._pulls_samples) -------
    def pull_into(self, inbox: Inbox) -> bool:
        """From the next sample on, ``inbox``'s executor handles them (:meth:`pull`).

        The first such subscription of an executor becomes the primary of its
        :class:`~posekit.transport.zenoh_wait.ChannelWaiter`: the executor waits in its
        channel.
        """
        with self._mode:
            if not self.pullable or self._destroyed or self._pulled_by is not None:
                return False
            waiter = inbox.adopt_waiter(self._owner, self._owner.make_waiter)
            self._pulled_by = inbox
            self._waiter = waiter if isinstance(waiter, ChannelWaiter) else None
            if self._waiter is not None and self._waiter.primary is None and self._local_ok:
                self._waiter.primary = self
                self._primary = True
            inbox.add_source(self)
            return True

    def release_pull(self, inbox: Inbox) -> None:
        """The drain thread handles the samples again (a handed-over one is handled here)."""
        with self._mode:
            if self._pulled_by is not inbox:
                return
            self._pulled_by = None
            inbox.remove_source(self)
            waiter = self._leave_waiter()
            if waiter is None:
                self._give_back_turn()
        if waiter is not None:
            waiter.set()  # the executor leaves the channel and gives the turn back (took)

    def _leave_waiter(self) -> ChannelWaiter | None:
        """Stop being a source of the waiter (caller holds ``_mode``).

        Returns the waiter when the executor is blocked in this channel right now: it gives
        the turn back itself when it leaves (:meth:`took`).
        """
        waiter, self._waiter = self._waiter, None
        if waiter is None:
            self._primary = False
            return None
        if self._primary and waiter.primary is self:
            waiter.primary = None
        self._primary = False
        waiter.forget(self)
        return waiter if waiter.inside_of is self else None

    def _give_back_turn(self, last: zenoh.Sample | None = None) -> None:
        """The executor's turn goes back to the drain thread (caller holds ``_mode``).

        What the executor took and did not handle yet (a handed-over sample, then ``last``)
        is handled first, so the drain thread's next sample comes after it.
        """
        if not (self._handed or self._executor_reads):
            return  # the drain thread holds the turn
        head, self._head = self._head, None
        self._handed = self._executor_reads = False
        for sample in (head, last):
            if sample is not None and sample.kind == _PUT:
                self._on_sample(sample)
        self._turn.release()

    def promote(self, replacing: PrimaryChannel) -> None:
        """Become the primary of our waiter instead of ``replacing`` (see ChannelWaiter).

        Called on the executor's thread while it is in no channel. ``replacing`` gives its
        turn back to its receive thread (what the executor took of it is handled first);
        ours takes the channel over with its next sample, as a first primary's does.
        """
        if not isinstance(replacing, WireSubscription):
            return
        old: WireSubscription = replacing
        first, second = sorted((self, old), key=id)  # one lock order for both
        with first._mode, second._mode:
            waiter = self._waiter
            if (waiter is None or waiter.primary is not old or waiter.inside_of is not None
                    or old._waiter is not waiter or not old._primary or self._primary
                    or not self._local_ok or self._destroyed or old._destroyed):
                return
            old._primary = False
            old._give_back_turn()
            self._primary = True
            waiter.primary = self

    def pending(self) -> bool:
        """Whether a sample waits for :meth:`pull` (the executor's look before it sleeps)."""
        return self._handed

    def pull(self, budget: int) -> int:
        """Handle the handed-over sample and up to ``budget`` in all from the channel."""
        if not (self._handed or self._executor_reads):
            return 0
        with self._mode:
            if not (self._handed or self._executor_reads) or self._destroyed:
                return 0
            head, self._head = self._head, None
            count = 0
            if head is not None:
                self._on_sample(head)
                count = 1
            try_recv, handle = self._sub.try_recv, self._handle
            # Large messages: stop once about _PULL_BYTES were taken, so that their callbacks
            # run while the payloads are still in the CPU's cache (64 queued 49 KB images
            # cost about 1.6x the CPU per message of 5, benchmarks/transport.py).
            taken = self._last_size * count
            while count < budget and taken < _PULL_BYTES:
                try:
                    sample = try_recv()
                except Exception:  # the channel closed: undeclared or session closed
                    sample = None
                if sample is None:  # empty
                    self._handed = False
                    if not self._executor_reads:  # the drain thread waits in recv() again
                        self._turn.release()
                    break
                try:  # _on_sample inlined: one Python frame less per sample
                    handle(sample)
                except Exception as exc:
                    self._internal_error(exc)
                count += 1
                taken += self._last_size
            # data from the primary's channel (a lone DELETE is a poke for a secondary)
            if self._primary and self._waiter is not None and (
                    count > 1 or (count and (head is None or head.kind == _PUT))):
                self._waiter.note_primary()
            return count

    # -- the primary's side of ChannelWaiter (PrimaryChannel) -----------------------------
    def enter_wait(self, waiter: ChannelWaiter) -> bool:
        """Whether ``waiter``'s executor may block in this channel now (see PrimaryChannel)."""
        with self._mode:
            if (self._waiter is not waiter or not self._primary or not self._executor_reads
                    or self._destroyed or self._handed):
                return False
            waiter.inside_of = self
            return True

    def channel_recv(self) -> zenoh.Sample:
        """Block in the channel (GIL released) until it holds a sample."""
        sample: zenoh.Sample = self._sub.recv()
        return sample

    def took(self, waiter: ChannelWaiter, sample: zenoh.Sample | None,
             closed: bool = False) -> None:
        """The executor left the channel of ``waiter`` with ``sample`` (None: nothing).

        ``closed``: the channel closed (the session did). The executor counts as inside
        the channel until here: a release meanwhile leaves the turn to this method, which
        then hands ``sample`` on before the receive thread reads again.
        """
        with self._mode:
            waiter.inside_of = None
            if closed:
                self.pullable = False  # the session closed: nothing to wait in any more
            if self._primary and self._executor_reads and not self._destroyed:
                if sample is not None:  # a poke too: pull ignores it as any DELETE
                    self._head, self._handed = sample, True
                return
            # released or destroyed while the executor waited in the channel
            self._give_back_turn(sample)
            undeclare, self._undeclare_on_leave = self._undeclare_on_leave, False
        if undeclare:
            _quiet(self._sub.undeclare)

    def poke(self) -> None:
        """Wake a receive blocked in the channel: a DELETE on our key for this session only.

        Every subscription ignores DELETE samples, and this one never reaches the network.
        """
        try:
            self._zenoh.delete(self.key, allowed_destination=zenoh.Locality.SESSION_LOCAL)
        except Exception:  # the session closed: the closed channel ends the receive anyway
            _log.debug("poke on %s failed", self.topic, exc_info=True)

    def _drop(self, reason: str, source: str, detail: str) -> None:
        self.dropped[reason] += 1
        try:
            self._warn(reason, f"from {source[:160]}: {detail[:300]}")
        except Exception:  # a broken logger must not kill zenoh's thread
            _log.exception("warning callback failed")

    def _on_sample(self, sample: zenoh.Sample) -> None:
        if self._destroyed:
            return
        try:
            self._handle(sample)
        except Exception as exc:  # last line of defence: never raise into zenoh
            self._internal_error(exc)

    def _internal_error(self, exc: Exception) -> None:
        """A sample's handling raised where it never should: dropped, with the reason."""
        self._drop("internal", "?", f"unexpected {type(exc).__name__}: {exc}")

    def _drop_put(self, sample: zenoh.Sample, reason: str, source: str, detail: str) -> None:
        """:meth:`_drop` for a PUT; a DELETE (no attachment, no payload) is ignored silently."""
        if sample.kind == _PUT:
            self._drop(reason, source, detail)

    def _handle(self, sample: zenoh.Sample) -> None:
        # Hot path (one call per sample): the checks a valid sample passes come first and
        # cost one comparison each; the sample kind is looked at only when one fails (a
        # DELETE has no attachment and no payload, and is ignored without a word).
        raw_att = sample.attachment
        if raw_att is None:
            self._drop_put(sample, "attachment", self.key,
                           "no attachment (rmw_zenoh requires one)")
            return
        try:
            att = decode_attachment(raw_att.to_bytes())
        except WireFormatError as exc:
            self._drop_put(sample, "attachment", self.key, str(exc))
            return
        try:
            payload = sample.payload.to_bytes()
            self._last_size = len(payload)
            msg = self._decode(payload)
        except CdrError as exc:
            self._drop_put(sample, "cdr", att.gid.hex(), str(exc))
            return
        seq, gid = att[0], att[2]
        last_seq = self._last_seq
        last = last_seq.get(gid)
        if last is None or seq > last:
            if last is not None and seq > last + 1:
                self.lost[gid] += seq - last - 1
            last_seq[gid] = seq
            if last is None and len(last_seq) > MAX_TRACKED_PUBLISHERS:
                gone, _ = last_seq.popitem(last=False)  # the longest silent one
                self.lost.pop(gone, None)
        if last is not None and gid != self._recent_gid:  # most recent last (LRU order)
            last_seq.move_to_end(gid)
        self._recent_gid = gid
        self.received += 1
        if self._destroyed:
            return
        try:
            if self._message_only:
                self._callback(msg)
            else:
                self._callback(msg, att)
        except Exception as exc:
            self.dropped["callback"] += 1
            _log.exception("subscription callback on %s raised: %s", self.topic, exc)

    def destroy(self) -> None:
        """Leave the graph; the callback is not called afterwards."""
        if self._destroyed:
            return
        self._destroyed = True
        _quiet(self._token.undeclare)
        self._stop_watching()
        with self._mode:
            inbox, self._pulled_by = self._pulled_by, None
            if inbox is not None:
                inbox.remove_source(self)
            waiter = self._leave_waiter()
            if waiter is None:
                self._give_back_turn()  # the drain thread sees that it is over
            else:
                # The executor waits in the channel: poke it out first (an undeclared
                # subscriber's channel receives nothing more); it undeclares on leaving.
                self._undeclare_on_leave = True
        if waiter is None:
            _quiet(self._sub.undeclare)
        else:
            waiter.set()


def _service_token(
    owner: ZenohSession, node: NodeEntity, entity_id: int, kind: EntityKind, service: str,
    srv_name: str, qos: WireQoS,
) -> str:
    return endpoint_token(
        owner.domain_id, owner.zid, node.node_id, entity_id, kind, node.namespace, node.name,
        service, srv_name, qos, enclave=owner.options.enclave,
        explicit_qos=owner.options.explicit_qos,
    )


#: How long a client's query may wait for its reply (rmw_zenoh: no limit; zenoh needs one).
_QUERY_TIMEOUT_S = 7 * 24 * 3600.0


class WireServiceServer:
    """A service server: a *complete* queryable on the service key; announced by ``SS``.

    As rmw_zenoh: each query carries the request CDR and an attachment with the client's
    sequence number and GID; the reply carries the response CDR on the service key and an
    attachment with that same sequence number and client GID, and this side's time.
    """

    def __init__(
        self,
        owner: ZenohSession,
        node: NodeEntity,
        service: str,
        srv_type: type[Any],
        qos: WireQoS,
        on_request: Callable[[Any, Callable[[Any], None], Attachment], None],
        warn: Callable[[str], object] | None,
    ) -> None:
        self.service = service
        self.srv_type = srv_type
        self.srv_name: str = srv_type.__srvtype__
        self.qos = qos
        self.key = data_key(owner.domain_id, service, self.srv_name)
        self.entity_id = owner.next_entity_id()
        self.token_key = _service_token(
            owner, node, self.entity_id, EntityKind.SERVICE, service, self.srv_name, qos
        )
        self._on_request = on_request
        self._warn = warn or _log.warning
        self._warned: set[str] = set()
        self._encode = (
            encode_attachment_legacy if owner.options.legacy_attachment else encode_attachment
        )
        #: Dropped queries by reason ("attachment", "cdr", "callback").
        self.dropped: collections.Counter[str] = collections.Counter()
        self._destroyed = False
        session = owner.session
        try:
            # _on_query only decodes and queues: run it on zenoh's own thread, without the
            # hop through a Python thread of its own that zenoh-python's default adds
            self._queryable = session.declare_queryable(
                self.key, zenoh.handlers.Callback(on_receive_thread(self._on_query),
                                                  indirect=False),
                complete=True,
            )
            self._token = session.liveliness().declare_token(self.token_key)
        except Exception as exc:
            raise ZenohSessionError(f"cannot declare a service on {self.key}: {exc}") from exc

    def _drop(self, reason: str, detail: str) -> None:
        self.dropped[reason] += 1
        if reason in self._warned:
            return
        self._warned.add(reason)
        try:
            self._warn(f"dropping request on {self.service}: {detail}")
        except Exception:
            _log.exception("warning callback failed")

    def _on_query(self, query: zenoh.Query) -> None:
        if self._destroyed:
            return
        try:
            raw = query.attachment
            if raw is None:
                self._drop("attachment", "no attachment (rmw_zenoh requires one)")
                return
            try:
                att = decode_attachment(raw.to_bytes())
            except WireFormatError as exc:
                self._drop("attachment", str(exc))
                return
            payload = query.payload
            try:
                request = from_cdr(
                    payload.to_bytes() if payload is not None else b"", self.srv_type.Request
                )
            except CdrError as exc:
                self._drop("cdr", str(exc))
                return
            key, encode = self.key, self._encode
            answered = threading.Lock()

            def respond(response: Any) -> None:
                if self._destroyed or not answered.acquire(blocking=False):
                    return
                try:
                    query.reply(
                        key,
                        to_cdr(response, self.srv_type.Response.__msgtype__),
                        attachment=encode(att.sequence_number, time.time_ns(), att.gid),
                    )
                finally:
                    _quiet(query.drop)  # finalizes the query: the client sees the end

            self._on_request(request, respond, att)
        except Exception as exc:  # never raise into zenoh
            self._drop("callback", f"unexpected {type(exc).__name__}: {exc}")

    def destroy(self) -> None:
        """Leave the graph; no further requests are delivered."""
        if self._destroyed:
            return
        self._destroyed = True
        _quiet(self._token.undeclare)
        _quiet(self._queryable.undeclare)


class WireServiceClient:
    """A service client: each request is a zenoh query; announced by ``SC``.

    Target ALL_COMPLETE, consolidation LATEST, as rmw_zenoh sends it.
    """

    def __init__(
        self,
        owner: ZenohSession,
        node: NodeEntity,
        service: str,
        srv_type: type[Any],
        qos: WireQoS,
        warn: Callable[[str], object] | None,
    ) -> None:
        self.service = service
        self.srv_type = srv_type
        self.srv_name: str = srv_type.__srvtype__
        self.type_hash = type_hash(self.srv_name)
        self.qos = qos
        self.key = data_key(owner.domain_id, service, self.srv_name)
        self.entity_id = owner.next_entity_id()
        self.token_key = _service_token(
            owner, node, self.entity_id, EntityKind.CLIENT, service, self.srv_name, qos
        )
        self.gid = entity_gid(self.token_key)
        self._session = owner.session
        self._warn = warn or _log.warning
        self._encode = (
            encode_attachment_legacy if owner.options.legacy_attachment else encode_attachment
        )
        self._seq = itertools.count(1)
        self._destroyed = False
        try:
            self._token = owner.session.liveliness().declare_token(self.token_key)
        except Exception as exc:
            raise ZenohSessionError(f"cannot declare a client on {self.key}: {exc}") from exc

    def send_request(self, request: Any, on_response: Callable[[Any], None],
                     sequence_number: int | None = None) -> int:
        """Send ``request``; returns the request's sequence number.

        ``sequence_number`` numbers the request in its attachment (the caller's own numbering,
        unique per client); None takes this client's next number. ``on_response(response)``
        is called (on a zenoh thread) for the first matching reply.
        """
        if self._destroyed:
            raise ZenohSessionError(f"client of {self.service} was destroyed")
        payload = to_cdr(request, self.srv_type.Request.__msgtype__)
        seq = next(self._seq) if sequence_number is None else sequence_number
        done = threading.Lock()

        def on_reply(reply: zenoh.Reply) -> None:
            if self._destroyed:
                return
            try:
                sample = reply.ok
                if sample is None:
                    self._warn(f"service {self.service} answered with an error: {reply.err}")
                    return
                raw = sample.attachment
                att = decode_attachment(raw.to_bytes()) if raw is not None else None
                if att is not None and att.sequence_number != seq:
                    return  # not the answer to this request
                response = from_cdr(sample.payload.to_bytes(), self.srv_type.Response)
            except (WireFormatError, CdrError) as exc:
                self._warn(f"dropping a reply from {self.service}: {exc}")
                return
            if done.acquire(blocking=False):
                try:
                    on_response(response)
                except Exception:
                    _log.exception("response callback of %s raised", self.service)

        self._session.get(
            self.key,
            # on_reply runs on zenoh's own thread: zenoh-python's default would start a
            # Python thread for every query (about 0.3 ms of each call on this machine)
            zenoh.handlers.Callback(on_receive_thread(on_reply), indirect=False),
            target=zenoh.QueryTarget.ALL_COMPLETE,
            consolidation=zenoh.ConsolidationMode.LATEST,
            payload=payload,
            attachment=self._encode(seq, time.time_ns(), self.gid),
            timeout=_QUERY_TIMEOUT_S,
        )
        return seq

    def destroy(self) -> None:
        """Leave the graph; replies still in flight are ignored."""
        if self._destroyed:
            return
        self._destroyed = True
        _quiet(self._token.undeclare)


class ZenohGraph:
    """Live view of the ROS graph of one domain from ``@ros2_lv`` liveliness tokens."""

    def __init__(self, session: zenoh.Session, domain_id: int) -> None:
        self.cache = GraphCache()
        self._cond = threading.Condition()
        #: topic -> callbacks told of each publisher announced on it (watch_publishers)
        self._publisher_watchers: dict[str, list[Callable[[TokenInfo], None]]] = {}
        self._sub = session.liveliness().declare_subscriber(
            f"{LIVELINESS_PREFIX}/{int(domain_id)}/**", self._on_token, history=True
        )

    def _on_token(self, sample: zenoh.Sample) -> None:
        key = str(sample.key_expr)
        if sample.kind == zenoh.SampleKind.PUT:
            self._add(key)
            return
        with self._cond:
            self.cache.remove(key)
            self._cond.notify_all()

    def _add(self, keyexpr: str) -> None:
        with self._cond:
            info = self.cache.add(keyexpr)
            self._cond.notify_all()
            watchers = (
                list(self._publisher_watchers.get(info.topic or "", ()))
                if info is not None and info.kind == EntityKind.PUBLISHER else []
            )
        for watcher in watchers:  # outside the lock: a watcher may log
            assert info is not None
            watcher(info)

    def add_remote(self, keyexpr: str) -> None:
        """Record a token learnt from a liveliness query."""
        self._add(keyexpr)

    def add_local(self, keyexpr: str) -> None:
        """Record one of this session's own tokens now (liveliness echoes it later)."""
        self._add(keyexpr)

    def watch_publishers(
        self, topic: str, callback: Callable[[TokenInfo], None]
    ) -> Callable[[], None]:
        """Call ``callback(info)`` for each publisher announced on ``topic``.

        Those known now first, then each new token (on zenoh's thread; a token seen again is
        reported again). Returns the function that stops the calls.
        """
        with self._cond:
            self._publisher_watchers.setdefault(topic, []).append(callback)
            known = self.cache.endpoints(topic, EntityKind.PUBLISHER)
        for info in known:
            callback(info)

        def stop() -> None:
            with self._cond:
                watchers = self._publisher_watchers.get(topic, [])
                if callback in watchers:
                    watchers.remove(callback)
                if not watchers:
                    self._publisher_watchers.pop(topic, None)

        return stop

    def remove_local(self, keyexpr: str) -> None:
        """Forget one of this session's own tokens now."""
        with self._cond:
            self.cache.remove(keyexpr)
            self._cond.notify_all()

    def wait_until(self, predicate: Callable[[GraphCache], bool], timeout: float) -> bool:
        """Block until ``predicate(cache)`` holds (True) or ``timeout`` seconds pass (False)."""
        with self._cond:
            return self._cond.wait_for(lambda: predicate(self.cache), timeout)

    def entities(self) -> list[TokenInfo]:
        """A consistent snapshot of every announced entity (duplicates kept)."""
        with self._cond:
            return self.cache.entities()

    def node_names(self) -> list[str]:
        """Fully qualified node names, sorted."""
        with self._cond:
            return self.cache.node_names()

    def topic_names_and_types(self) -> list[tuple[str, list[str]]]:
        """Topics with their types, sorted."""
        with self._cond:
            return self.cache.topic_names_and_types()

    def publishers(self, topic: str) -> list[TokenInfo]:
        """Publishers announced on ``topic``."""
        with self._cond:
            return self.cache.endpoints(topic, EntityKind.PUBLISHER)

    def subscriptions(self, topic: str) -> list[TokenInfo]:
        """Subscriptions announced on ``topic``."""
        with self._cond:
            return self.cache.endpoints(topic, EntityKind.SUBSCRIPTION)

    def services(self, service: str) -> list[TokenInfo]:
        """Servers announced for ``service``."""
        with self._cond:
            return self.cache.endpoints(service, EntityKind.SERVICE)

    def clients(self, service: str) -> list[TokenInfo]:
        """Clients announced for ``service``."""
        with self._cond:
            return self.cache.endpoints(service, EntityKind.CLIENT)

    def service_names_and_types(self) -> list[tuple[str, list[str]]]:
        """Services (with a server or a client) and their types, sorted."""
        with self._cond:
            return self.cache.service_names_and_types()

    def names_and_types_by_node(
        self, node_name: str, namespace: str, kind: EntityKind
    ) -> list[tuple[str, list[str]]]:
        """Names one node announced endpoints of ``kind`` on, with types, sorted."""
        with self._cond:
            return self.cache.names_and_types_by_node(node_name, namespace, (kind,))

    def close(self) -> None:
        """Stop following the graph."""
        _quiet(self._sub.undeclare)
