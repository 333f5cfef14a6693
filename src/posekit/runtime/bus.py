"""The in-process bus: publish/subscribe between nodes of one process, no serialization.

Mutation policy ("snapshot + private structure, shared frozen bulk")
--------------------------------------------------------------------
Python messages are mutable dataclasses, and rclpy code freely reuses and edits them. So:

1. ``publish(msg)`` takes a **snapshot**: a structural copy of the message tree (new
   dataclass objects and lists; immutable scalars and ``bytes`` shared). Numpy arrays up to
   :data:`SMALL_ARRAY_BYTES` (covariances, camera matrices, joint states) are copied; larger
   arrays (image pixels, point clouds) are **not copied but frozen in place**
   (``flags.writeable = False``): the publisher hands the buffer over. The publisher may keep
   editing and re-publishing its message object; only writing *into* a published large
   array raises ``ValueError: assignment destination is read-only`` (allocate a new array or
   ``.copy()`` first).
2. Every subscription receives its **own** structural copy of the snapshot (the last one
   receives the snapshot itself when no TRANSIENT_LOCAL history keeps it), with small arrays
   copied again and the frozen large arrays shared. A callback can therefore change any field
   of its message without another subscriber seeing it, and a 1280x720 image costs the same
   few microseconds per subscriber as an empty one.
3. Immutable messages are shared, never copied: frozen dataclass messages whose fields all
   hold numbers, strings or bytes (nobody can change them, so isolation holds for free).
4. ``publish_transfer(msg)`` (``Publisher.publish_transfer``, rclcpp's ``unique_ptr``
   publish) is for a message the publisher built for this one publish and gives up: step 1 is
   skipped and the last subscription receives ``msg`` itself, the others copies as in 2. The
   isolation guarantee between subscribers is unchanged; the publisher must not touch ``msg``
   (or any array or sub-message in it) afterwards. The simulator's nodes publish this way:
   with one subscriber per topic a delivery then costs no copy at all.

Numbers are in docs/performance.md (``benchmarks/runtime.py``).

QoS on the bus
--------------
* Queues live in the runtime's subscriptions (KEEP_LAST depth drops the oldest undelivered
  message; KEEP_ALL never drops).
* RELIABLE vs BEST_EFFORT: in one process nothing is lost in transit, so both deliver every
  published message to the subscription queue; the observable difference is matching: a
  BEST_EFFORT publisher does not connect to a RELIABLE subscription (logged as incompatible
  QoS, as DDS / rmw_zenoh do).
* TRANSIENT_LOCAL publishers keep their last ``depth`` snapshots; a TRANSIENT_LOCAL
  subscription created later receives them (oldest first, in original publish order across
  publishers). A VOLATILE publisher does not match a TRANSIENT_LOCAL subscription. With a
  ``lifespan`` in the publisher's QoS, snapshots older than it (wall time) are not delivered
  to late subscriptions and are dropped from the history.

Services on the bus
-------------------
A request goes to the oldest live server of the service (snapshot of the request, as a
publish); its response comes back as a snapshot too, synchronously in the thread that
answers. With no server the request is dropped (the client's future stays pending, as
with rmw when no server exists). A server or client of another service type on the same
name raises :class:`TopicTypeMismatchError`.
"""

from __future__ import annotations

import copy
import dataclasses
import functools
import itertools
import os
import threading
import time
import typing
from collections import deque
from collections.abc import Callable
from typing import Any, NoReturn

import numpy as np

from posekit.runtime.qos import (
    DurabilityPolicy,
    OfferMatch,
    QoSProfile,
    match_offer,
)
from posekit.runtime.transport import (
    EndpointInfo,
    GraphEndpoint,
    MessageSink,
    PublisherEndpoint,
    RequestHeader,
    RequestSink,
    ResponseSink,
    ServiceClientEndpoint,
    ServiceInfo,
    ServiceServerEndpoint,
    SubscriptionEndpoint,
    TopicTypeMismatchError,
    Transport,
)

__all__ = ["SMALL_ARRAY_BYTES", "InProcessBus", "snapshot"]

