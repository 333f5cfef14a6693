"""A process's own nodes on the in-process bus, mirrored onto a network transport.

``MirroredTransport(local, network)`` is what ``posekit launch`` uses by default: every
endpoint is created on ``local`` (the deterministic, zero-serialization
:class:`~posekit.runtime.bus.InProcessBus`) *and* announced on ``network`` (Zenoh, or any
transport honouring :attr:`EndpointInfo.remote_only`), so ``posekit topic list``,
``node list``, ``tf echo`` or a user's node in another terminal see the launch's nodes and
endpoints and talk to them, while the launch's nodes keep talking to each other exactly as
they do with no network at all.

Delivery rules:

* Between the process's own nodes: the local bus only (the network endpoints are
  ``remote_only``, so a message never comes back in through the network).
* Out: a message published here is also sent on the network when some *other* process
  subscribes to its topic (demand is polled every :data:`DEMAND_POLL_S`), and always for
  TRANSIENT_LOCAL publishers (``/tf_static``: late remote subscribers get the latched
  samples from the network transport's cache). Sending is done by a forwarding thread per
  publisher from its bounded queue: the publishing thread (the simulator) never serializes
  large messages or waits on the network, one topic's slow send (a large image to a
  stalled subscriber) does not hold up another's (``/clock``), and a slow or vanished remote
  subscriber can only make the queue drop (counted in :attr:`MirroredTransport.dropped`;
  a KEEP_LAST queue keeps its newest ``depth`` messages as that QoS promises, a KEEP_ALL
  queue holds :data:`FORWARD_QUEUE_LIMIT` and logs once when it must drop), never stall
  the run.
* In: messages published by other processes reach the local subscriptions of their topic,
  except on topics this process *owns* (:meth:`MirroredTransport.own_topic`; a simulation
  owns ``/clock``): those are never taken from the network.

Graph questions (topic names, node names, endpoint counts, services) are answered by the
network transport, which knows this process's endpoints and every other process's.

Services: a server is created on both (this process's clients reach it on the bus, other
processes' over the network: ``posekit param set`` on a launch's node); a client calls a
server of this process on the bus when there is one, else over the network.
``get_subscription_count()`` of a publisher counts local subscriptions plus remote ones
(known within one demand poll), so nodes that publish only while someone listens (lazy
cameras, ``/tf`` when nobody subscribes) work for remote subscribers too.
"""

from __future__ import annotations

import dataclasses
import itertools
import logging
import threading
import time
from collections import deque
from typing import Any

from posekit.runtime.bus import snapshot
from posekit.runtime.qos import DurabilityPolicy, HistoryPolicy, QoSProfile
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

__all__ = ["DEMAND_POLL_S", "FORWARD_QUEUE_LIMIT", "MirroredTransport"]

_log = logging.getLogger("posekit.runtime.mirror")

#: Seconds between polls of "does another process subscribe to this topic?".
DEMAND_POLL_S = 0.1
#: Messages waiting to be sent per KEEP_ALL publisher before the oldest are dropped
#: (KEEP_LAST publishers keep their QoS depth).
FORWARD_QUEUE_LIMIT = 1000


class _MirrorPublisher(PublisherEndpoint):
    __slots__ = ("_mirror", "always", "busy", "cond", "info", "lane", "local", "pending",
                 "remote", "remote_count", "stopped")

    def __init__(self, mirror: MirroredTransport, info: EndpointInfo,
                 local: PublisherEndpoint, remote: PublisherEndpoint) -> None:
        self._mirror = mirror
        self.info = info
        self.local = local
        self.remote = remote
        self.always = info.qos.resolved_durability == DurabilityPolicy.TRANSIENT_LOCAL
        limit = (FORWARD_QUEUE_LIMIT if info.qos.history == HistoryPolicy.KEEP_ALL
                 else max(1, info.qos.depth))
        self.pending: deque[Any] = deque(maxlen=limit)
        #: Remote subscriptions seen at the last demand poll.
        self.remote_count = 0
        # This publisher's forwarding lane: its queue's lock and the thread sending from it
        # (started on the first message for the network); ``busy`` while a send is under way.
        self.cond = threading.Condition()
        self.lane: threading.Thread | None = None
        self.busy = False
        #: Set when the publisher is destroyed: its lane ends.
        self.stopped = False

    def publish(self, msg: Any) -> None:
        self.local.publish(msg)
        if self.always or self.remote_count:
            self._mirror._forward(self, snapshot(msg))

    def publish_transfer(self, msg: Any) -> None:
        # Snapshot before the local bus hands ``msg`` itself to a subscriber that may edit it.
        if self.always or self.remote_count:
            self._mirror._forward(self, snapshot(msg))
        self.local.publish_transfer(msg)

    def destroy(self) -> None:
        self._mirror._drop_publisher(self)
        self.local.destroy()
        self.remote.destroy()

    @property
    def subscription_count(self) -> int:
        return self.local.subscription_count + self.remote_count


