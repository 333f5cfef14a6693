"""The runtime's :class:`~posekit.runtime.transport.Transport` over Zenoh, rmw_zenoh-compatible.

Select it with ``POSEKIT_TRANSPORT=zenoh``, ``init(transport="zenoh")`` or
``Node(..., transport="zenoh")``. One instance (one Zenoh session) per context; nodes are
announced on the ROS graph with their first endpoint, or as soon as the runtime calls
:meth:`ZenohTransport.declare_node` (withdrawn with :meth:`ZenohTransport.undeclare_node`
or when their last endpoint goes).

QoS: reliability, durability and depth are mapped as rmw_zenoh maps them
(TRANSIENT_LOCAL through zenoh-ext's advanced publisher cache / subscriber history).
Like rmw_zenoh, there is no QoS incompatibility over Zenoh: a BEST_EFFORT publisher still
reaches a RELIABLE subscription (logged once as a warning, since DDS would refuse it).
Messages published in this process reach this process's subscriptions through Zenoh too
(serialized, so subscribers never share objects with publishers).

Services are rmw_zenoh's: a server is a complete queryable on
``<domain>/<service>/<pkg>::srv::dds_::<Srv>_/<RIHS01 hash>`` announced by an ``SS`` token, a
request a query carrying the request CDR and the client's sequence number and GID in the
attachment (``SC`` token), the reply the response CDR with the same sequence number and GID.

Environment: ``POSEKIT_ZENOH_ROUTER`` (router endpoint, default ``tcp/127.0.0.1:7447``),
``POSEKIT_ZENOH_ATTACHMENT=legacy`` (77-byte attachment for Jazzy rmw_zenoh <= 0.2.3), plus
``ROS_DOMAIN_ID``, ``ZENOH_SESSION_CONFIG_URI`` and ``ZENOH_CONFIG_OVERRIDE``.
"""

from __future__ import annotations

import os
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from posekit.runtime.inbox import Inbox
from posekit.runtime.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from posekit.runtime.transport import (
    EndpointInfo,
    MessageSink,
    PublisherEndpoint,
    RequestHeader,
    RequestSink,
    ResponseSink,
    ServiceClientEndpoint,
    ServiceInfo,
    ServiceServerEndpoint,
    SourcedMessageSink,
    SubscriptionEndpoint,
    Transport,
)
from posekit.transport.zenoh_session import (
    DEFAULT_ROUTER_ENDPOINT,
    NodeEntity,
    SessionOptions,
    WirePublisher,
    WireServiceClient,
    WireServiceServer,
    WireSubscription,
    ZenohGraph,
    ZenohSession,
    open_session,
)
from posekit.transport.zenoh_wire import (
    DEFAULT_WIRE_QOS,
    Attachment,
    EntityKind,
    TokenInfo,
    WireQoS,
)

__all__ = ["ENV_ATTACHMENT", "ENV_ROUTER", "ZenohTransport", "options_from_env", "wire_qos"]

ENV_ROUTER = "POSEKIT_ZENOH_ROUTER"
ENV_ATTACHMENT = "POSEKIT_ZENOH_ATTACHMENT"


def wire_qos(qos: QoSProfile) -> WireQoS:
    """Map an rclpy-style profile to rmw_zenoh's QoS (rmw enum values are rclpy's)."""
    lifespan = qos.lifespan_ns
    return WireQoS(
        reliability=2 if qos.resolved_reliability == ReliabilityPolicy.BEST_EFFORT else 1,
        durability=1 if qos.resolved_durability == DurabilityPolicy.TRANSIENT_LOCAL else 2,
        history=2 if qos.history == HistoryPolicy.KEEP_ALL else 1,
        depth=qos.depth if qos.depth > 0 else 42,
        lifespan=DEFAULT_WIRE_QOS.lifespan if lifespan is None
        else divmod(lifespan, 1_000_000_000),
    )


def options_from_env() -> SessionOptions:
    """Session options from ``POSEKIT_ZENOH_ROUTER`` / ``POSEKIT_ZENOH_ATTACHMENT``."""
    attachment = os.environ.get(ENV_ATTACHMENT, "compact").strip().lower()
    if attachment not in ("compact", "legacy"):
        raise ValueError(f"{ENV_ATTACHMENT}={attachment!r}: expected 'compact' or 'legacy'")
    return SessionOptions(
        router_endpoint=os.environ.get(ENV_ROUTER, "").strip() or DEFAULT_ROUTER_ENDPOINT,
        legacy_attachment=attachment == "legacy",
    )