#: Arrays up to this many bytes are copied on publish and per subscriber; larger ones are
#: frozen and shared.
SMALL_ARRAY_BYTES = 4096

_ATOMIC: frozenset[type] = frozenset(
    {int, float, str, bool, bytes, complex, type(None), np.float64, np.float32, np.int64,
     np.int32, np.uint8, np.uint32, np.bool_}
)
_copiers: dict[type, Callable[[Any], Any]] = {}


def snapshot(value: Any) -> Any:
    """The bus's copy of a message (policy in the module docstring)."""
    t = type(value)
    if t in _ATOMIC:
        return value
    fn = _copiers.get(t)
    if fn is None:
        fn = _make_copier(t)
    return fn(value)


def _copy_array(a: np.ndarray) -> np.ndarray:
    if a.nbytes <= SMALL_ARRAY_BYTES:
        return a.copy()
    if a.flags.writeable:
        a.flags.writeable = False
    return a


def _copy_list(items: list[Any]) -> list[Any]:
    atomic = _ATOMIC
    return [x if type(x) in atomic else snapshot(x) for x in items]


def _copy_tuple(items: tuple[Any, ...]) -> tuple[Any, ...]:
    return tuple(_copy_list(list(items)))


def _copy_dict(d: dict[Any, Any]) -> dict[Any, Any]:
    return {k: snapshot(v) for k, v in d.items()}


def _make_copier(t: type) -> Callable[[Any], Any]:
    fn: Callable[[Any], Any]
    if issubclass(t, np.ndarray):
        fn = _copy_array
    elif t is list:
        fn = _copy_list
    elif t is tuple:
        fn = _copy_tuple
    elif t is dict:
        fn = _copy_dict
    elif t in (bytearray,):
        fn = bytearray
    elif isinstance(t, type) and issubclass(t, np.generic):
        fn = _identity
    elif dataclasses.is_dataclass(t):
        fn = _dataclass_copier(t)
    else:
        fn = copy.deepcopy
    _copiers[t] = fn
    return fn


def _identity(x: Any) -> Any:
    return x


_MAX_INLINE_DEPTH = 4


def _list_element_types(cls: type) -> dict[str, type]:
    """Fields annotated ``list[SomeDataclass]`` -> SomeDataclass (best effort)."""
    try:
        hints = typing.get_type_hints(cls)
    except Exception:  # unresolvable annotations: no specialisation
        return {}
    out: dict[str, type] = {}
    for name, hint in hints.items():
        args = typing.get_args(hint)
        if typing.get_origin(hint) is list and len(args) == 1 and dataclasses.is_dataclass(
            args[0]
        ) and isinstance(args[0], type):
            out[name] = args[0]
    return out


def _frozen_copier(cls: type) -> Callable[[Any], Any]:
    """Copier of a frozen dataclass.

    An instance whose fields all hold immutable scalars (numbers, strings, bytes) cannot be
    changed, so it is shared, not copied; anything holding a mutable field is deep-copied
    (frozen classes cannot be rebuilt field by field).
    """
    names = tuple(f.name for f in dataclasses.fields(cls))
    atomic = _ATOMIC

    def copy_frozen(o: Any) -> Any:
        for name in names:
            if type(getattr(o, name)) not in atomic:
                return copy.deepcopy(o)
        return o

    return copy_frozen