class _MirrorSubscription(SubscriptionEndpoint):
    __slots__ = ("local", "remote")

    def __init__(self, local: SubscriptionEndpoint, remote: SubscriptionEndpoint | None) -> None:
        self.local = local
        self.remote = remote

    def destroy(self) -> None:
        self.local.destroy()
        if self.remote is not None:
            self.remote.destroy()

    @property
    def publisher_count(self) -> int:
        remote = self.remote.publisher_count if self.remote is not None else 0
        return self.local.publisher_count + remote


class _MirrorServer(ServiceServerEndpoint):
    __slots__ = ("local", "remote")

    def __init__(self, local: ServiceServerEndpoint, remote: ServiceServerEndpoint) -> None:
        self.local = local
        self.remote = remote

    def destroy(self) -> None:
        self.local.destroy()
        self.remote.destroy()


class _MirrorClient(ServiceClientEndpoint):
    __slots__ = ("_numbers", "local", "remote")

    def __init__(self, local: ServiceClientEndpoint, remote: ServiceClientEndpoint) -> None:
        self.local = local
        self.remote = remote
        self._numbers = itertools.count(1)

    @property
    def gid(self) -> bytes:
        # One id whichever side carries the request: the network's (other processes see it).
        return self.remote.gid

    def send_request(self, request: Any, on_response: ResponseSink,
                     header: RequestHeader | None = None) -> None:
        target = self.local if self.local.server_count else self.remote
        if header is None:
            header = RequestHeader(self.remote.gid, next(self._numbers))
        target.send_request(request, on_response, header)

    @property
    def server_count(self) -> int:
        # The network also counts this process's servers (created on both).
        return max(self.local.server_count, self.remote.server_count)

    def destroy(self) -> None:
        self.local.destroy()
        self.remote.destroy()