def _type_name(info: EndpointInfo) -> str:
    name = getattr(info.msg_type, "__msgtype__", None)
    if not isinstance(name, str):
        raise TypeError(
            f"the zenoh transport carries ROS messages only; {info.msg_type!r} on "
            f"'{info.topic}' has no __msgtype__"
        )
    return name


class _Publisher(PublisherEndpoint):
    def __init__(self, owner: ZenohTransport, info: EndpointInfo, wire: WirePublisher) -> None:
        self._owner = owner
        self.info = info
        self.wire = wire
        self._type = info.msg_type
        self.alive = True

    def publish(self, msg: Any) -> None:
        if not self.alive:
            raise RuntimeError(f"publisher on '{self.info.topic}' has been destroyed")
        if type(msg) is not self._type and not isinstance(msg, self._type):
            raise TypeError(
                f"publisher on '{self.info.topic}' expects {self._type.__name__}, "
                f"got {type(msg).__name__}"
            )
        self.wire.publish(msg)

    def destroy(self) -> None:
        if self.alive:
            self.alive = False
            self._owner._forget(self.wire, self.info)

    @property
    def subscription_count(self) -> int:
        return self._owner._count(self.info, EntityKind.SUBSCRIPTION)


class _Subscription(SubscriptionEndpoint):
    def __init__(self, owner: ZenohTransport, info: EndpointInfo) -> None:
        self._owner = owner
        self.info = info
        self.wire: WireSubscription | None = None
        self.alive = True

    def destroy(self) -> None:
        if self.alive:
            self.alive = False
            if self.wire is not None:
                self._owner._forget(self.wire, self.info)

    def pull_into(self, inbox: Inbox) -> bool:
        return self.alive and self.wire is not None and self.wire.pull_into(inbox)

    def release_pull(self, inbox: Inbox) -> None:
        if self.wire is not None:
            self.wire.release_pull(inbox)

    @property
    def publisher_count(self) -> int:
        return self._owner._count(self.info, EntityKind.PUBLISHER)


class _Server(ServiceServerEndpoint):
    def __init__(self, owner: ZenohTransport, info: ServiceInfo) -> None:
        self._owner = owner
        self.info = info
        self.wire: WireServiceServer | None = None

    def destroy(self) -> None:
        if self.wire is not None:
            wire, self.wire = self.wire, None
            self._owner._forget(wire, self.info)


class _Client(ServiceClientEndpoint):
    def __init__(self, owner: ZenohTransport, info: ServiceInfo, wire: WireServiceClient) -> None:
        self._owner = owner
        self.info = info
        self.wire: WireServiceClient | None = wire
        self._gid = wire.gid
        self._warned = False

    @property
    def gid(self) -> bytes:
        """rmw_zenoh's client GID (from the client's liveliness token), sent with requests."""
        return self._gid

    def send_request(self, request: Any, on_response: ResponseSink,
                     header: RequestHeader | None = None) -> None:
        """Query the service; the attachment carries this client's GID and the number.

        rmw_zenoh's attachment has room for the client's own GID only, so ``header``'s
        ``sequence_number`` is sent and its ``client_gid`` must be :attr:`gid`.
        """
        if self.wire is None:
            raise RuntimeError(f"client of '{self.info.service}' has been destroyed")
        if header is not None and header.client_gid != self._gid:
            raise ValueError("a zenoh client sends its own GID with each request")
        self.wire.send_request(request, on_response,
                               None if header is None else header.sequence_number)

    @property
    def server_count(self) -> int:
        """Servers of this service *with this client's type and type hash*.

        A request only reaches those (the hash is part of the key); others are reported once.
        """
        wire = self.wire
        if wire is None:
            return 0
        servers = self._owner._graph.services(self.info.service)
        matching = [t for t in servers if t.ros_type == wire.srv_name and (
            t.type_hash == wire.type_hash)]
        if len(matching) < len(servers) and not self._warned:
            self._warned = True
            other = next(t for t in servers if t not in matching)
            self.info.logger.warning(
                f"a server of '{self.info.service}' on node '{other.node_fqn}' offers "
                f"{other.ros_type} ({other.type_hash}), not {wire.srv_name} ({wire.type_hash}): "
                "requests do not reach it"
            )
        return len(matching)

    def destroy(self) -> None:
        if self.wire is not None:
            wire, self.wire = self.wire, None
            self._owner._forget(wire, self.info)