def _dataclass_copier(cls: type) -> Callable[[Any], Any]:
    """Generate ``copy_msg(o)`` for a dataclass message.

    Nested message fields whose default value is itself a dataclass are copied inline, guarded
    by an exact type check (a field holding another type falls back to :func:`snapshot`), so
    a TransformStamped is copied by one flat function instead of a call per sub-message.
    """
    if getattr(cls, "__dataclass_params__").frozen:  # noqa: B009
        return _frozen_copier(cls)
    env: dict[str, Any] = {"new": object.__new__, "atomic": _ATOMIC, "snap": snapshot}
    lines = ["def copy_msg(o0):"]
    counter = itertools.count(1)

    def emit(c: type, src: str, dst: str, indent: str, depth: int) -> None:
        cname = f"C{next(counter)}"
        env[cname] = c
        lines.append(f"{indent}{dst} = new({cname})")
        try:
            defaults = c()
        except Exception:  # not default-constructible: no inlining below
            defaults = None
        hints = _list_element_types(c)
        for f in dataclasses.fields(c):
            value = f"v{next(counter)}"
            lines.append(f"{indent}{value} = {src}.{f.name}")
            default = getattr(defaults, f.name, None) if defaults is not None else None
            sub = type(default)
            if (
                depth < _MAX_INLINE_DEPTH
                and dataclasses.is_dataclass(sub)
                and not getattr(sub, "__dataclass_params__").frozen  # noqa: B009
            ):
                guard = f"C{next(counter)}"
                env[guard] = sub
                child = f"n{next(counter)}"
                lines.append(f"{indent}if type({value}) is {guard}:")
                emit(sub, value, child, indent + "    ", depth + 1)
                lines.append(f"{indent}    {dst}.{f.name} = {child}")
                lines.append(f"{indent}else:")
                lines.append(f"{indent}    {dst}.{f.name} = snap({value})")
            elif f.name in hints and type(default) is list:
                # list[Message]: copy elements with that message's copier directly.
                elem = hints[f.name]
                guard, elem_copy = f"C{next(counter)}", f"F{next(counter)}"
                env[guard] = elem
                env[elem_copy] = _copiers.get(elem) or _make_copier(elem)
                lines.append(
                    f"{indent}{dst}.{f.name} = [{elem_copy}(x) if type(x) is {guard} "
                    f"else snap(x) for x in {value}] if type({value}) is list "
                    f"else snap({value})"
                )
            else:
                lines.append(
                    f"{indent}{dst}.{f.name} = {value} if type({value}) in atomic "
                    f"else snap({value})"
                )

    emit(cls, "o0", "r0", "    ", 0)
    lines.append("    return r0")
    # Bind every helper as a default argument: fast locals instead of global lookups.
    lines[0] = "def copy_msg(o0, *, " + ", ".join(f"{k}={k}" for k in env) + "):"
    namespace: dict[str, Any] = {}
    exec("\n".join(lines), dict(env), namespace)  # generated from field names only
    fn: Callable[[Any], Any] = namespace["copy_msg"]
    return fn


@functools.lru_cache(maxsize=256)
def _type_hash(msg_type: type) -> str | None:
    """The RIHS01 hash of a message class, None when unknown.

    Unknown: a class that is no ROS message (the bus carries any class), or no rosbags (the
    ``cdr`` extra), which computes it.
    """
    try:
        from posekit.msgs.cdr import type_hash_rihs01

        return type_hash_rihs01(msg_type)
    except Exception:  # no ROS type, or no rosbags: the hash is unknown
        return None


def _graph_endpoint(info: EndpointInfo, gid: bytes) -> GraphEndpoint:
    return GraphEndpoint(info.node_name, info.node_namespace, info.topic, info.type_name,
                         _type_hash(info.msg_type), info.qos.copy(), gid)


class _Topic:
    __slots__ = ("msg_type", "name", "publishers", "subscriptions")

    def __init__(self, name: str, msg_type: type) -> None:
        self.name = name
        self.msg_type = msg_type
        self.publishers: list[_BusPublisher] = []
        self.subscriptions: list[_BusSubscription] = []


class _BusSubscription(SubscriptionEndpoint):
    def __init__(self, bus: InProcessBus, info: EndpointInfo, sink: MessageSink) -> None:
        self._bus = bus
        self.info = info
        self.gid = os.urandom(16)  # unique per endpoint, as an rmw GID
        self.sink = sink
        self.alive = True

    def destroy(self) -> None:
        if self.alive:
            self.alive = False
            self._bus._remove_subscription(self)

    @property
    def publisher_count(self) -> int:
        return self._bus._matched_publishers(self)


