"""The runtime's :class:`~posekit.runtime.transport.Transport` over Zenoh, rmw_zenoh-compatible.

Select it with ``POSEKIT_TRANSPORT=zenoh``, ``init(transport="zenoh")`` or
``Node(..., transport="zenoh")``. One instance (one Zenoh session) per context; nodes are
announced on the ROS graph with their first endpoint (or :meth:`ZenohTransport.declare_node`).

QoS: reliability, durability and depth are mapped as rmw_zenoh maps them
(TRANSIENT_LOCAL through zenoh-ext's advanced publisher cache / subscriber history).
Like rmw_zenoh, there is no QoS incompatibility over Zenoh: a BEST_EFFORT publisher still
reaches a RELIABLE subscription (logged once as a warning, since DDS would refuse it).
Messages published in this process reach this process's subscriptions through Zenoh too
(serialized, so subscribers never share objects with publishers).

Environment: ``POSEKIT_ZENOH_ROUTER`` (router endpoint, default ``tcp/127.0.0.1:7447``),
``POSEKIT_ZENOH_ATTACHMENT=legacy`` (77-byte attachment for Jazzy rmw_zenoh <= 0.2.3), plus
``ROS_DOMAIN_ID``, ``ZENOH_SESSION_CONFIG_URI`` and ``ZENOH_CONFIG_OVERRIDE``.
"""

from __future__ import annotations

import os
import threading
from typing import Any

from posekit.runtime.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from posekit.runtime.transport import (
    EndpointInfo,
    MessageSink,
    PublisherEndpoint,
    SubscriptionEndpoint,
    Transport,
)
from posekit.transport.zenoh_session import (
    DEFAULT_ROUTER_ENDPOINT,
    NodeEntity,
    SessionOptions,
    WirePublisher,
    WireSubscription,
    ZenohSession,
    open_session,
)
from posekit.transport.zenoh_wire import Attachment, EntityKind, TokenInfo, WireQoS

__all__ = ["ENV_ATTACHMENT", "ENV_ROUTER", "ZenohTransport", "options_from_env", "wire_qos"]

ENV_ROUTER = "POSEKIT_ZENOH_ROUTER"
ENV_ATTACHMENT = "POSEKIT_ZENOH_ATTACHMENT"


def wire_qos(qos: QoSProfile) -> WireQoS:
    """Map an rclpy-style profile to rmw_zenoh's QoS (rmw enum values are rclpy's)."""
    return WireQoS(
        reliability=2 if qos.resolved_reliability == ReliabilityPolicy.BEST_EFFORT else 1,
        durability=1 if qos.resolved_durability == DurabilityPolicy.TRANSIENT_LOCAL else 2,
        history=2 if qos.history == HistoryPolicy.KEEP_ALL else 1,
        depth=qos.depth if qos.depth > 0 else 42,
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
            self._owner._forget(self.wire)

    @property
    def subscription_count(self) -> int:
        return len(self._owner._endpoints(self.info.topic, EntityKind.SUBSCRIPTION))


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
                self._owner._forget(self.wire)

    @property
    def publisher_count(self) -> int:
        return len(self._owner._endpoints(self.info.topic, EntityKind.PUBLISHER))


class ZenohTransport(Transport):
    """Nodes' endpoints as rmw_zenoh entities on one Zenoh session."""

    name = "zenoh"

    def __init__(
        self, options: SessionOptions | None = None, *, session: ZenohSession | None = None
    ) -> None:
        self.session = (
            session if session is not None else open_session(options or options_from_env())
        )
        self._lock = threading.Lock()
        self._nodes: dict[tuple[str, str], NodeEntity] = {}
        self._graph = self.session.graph
        self._warned_qos: set[tuple[str, str]] = set()

    # -- nodes -------------------------------------------------------------------------
    def declare_node(self, name: str, namespace: str = "/") -> NodeEntity:
        """Announce a node (idempotent); endpoints announce their node automatically."""
        key = (namespace or "/", name)
        with self._lock:
            node = self._nodes.get(key)
            if node is None:
                node = self.session.create_node(name, key[0])
                self._graph.add_local(node.token_key)  # visible locally at once
                self._nodes[key] = node
            return node

    # -- endpoints ---------------------------------------------------------------------
    def advertise(self, info: EndpointInfo) -> PublisherEndpoint:
        type_name = _type_name(info)
        node = self.declare_node(info.node_name, info.node_namespace)
        wire = self.session.create_publisher(node, info.topic, type_name, wire_qos(info.qos))
        self._graph.add_local(wire.token_key)
        self._check_qos(info, wire_qos(info.qos), EntityKind.PUBLISHER)
        return _Publisher(self, info, wire)

    def subscribe(self, info: EndpointInfo, sink: MessageSink) -> SubscriptionEndpoint:
        _type_name(info)
        node = self.declare_node(info.node_name, info.node_namespace)
        endpoint = _Subscription(self, info)

        def deliver(msg: Any, _att: Attachment) -> None:
            if endpoint.alive:
                sink(msg)

        qos = wire_qos(info.qos)
        self._check_qos(info, qos, EntityKind.SUBSCRIPTION)
        endpoint.wire = self.session.create_subscription(
            node, info.topic, info.msg_type, qos, deliver, warn=info.logger.warning
        )
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

    def _forget(self, wire: WirePublisher | WireSubscription) -> None:
        wire.destroy()
        self._graph.remove_local(wire.token_key)

    def _endpoints(self, topic: str, kind: EntityKind) -> list[TokenInfo]:
        if kind is EntityKind.PUBLISHER:
            return self._graph.publishers(topic)
        return self._graph.subscriptions(topic)

    # -- graph -------------------------------------------------------------------------
    def get_topic_names_and_types(self) -> list[tuple[str, list[str]]]:
        return self._graph.topic_names_and_types()

    def count_publishers(self, topic: str) -> int:
        return len(self._graph.publishers(topic))

    def count_subscribers(self, topic: str) -> int:
        return len(self._graph.subscriptions(topic))

    def get_node_names(self) -> list[str]:
        """Fully qualified names of every node on the graph (this and other processes)."""
        return self._graph.node_names()

    def close(self) -> None:
        self.session.close()