@dataclass(slots=True)
class _NodeRef:
    node: NodeEntity
    refs: int = 0


class ZenohTransport(Transport):
    """Nodes' endpoints as rmw_zenoh entities on one Zenoh session."""

    name = "zenoh"
    crosses_processes = True
    supports_services = True

    def __init__(
        self, options: SessionOptions | None = None, *, session: ZenohSession | None = None
    ) -> None:
        self.session = (
            session if session is not None else open_session(options or options_from_env())
        )
        self._lock = threading.Lock()
        # (namespace, name) -> node and its references (endpoints + declare_node calls)
        self._nodes: dict[tuple[str, str], _NodeRef] = {}
        self._graph = self.session.graph
        self._warned_qos: set[tuple[str, str]] = set()

    # -- nodes -------------------------------------------------------------------------
    def declare_node(self, name: str, namespace: str = "/") -> NodeEntity:
        """Announce a node on the graph (the ``NN`` token), e.g. from ``Node.__init__``.

        Reference counted together with the node's endpoints: the token is withdrawn when
        :meth:`undeclare_node` has balanced every call and the node's last endpoint is
        destroyed. Without these calls a node is announced by its first endpoint.
        """
        return self._acquire_node(namespace, name)

    def undeclare_node(self, name: str, namespace: str = "/") -> None:
        """Balance one :meth:`declare_node` call (``Node.destroy_node``); unknown: no-op."""
        self._release_node(namespace, name)

    def _acquire_node(self, namespace: str, name: str) -> NodeEntity:
        key = (namespace or "/", name)
        with self._lock:
            entry = self._nodes.get(key)
            if entry is None:
                node = self.session.create_node(name, key[0])
                self._graph.add_local(node.token_key)  # visible locally at once
                entry = self._nodes[key] = _NodeRef(node)
            entry.refs += 1
            return entry.node

    def _release_node(self, namespace: str, name: str) -> None:
        key = (namespace or "/", name)
        with self._lock:
            entry = self._nodes.get(key)
            if entry is None:
                return
            entry.refs -= 1
            if entry.refs > 0:
                return
            del self._nodes[key]
        node = entry.node
        self.session.destroy_node(node)
        self._graph.remove_local(node.token_key)

    # -- endpoints ---------------------------------------------------------------------
    def advertise(self, info: EndpointInfo) -> PublisherEndpoint:
        """A Zenoh publisher on ``info``'s topic (see :meth:`Transport.advertise`)."""
        type_name = _type_name(info)
        node = self._acquire_node(info.node_namespace, info.node_name)
        try:
            wire = self.session.create_publisher(
                node, info.topic, type_name, wire_qos(info.qos), remote_only=info.remote_only
            )
        except BaseException:
            self._release_node(info.node_namespace, info.node_name)
            raise
        self._graph.add_local(wire.token_key)
        self._check_qos(info, wire_qos(info.qos), EntityKind.PUBLISHER)
        return _Publisher(self, info, wire)

    def subscribe(self, info: EndpointInfo, sink: MessageSink) -> SubscriptionEndpoint:
        """A Zenoh subscriber on ``info``'s topic calling ``sink(msg)``."""
        if not getattr(getattr(sink, "__self__", None), "wants_message_info", False):
            # The hot path: the sink is called with the message alone, straight from the
            # receive thread (a destroyed endpoint's wire subscription stops calling it).
            return self._subscribe(info, lambda _endpoint: sink, message_only=True)

        def deliverer(endpoint: _Subscription) -> Callable[[Any, Attachment], None]:
            def deliver(msg: Any, att: Attachment) -> None:
                if endpoint.alive:  # rclpy's MessageInfo from rmw_zenoh's attachment
                    sink(msg, {"source_timestamp": att.source_timestamp,  # type: ignore[call-arg]
                               "received_timestamp": time.time_ns(),
                               "publication_sequence_number": att.sequence_number,
                               "reception_sequence_number": 0})

            return deliver

        return self._subscribe(info, deliverer)

    def subscribe_with_source(
        self, info: EndpointInfo, sink: SourcedMessageSink
    ) -> SubscriptionEndpoint:
        """:meth:`subscribe` whose sink also gets the sending publisher's GID (16 bytes)."""

        def deliverer(endpoint: _Subscription) -> Callable[[Any, Attachment], None]:
            def deliver(msg: Any, att: Attachment) -> None:
                if endpoint.alive:
                    sink(msg, att.gid)

            return deliver

        return self._subscribe(info, deliverer)

    def _subscribe(
        self,
        info: EndpointInfo,
        deliverer: Callable[[_Subscription], Callable[[Any, Attachment], None]]
        | Callable[[_Subscription], Callable[[Any], None]],
        *,
        message_only: bool = False,
    ) -> SubscriptionEndpoint:
        _type_name(info)
        node = self._acquire_node(info.node_namespace, info.node_name)
        endpoint = _Subscription(self, info)
        deliver = deliverer(endpoint)

        qos = wire_qos(info.qos)
        self._check_qos(info, qos, EntityKind.SUBSCRIPTION)
        try:
            endpoint.wire = self.session.create_subscription(
                node, info.topic, info.msg_type, qos, deliver, warn=info.logger.warning,
                remote_only=info.remote_only, message_only=message_only,
            )
        except BaseException:
            self._release_node(info.node_namespace, info.node_name)
            raise
        self._graph.add_local(endpoint.wire.token_key)
        return endpoint

    def _check_qos(self, info: EndpointInfo, qos: WireQoS, kind: EntityKind) -> None:
        # DDS would refuse BEST_EFFORT -> RELIABLE and VOLATILE -> TRANSIENT_LOCAL pairs;
        # rmw_zenoh delivers anyway. Say so once per topic, do not block delivery.
        others = self._endpoints(
            info.topic,
            EntityKind.SUBSCRIPTION if kind is EntityKind.PUBLISHER else EntityKind.PUBLISHER,
        )
        for other in others:
            if other.qos is None:
                continue
            pub_q, sub_q = (qos, other.qos) if kind is EntityKind.PUBLISHER else (other.qos, qos)
            if (not pub_q.reliable and sub_q.reliable) or (
                not pub_q.transient_local and sub_q.transient_local
            ):
                tag = (info.topic, "qos")
                if tag not in self._warned_qos:
                    self._warned_qos.add(tag)
                    info.logger.warning(
                        f"QoS on '{info.topic}' would be incompatible under DDS "
                        "(offered weaker reliability or durability than requested); "
                        "over Zenoh, as with rmw_zenoh, messages are delivered anyway"
                    )
                return

    # -- services ----------------------------------------------------------------------
    def create_service_server(self, info: ServiceInfo, sink: RequestSink) -> ServiceServerEndpoint:
        """A Zenoh queryable serving ``info``'s service (rmw_zenoh's service server)."""
        info.require_ros_service("zenoh")
        node = self._acquire_node(info.node_namespace, info.node_name)
        endpoint = _Server(self, info)
        try:
            endpoint.wire = self.session.create_service_server(
                node, info.service, info.srv_type, wire_qos(info.qos),
                lambda request, respond, att: sink(
                    request, respond, RequestHeader(att.gid, att.sequence_number)),
                warn=info.logger.warning,
            )
        except BaseException:
            self._release_node(info.node_namespace, info.node_name)
            raise
        self._graph.add_local(endpoint.wire.token_key)
        return endpoint

    def create_service_client(self, info: ServiceInfo) -> ServiceClientEndpoint:
        """A client of ``info``'s service; each request is a Zenoh query."""
        info.require_ros_service("zenoh")
        node = self._acquire_node(info.node_namespace, info.node_name)
        try:
            wire = self.session.create_service_client(
                node, info.service, info.srv_type, wire_qos(info.qos), warn=info.logger.warning
            )
        except BaseException:
            self._release_node(info.node_namespace, info.node_name)
            raise
        self._graph.add_local(wire.token_key)
        return _Client(self, info, wire)

    def get_service_names_and_types(self) -> list[tuple[str, list[str]]]:
        """Every service of the graph, with its type names."""
        return self._graph.service_names_and_types()

    def count_services(self, service: str) -> int:
        """Number of servers of ``service`` on the graph."""
        return len(self._graph.services(service))

    def count_clients(self, service: str) -> int:
        """Number of clients of ``service`` on the graph."""
        return len(self._graph.clients(service))

    def get_service_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The services a node serves, from the graph."""
        return self._graph.names_and_types_by_node(node_name, node_namespace, EntityKind.SERVICE)

    def get_client_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The services a node is a client of, from the graph."""
        return self._graph.names_and_types_by_node(node_name, node_namespace, EntityKind.CLIENT)

    def get_publisher_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The topics a node publishes, from the graph."""
        return self._graph.names_and_types_by_node(
            node_name, node_namespace, EntityKind.PUBLISHER)

    def get_subscriber_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The topics a node subscribes to, from the graph."""
        return self._graph.names_and_types_by_node(
            node_name, node_namespace, EntityKind.SUBSCRIPTION)

    def _forget(
        self,
        wire: WirePublisher | WireSubscription | WireServiceServer | WireServiceClient,
        info: EndpointInfo | ServiceInfo,
    ) -> None:
        wire.destroy()
        self._graph.remove_local(wire.token_key)
        self._release_node(info.node_namespace, info.node_name)

    def _count(self, info: EndpointInfo, kind: EntityKind) -> int:
        """Matched endpoints of ``kind`` on ``info``'s topic.

        Other sessions' only when ``info.remote_only``.
        """
        found = self._endpoints(info.topic, kind)
        if info.remote_only:
            own = self.session.zid
            return sum(1 for e in found if e.zid != own)
        return len(found)

    def _endpoints(self, topic: str, kind: EntityKind) -> list[TokenInfo]:
        if kind is EntityKind.PUBLISHER:
            return self._graph.publishers(topic)
        return self._graph.subscriptions(topic)

    # -- graph -------------------------------------------------------------------------
    def get_topic_names_and_types(self) -> list[tuple[str, list[str]]]:
        """Every topic of the graph, with its type names."""
        return self._graph.topic_names_and_types()

    def count_publishers(self, topic: str) -> int:
        """Number of publishers on ``topic`` on the graph."""
        return len(self._graph.publishers(topic))

    def count_subscribers(self, topic: str) -> int:
        """Number of subscriptions on ``topic`` on the graph."""
        return len(self._graph.subscriptions(topic))

    def get_node_names(self) -> list[str]:
        """Fully qualified names of every node on the graph (this and other processes), sorted.

        Duplicates are kept (``ros2 node list`` warns about them).
        """
        return sorted(t.node_fqn for t in self._graph.entities() if t.kind is EntityKind.NODE)

    def get_node_names_and_namespaces_with_enclaves(self) -> list[tuple[str, str, str]]:
        """``(name, namespace, enclave)`` of every node on the graph, sorted."""
        return sorted((t.node_name, t.namespace, t.enclave or "/")
                      for t in self._graph.entities() if t.kind is EntityKind.NODE)

    def graph_entities(self) -> list[TokenInfo]:
        """Every entity announced on the graph (nodes and endpoints, duplicates kept)."""
        return self._graph.entities()

    def graph_description(self) -> str:
        """The Zenoh domain and router this transport's graph lives on."""
        s = self.session
        hosted = " (hosted by this tool: no router was running)" if s.hosts_router else ""
        return f"zenoh domain {s.domain_id} via router {s.options.router_endpoint}{hosted}"

    @property
    def graph(self) -> ZenohGraph:
        """The live ROS graph of this domain (posekit's and rmw_zenoh's tokens)."""
        return self._graph

    def sync_graph(self, timeout: float = 2.0) -> int:
        """Complete the graph with a liveliness query (see :meth:`ZenohSession.sync_graph`)."""
        return self.session.sync_graph(timeout)

    def get_publishers_info_by_topic(self, topic: str) -> list[TokenInfo]:
        """Every publisher announced on ``topic`` (node, type, hash, QoS, GID source)."""
        return self._graph.publishers(topic)

    def publisher_qos_profiles(self, topic: str) -> list[QoSProfile]:
        """The QoS each publisher on ``topic`` announced on the graph."""
        return [e.qos.to_profile() for e in self.get_publishers_info_by_topic(topic)
                if e.qos is not None]

    def get_subscriptions_info_by_topic(self, topic: str) -> list[TokenInfo]:
        """Every subscription announced on ``topic``."""
        return self._graph.subscriptions(topic)

    def close(self) -> None:
        """Close the Zenoh session."""
        self.session.close()