class _BusPublisher(PublisherEndpoint):
    def __init__(self, bus: InProcessBus, info: EndpointInfo) -> None:
        self._bus = bus
        self.info = info
        self.gid = os.urandom(16)  # unique per endpoint, as an rmw GID
        self.alive = True
        self.matched: tuple[_BusSubscription, ...] = ()
        # TRANSIENT_LOCAL history: (publish sequence number, snapshot, monotonic ns when
        # the QoS has a lifespan else 0), oldest first.
        self.history: deque[tuple[int, Any, int]] | None = None
        self.lifespan_ns = info.qos.lifespan_ns
        if info.qos.resolved_durability == DurabilityPolicy.TRANSIENT_LOCAL:
            self.history = deque(maxlen=info.qos.queue_limit)
        self._type = info.msg_type

    def _keep(self, history: deque[tuple[int, Any, int]], snap: Any) -> None:
        """Append ``snap`` to the history, first forgetting entries past their lifespan."""
        lifespan = self.lifespan_ns
        if lifespan is None:
            history.append((next(self._bus._seq), snap, 0))
            return
        now = time.monotonic_ns()
        while history and now - history[0][2] > lifespan:
            history.popleft()
        history.append((next(self._bus._seq), snap, now))

    def live_history(self) -> list[tuple[int, Any, int]]:
        """The history entries still within their lifespan."""
        history = self.history or ()
        lifespan = self.lifespan_ns
        if lifespan is None:
            return list(history)
        now = time.monotonic_ns()
        return [entry for entry in history if now - entry[2] <= lifespan]

    def _reject(self, msg: Any) -> NoReturn:
        """Raise why ``msg`` cannot be published (kept off the inlined publish checks)."""
        if not self.alive:
            raise RuntimeError(f"publisher on '{self.info.topic}' has been destroyed")
        raise TypeError(
            f"publisher on '{self.info.topic}' expects {self._type.__name__}, "
            f"got {type(msg).__name__}"
        )

    def publish(self, msg: Any) -> None:
        if not self.alive or (type(msg) is not self._type and not isinstance(msg, self._type)):
            self._reject(msg)
        subs = self.matched
        history = self.history
        if history is None:
            if not subs:
                return
            copier = _copiers.get(type(msg))
            snap = copier(msg) if copier is not None else snapshot(msg)
            if len(subs) == 1:
                subs[0].sink(snap)
                return
            last = len(subs) - 1
            for i, sub in enumerate(subs):
                sub.sink(snap if i == last else snapshot(snap))
            return
        snap = snapshot(msg)
        self._keep(history, snap)
        for sub in subs:
            sub.sink(snapshot(snap))

    def publish_transfer(self, msg: Any) -> None:
        """Deliver ``msg`` itself to the last matched subscription, copies to the others.

        The caller gave it up, so the publish snapshot is not needed.
        """
        if not self.alive or (type(msg) is not self._type and not isinstance(msg, self._type)):
            self._reject(msg)
        subs = self.matched
        history = self.history
        if history is None:
            if len(subs) == 1:
                subs[0].sink(msg)
                return
            last = len(subs) - 1
            for i, sub in enumerate(subs):
                sub.sink(msg if i == last else snapshot(msg))
            return
        # The history keeps the handed-over object as its snapshot; subscribers get copies
        # (which freeze its large arrays, as publish() does, before anyone shares them).
        self._keep(history, msg)
        for sub in subs:
            sub.sink(snapshot(msg))

    def destroy(self) -> None:
        if self.alive:
            self.alive = False
            self._bus._remove_publisher(self)

    @property
    def subscription_count(self) -> int:
        return len(self.matched)


class _ServiceName:
    __slots__ = ("clients", "name", "servers", "srv_type")

    def __init__(self, name: str, srv_type: type) -> None:
        self.name = name
        self.srv_type = srv_type
        self.servers: list[_BusServer] = []
        self.clients: list[_BusClient] = []


class _BusServer(ServiceServerEndpoint):
    def __init__(self, bus: InProcessBus, info: ServiceInfo, sink: RequestSink) -> None:
        self._bus = bus
        self.info = info
        self.sink = sink
        self.alive = True

    def destroy(self) -> None:
        if self.alive:
            self.alive = False
            self._bus._remove_service_endpoint(self.info.service, self)