class MirroredTransport(Transport):
    """Local delivery on ``local``, visibility and remote traffic on ``network``."""

    crosses_processes = True

    def __init__(self, local: Transport, network: Transport) -> None:
        self.local = local
        self.network = network
        self.name = f"{local.name}+{network.name}"
        self.supports_services = local.supports_services and network.supports_services
        self._owned: set[str] = set()
        self._publishers: list[_MirrorPublisher] = []
        self._lock = threading.Lock()  # the publisher list
        self._closed = False
        self._stop = threading.Event()  # ends the demand poll
        #: Messages not sent to the network because a forward queue was full, per topic.
        self.dropped: dict[str, int] = {}
        #: Messages sent to the network, per topic.
        self.forwarded: dict[str, int] = {}
        self._demand = threading.Thread(target=self._demand_loop, name="posekit-mirror-demand",
                                        daemon=True)
        self._demand.start()

    # -- ownership ------------------------------------------------------------------------
    def own_topic(self, topic: str) -> None:
        """Never take ``topic`` from other processes (this process is its only source).

        Applies to subscriptions created afterwards.
        """
        self._owned.add(topic)

    @property
    def owned_topics(self) -> frozenset[str]:
        """Topics taken from local publishers only."""
        return frozenset(self._owned)

    # -- endpoints ------------------------------------------------------------------------
    def advertise(self, info: EndpointInfo) -> PublisherEndpoint:
        """A publisher on the local bus whose messages are also sent on the network."""
        local = self.local.advertise(info)
        try:
            remote = self.network.advertise(dataclasses.replace(info, remote_only=True))
        except BaseException:
            local.destroy()
            raise
        pub = _MirrorPublisher(self, info, local, remote)
        pub.remote_count = remote.subscription_count
        with self._lock:
            self._publishers.append(pub)
        return pub

    def subscribe(self, info: EndpointInfo, sink: MessageSink) -> SubscriptionEndpoint:
        """A subscription receiving local and remote messages."""
        return self.subscribe_with_source(info, lambda msg, _source: sink(msg))

    def subscribe_with_source(
        self, info: EndpointInfo, sink: SourcedMessageSink
    ) -> SubscriptionEndpoint:
        """Subscribe with source ids: the local transport's for local messages.

        Remote messages carry the network's (a GID).
        """
        local = self.local.subscribe_with_source(info, sink)
        remote: SubscriptionEndpoint | None = None
        try:
            if info.topic not in self._owned:
                remote = self.network.subscribe_with_source(
                    dataclasses.replace(info, remote_only=True), sink)
        except BaseException:
            local.destroy()
            raise
        return _MirrorSubscription(local, remote)

    # -- services -------------------------------------------------------------------------
    def create_service_server(self, info: ServiceInfo, sink: RequestSink) -> ServiceServerEndpoint:
        """A server on the local bus, also reachable over the network."""
        local = self.local.create_service_server(info, sink)
        try:
            remote = self.network.create_service_server(info, sink)
        except BaseException:
            local.destroy()
            raise
        return _MirrorServer(local, remote)

    def create_service_client(self, info: ServiceInfo) -> ServiceClientEndpoint:
        """A client that calls a local server when there is one, else one on the network."""
        local = self.local.create_service_client(info)
        try:
            remote = self.network.create_service_client(info)
        except BaseException:
            local.destroy()
            raise
        return _MirrorClient(local, remote)

    def get_service_names_and_types(self) -> list[tuple[str, list[str]]]:
        """The network graph's services (this process's are on it too)."""
        return self.network.get_service_names_and_types()

    def get_service_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The services a node serves, from the network graph."""
        return self.network.get_service_names_and_types_by_node(node_name, node_namespace)

    def get_client_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The services a node is a client of, from the network graph."""
        return self.network.get_client_names_and_types_by_node(node_name, node_namespace)

    def get_publisher_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The topics a node publishes, from the network graph."""
        return self.network.get_publisher_names_and_types_by_node(node_name, node_namespace)

    def get_subscriber_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The topics a node subscribes to, from the network graph."""
        return self.network.get_subscriber_names_and_types_by_node(node_name, node_namespace)

    def declare_node(self, name: str, namespace: str = "/") -> Any:
        """Declare the node on the local bus and on the network."""
        self.local.declare_node(name, namespace)
        return self.network.declare_node(name, namespace)

    def undeclare_node(self, name: str, namespace: str = "/") -> None:
        """Undeclare the node on the local bus and on the network."""
        self.local.undeclare_node(name, namespace)
        self.network.undeclare_node(name, namespace)

    # -- graph: the network's view (this process's endpoints and everyone else's) ----------
    def get_topic_names_and_types(self) -> list[tuple[str, list[str]]]:
        """The network graph's topics (this process's are on it too)."""
        return self.network.get_topic_names_and_types()

    def count_publishers(self, topic: str) -> int:
        """Publishers on ``topic``, from the network graph."""
        return self.network.count_publishers(topic)

    def count_subscribers(self, topic: str) -> int:
        """Subscriptions on ``topic``, from the network graph."""
        return self.network.count_subscribers(topic)

    def publisher_qos_profiles(self, topic: str) -> list[QoSProfile] | None:
        """The QoS each publisher on ``topic`` offers, from the network graph."""
        return self.network.publisher_qos_profiles(topic)

    def get_node_names(self) -> list[str]:
        """Fully qualified node names on the network graph."""
        return self.network.get_node_names()

    def get_publishers_info_by_topic(self, topic: str) -> list[Any]:
        """The publishers on ``topic``, from the network graph."""
        return self.network.get_publishers_info_by_topic(topic)

    def get_subscriptions_info_by_topic(self, topic: str) -> list[Any]:
        """The subscriptions on ``topic``, from the network graph."""
        return self.network.get_subscriptions_info_by_topic(topic)

    def graph_entities(self) -> list[Any]:
        """Every node and endpoint of the network graph."""
        return self.network.graph_entities()

    def sync_graph(self, timeout: float = 2.0) -> int:
        """Complete the network transport's view of the graph (see :meth:`Transport.sync_graph`)."""
        return self.network.sync_graph(timeout)

    def graph_description(self) -> str:
        """The network transport's description of its graph."""
        return self.network.graph_description()

    def __getattr__(self, name: str) -> Any:
        # Transport-specific tools of the network transport beyond the contract (e.g. the
        # Zenoh ``graph`` and ``session``), for command-line tools running in this process.
        if name.startswith("_") or name in ("local", "network"):
            raise AttributeError(name)
        return getattr(self.network, name)

    # -- forwarding -----------------------------------------------------------------------
    def _forward(self, pub: _MirrorPublisher, msg: Any) -> None:
        with pub.cond:
            if self._closed or pub.stopped:
                return
            if len(pub.pending) == pub.pending.maxlen:
                topic = pub.info.topic
                count = self.dropped.get(topic, 0)
                self.dropped[topic] = count + 1
                if count == 0 and pub.info.qos.history == HistoryPolicy.KEEP_ALL:
                    pub.info.logger.warning(
                        f"network send queue of '{topic}' is full (a remote subscriber or the "
                        "network is slower than the publisher): dropping the oldest messages "
                        "for the network; local delivery is unaffected"
                    )
            pub.pending.append(msg)
            if pub.lane is None:
                pub.lane = threading.Thread(
                    target=self._lane, args=(pub,), daemon=True,
                    name=f"posekit-mirror-out {pub.info.topic}",
                )
                pub.lane.start()
            pub.cond.notify()

    def _lane(self, pub: _MirrorPublisher) -> None:
        topic = pub.info.topic
        while True:
            with pub.cond:
                while not pub.pending and not self._closed and not pub.stopped:
                    pub.cond.wait()
                if self._closed or pub.stopped:
                    return
                msg = pub.pending.popleft()
                pub.busy = True
            try:
                pub.remote.publish(msg)
            except Exception as exc:  # a destroyed endpoint or an unserializable message
                if topic not in self.dropped:
                    pub.info.logger.warning(f"cannot send '{topic}' to the network: {exc}")
                self.dropped[topic] = self.dropped.get(topic, 0) + 1
            else:
                self.forwarded[topic] = self.forwarded.get(topic, 0) + 1
            finally:
                with pub.cond:
                    pub.busy = False
                    pub.cond.notify_all()

    def _demand_loop(self) -> None:
        while not self._stop.wait(DEMAND_POLL_S):
            with self._lock:
                publishers = [p for p in self._publishers if not p.always]
            for pub in publishers:
                try:
                    pub.remote_count = pub.remote.subscription_count
                except Exception as exc:  # the network transport is closing
                    _log.debug("demand poll failed: %s", exc)

    def _drop_publisher(self, pub: _MirrorPublisher) -> None:
        with self._lock:
            if pub in self._publishers:
                self._publishers.remove(pub)
        with pub.cond:
            pub.pending.clear()
            pub.remote_count = 0
            pub.always = False
            pub.stopped = True
            pub.cond.notify_all()
        # Wait for a send under way: a thread left inside the network library when the
        # interpreter exits is killed there, and zenoh's runtime aborts the process on that.
        if pub.lane is not None and pub.lane is not threading.current_thread():
            pub.lane.join(timeout=1.0)

    def flush(self, timeout: float = 2.0) -> bool:
        """Wait until every queued message was handed to the network (False on timeout)."""
        deadline = time.monotonic() + timeout
        with self._lock:
            publishers = list(self._publishers)
        for pub in publishers:
            with pub.cond:
                while pub.pending or pub.busy:
                    remaining = deadline - time.monotonic()
                    if remaining <= 0:
                        return False
                    pub.cond.wait(remaining)
        return True

    def close(self) -> None:
        """Flush pending sends (at most 0.5 s), then close both transports."""
        self.flush(0.5)
        self._stop.set()
        with self._lock:
            publishers = list(self._publishers)
        self._closed = True
        for pub in publishers:
            with pub.cond:
                pub.cond.notify_all()
        self._demand.join(timeout=1.0)
        for pub in publishers:
            if pub.lane is not None:
                pub.lane.join(timeout=1.0)
        self.network.close()
        self.local.close()