class _BusClient(ServiceClientEndpoint):
    def __init__(self, bus: InProcessBus, info: ServiceInfo) -> None:
        self._bus = bus
        self.info = info
        self.alive = True
        self._gid = os.urandom(16)  # unique per client, as an rmw GID
        self._numbers = itertools.count(1)

    @property
    def gid(self) -> bytes:
        return self._gid

    def send_request(self, request: Any, on_response: ResponseSink,
                     header: RequestHeader | None = None) -> None:
        if not self.alive:
            raise RuntimeError(f"client of '{self.info.service}' has been destroyed")
        if header is None:
            header = RequestHeader(self._gid, next(self._numbers))
        server = self._bus._server_for(self.info.service)
        if server is None:
            return
        answered = False

        def respond(response: Any) -> None:
            nonlocal answered
            if answered or not self.alive:
                return
            answered = True
            on_response(snapshot(response))

        server.sink(snapshot(request), respond, header)

    @property
    def server_count(self) -> int:
        return self._bus.count_services(self.info.service)

    def destroy(self) -> None:
        if self.alive:
            self.alive = False
            self._bus._remove_service_endpoint(self.info.service, self)


class InProcessBus(Transport):
    """Topic registry and zero-serialization delivery inside one process."""

    name = "inprocess"
    supports_services = True

    def __init__(self) -> None:
        self._topics: dict[str, _Topic] = {}
        self._services: dict[str, _ServiceName] = {}
        self._nodes: list[tuple[str, str]] = []  # (namespace, name) per declare_node
        self._lock = threading.RLock()
        self._seq = itertools.count()

    # -- nodes --------------------------------------------------------------------------
    def declare_node(self, name: str, namespace: str = "/") -> None:
        """Record node ``namespace/name`` in the graph."""
        with self._lock:
            self._nodes.append((namespace or "/", name))

    def undeclare_node(self, name: str, namespace: str = "/") -> None:
        """Remove node ``namespace/name`` from the graph."""
        with self._lock:
            if (namespace or "/", name) in self._nodes:
                self._nodes.remove((namespace or "/", name))

    def get_node_names(self) -> list[str]:
        """Fully qualified names of the nodes of this bus (duplicates kept), sorted."""
        with self._lock:
            return sorted(("" if ns == "/" else ns) + "/" + name for ns, name in self._nodes)

    # -- services ---------------------------------------------------------------------
    def _service_for(self, info: ServiceInfo) -> _ServiceName:
        entry = self._services.get(info.service)
        if entry is None or not (entry.servers or entry.clients):
            entry = self._services[info.service] = _ServiceName(info.service, info.srv_type)
        elif entry.srv_type is not info.srv_type:
            raise TopicTypeMismatchError(
                f"service '{info.service}' already has type {entry.srv_type.__qualname__}; "
                f"cannot create an endpoint of type {info.srv_type.__qualname__} (node "
                f"'{info.node_name}')"
            )
        return entry

    def create_service_server(self, info: ServiceInfo, sink: RequestSink) -> ServiceServerEndpoint:
        """A server of ``info``'s service on the bus; ``sink(request, respond)`` per request."""
        with self._lock:
            server = _BusServer(self, info, sink)
            self._service_for(info).servers.append(server)
            return server

    def create_service_client(self, info: ServiceInfo) -> ServiceClientEndpoint:
        """A client of ``info``'s service on the bus."""
        with self._lock:
            client = _BusClient(self, info)
            self._service_for(info).clients.append(client)
            return client

    def _server_for(self, service: str) -> _BusServer | None:
        entry = self._services.get(service)
        if entry is None:
            return None
        servers = entry.servers
        return servers[0] if servers else None

    def _remove_service_endpoint(self, service: str, endpoint: _BusServer | _BusClient) -> None:
        with self._lock:
            entry = self._services.get(service)
            if entry is None:
                return
            if isinstance(endpoint, _BusServer) and endpoint in entry.servers:
                entry.servers.remove(endpoint)
            elif isinstance(endpoint, _BusClient) and endpoint in entry.clients:
                entry.clients.remove(endpoint)

    def count_services(self, service: str) -> int:
        """Number of servers of ``service``."""
        entry = self._services.get(service)
        return len(entry.servers) if entry is not None else 0

    def count_clients(self, service: str) -> int:
        """Number of clients of ``service``."""
        entry = self._services.get(service)
        return len(entry.clients) if entry is not None else 0

    def get_service_names_and_types(self) -> list[tuple[str, list[str]]]:
        """Every service with a server or client, with its type names, sorted."""
        with self._lock:
            return sorted(
                (e.name, [(e.servers or e.clients)[0].info.type_name])
                for e in self._services.values()
                if e.servers or e.clients
            )

    def _by_node(self, node_name: str, node_namespace: str,
                 servers: bool) -> list[tuple[str, list[str]]]:
        with self._lock:
            out = []
            for e in self._services.values():
                endpoints: list[Any] = e.servers if servers else e.clients
                for ep in endpoints:
                    if ep.info.node_name == node_name and ep.info.node_namespace == node_namespace:
                        out.append((e.name, [ep.info.type_name]))
                        break
            return sorted(out)

    def get_service_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The services node ``node_namespace/node_name`` serves, with their type names."""
        return self._by_node(node_name, node_namespace, servers=True)

    def get_client_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The services node ``node_namespace/node_name`` is a client of, with their type names."""
        return self._by_node(node_name, node_namespace, servers=False)

    # -- graph ------------------------------------------------------------------------
    def _topic_for(self, info: EndpointInfo) -> _Topic:
        topic = self._topics.get(info.topic)
        if topic is None or not (topic.publishers or topic.subscriptions):
            topic = _Topic(info.topic, info.msg_type)
            self._topics[info.topic] = topic
        elif topic.msg_type is not info.msg_type:
            raise TopicTypeMismatchError(
                f"topic '{info.topic}' already carries {topic.msg_type.__module__}."
                f"{topic.msg_type.__qualname__}; cannot create an endpoint of type "
                f"{info.msg_type.__module__}.{info.msg_type.__qualname__} (node "
                f"'{info.node_name}')"
            )
        return topic

    @staticmethod
    def _compatible(pub: _BusPublisher, sub: _BusSubscription) -> bool:
        result = match_offer(pub.info.qos, sub.info.qos)
        if result == OfferMatch.OK:
            return True
        topic = pub.info.topic
        pub.info.logger.warning(
            f"New subscription discovered on topic '{topic}', requesting incompatible QoS. "
            f"No messages will be sent to it. Last incompatible policy: {result.value}"
        )
        sub.info.logger.warning(
            f"New publisher discovered on topic '{topic}', offering incompatible QoS. "
            f"No messages will be received from it. Last incompatible policy: {result.value}"
        )
        return False

    def _rematch(self, topic: _Topic) -> None:
        for pub in topic.publishers:
            pub.matched = tuple(
                s for s in topic.subscriptions
                if match_offer(pub.info.qos, s.info.qos) == OfferMatch.OK
            )

    def advertise(self, info: EndpointInfo) -> PublisherEndpoint:
        """A publisher on ``info``'s topic (see :meth:`Transport.advertise`)."""
        with self._lock:
            topic = self._topic_for(info)
            pub = _BusPublisher(self, info)
            for sub in topic.subscriptions:
                self._compatible(pub, sub)
            topic.publishers.append(pub)
            self._rematch(topic)
            return pub

    def subscribe(self, info: EndpointInfo, sink: MessageSink) -> SubscriptionEndpoint:
        """A subscription on ``info``'s topic calling ``sink(msg)``."""
        with self._lock:
            topic = self._topic_for(info)
            sub = _BusSubscription(self, info, sink)
            late: list[tuple[int, Any, int]] = []
            for pub in topic.publishers:
                if self._compatible(pub, sub) and pub.history is not None and (
                    info.qos.resolved_durability == DurabilityPolicy.TRANSIENT_LOCAL
                ):
                    late.extend(pub.live_history())
            topic.subscriptions.append(sub)
            self._rematch(topic)
        late.sort(key=lambda item: item[0])
        for _, snap, _ in late:
            sink(snapshot(snap))
        return sub

    def _remove_publisher(self, pub: _BusPublisher) -> None:
        with self._lock:
            topic = self._topics.get(pub.info.topic)
            if topic is not None and pub in topic.publishers:
                topic.publishers.remove(pub)
            pub.matched = ()

    def _remove_subscription(self, sub: _BusSubscription) -> None:
        with self._lock:
            topic = self._topics.get(sub.info.topic)
            if topic is not None and sub in topic.subscriptions:
                topic.subscriptions.remove(sub)
                self._rematch(topic)

    def _matched_publishers(self, sub: _BusSubscription) -> int:
        topic = self._topics.get(sub.info.topic)
        if topic is None:
            return 0
        return sum(1 for p in topic.publishers if sub in p.matched)

    def get_topic_names_and_types(self) -> list[tuple[str, list[str]]]:
        """Every topic with a publisher or subscription, with its type names, sorted."""
        with self._lock:
            return sorted(
                (t.name, [t.publishers[0].info.type_name if t.publishers
                          else t.subscriptions[0].info.type_name])
                for t in self._topics.values()
                if t.publishers or t.subscriptions
            )

    def _topics_by_node(self, node_name: str, node_namespace: str,
                        publishers: bool) -> list[tuple[str, list[str]]]:
        with self._lock:
            found: dict[str, set[str]] = {}
            for t in self._topics.values():
                for ep in (t.publishers if publishers else t.subscriptions):
                    if ep.info.node_name == node_name and ep.info.node_namespace == node_namespace:
                        found.setdefault(t.name, set()).add(ep.info.type_name)
            return [(name, sorted(types)) for name, types in sorted(found.items())]

    def get_publisher_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The topics node ``node_namespace/node_name`` publishes, with their type names."""
        return self._topics_by_node(node_name, node_namespace, publishers=True)

    def get_subscriber_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The topics node ``node_namespace/node_name`` subscribes to, with their type names."""
        return self._topics_by_node(node_name, node_namespace, publishers=False)

    def count_publishers(self, topic: str) -> int:
        """Number of publishers on ``topic``."""
        t = self._topics.get(topic)
        return len(t.publishers) if t is not None else 0

    def count_subscribers(self, topic: str) -> int:
        """Number of subscriptions on ``topic``."""
        t = self._topics.get(topic)
        return len(t.subscriptions) if t is not None else 0

    def publisher_qos_profiles(self, topic: str) -> list[QoSProfile]:
        """The profile each publisher on ``topic`` was created with (copies)."""
        with self._lock:
            t = self._topics.get(topic)
            return [p.info.qos.copy() for p in t.publishers] if t is not None else []

    def get_publishers_info_by_topic(self, topic: str) -> list[GraphEndpoint]:
        """Every publisher on ``topic``: node, type, type hash, QoS, GID."""
        with self._lock:
            t = self._topics.get(topic)
            return [_graph_endpoint(p.info, p.gid) for p in t.publishers] if t else []

    def get_subscriptions_info_by_topic(self, topic: str) -> list[GraphEndpoint]:
        """Every subscription on ``topic``."""
        with self._lock:
            t = self._topics.get(topic)
            return [_graph_endpoint(s.info, s.gid) for s in t.subscriptions] if t else []

    def close(self) -> None:
        """Drop every endpoint; the bus carries nothing afterwards."""
        with self._lock:
            for topic in self._topics.values():
                for pub in topic.publishers:
                    pub.alive = False
                    pub.matched = ()
                for sub in topic.subscriptions:
                    sub.alive = False
            self._topics.clear()
            for entry in self._services.values():
                for server in entry.servers:
                    server.alive = False
                for client in entry.clients:
                    client.alive = False
            self._services.clear()
