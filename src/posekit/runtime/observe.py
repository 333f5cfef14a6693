"""Passive observation of every topic of a graph.

What ``ros2 bag record``, a visualizer and a bridge have in common.

A :class:`TopicObserver` watches a :class:`~posekit.runtime.transport.Transport` (the
in-process bus, Zenoh, DDS or the mirrored bus of a launch) and keeps one subscription per
topic that has a publisher and that its owner wants, *without a node in any executor*: each
topic's sink is called directly by the transport (on the publisher's thread in process, on
the transport's receive thread across processes), so observing a simulated run never adds
callbacks to it nor changes its order of events. The owner decides what happens to the
messages; the observer owns discovery, QoS and teardown:

* **Discovery**: :meth:`TopicObserver.refresh` (called by the owner, periodically) reads the
  graph, subscribes to new topics that have at least one publisher (so the observer never
  creates a topic of its own) and that ``select(topic, type_name)`` accepts, at most
  ``max_topics`` of them (``priority`` topics first); topics whose type cannot be resolved,
  or that the owner refuses (``sink_for`` raising :class:`TopicSkipped`), are remembered
  with the reason (:attr:`TopicObserver.skipped`) and not retried until their type changes.
* **QoS** (what ``ros2 bag record`` does, rosbag2's adaptive request): the observer asks the
  transport what every publisher offers (:func:`offered_qos_profiles`) and requests
  RELIABLE only when every publisher is reliable and TRANSIENT_LOCAL only when every
  publisher is transient local (:func:`observing_qos`), so it matches every publisher and
  takes latched samples (``/tf_static``) whenever it can. A transport that cannot tell
  (:meth:`~posekit.runtime.transport.Transport.publisher_qos_profiles` returns None) is
  assumed to carry rclpy's default (reliable, volatile) except on ``/tf_static``, which
  gets tf2_ros's static profile (transient local). When the offers change so that the
  request must change (a best-effort publisher joins a reliable topic), the subscription is
  replaced.
* **Topics that go away**: a topic whose publishers have all left for ``grace_refreshes``
  refreshes in a row is unsubscribed and forgotten (``on_removed(topic)``); if it comes back
  it is observed afresh, with the QoS and type its new publishers offer. A type change is
  the same: the old subscription ends, a new one starts.
* **Teardown**: :meth:`TopicObserver.close` destroys every subscription; late messages are
  dropped, and sinks are never called after ``close`` returns (the transport's contract).

Sinks must be quick and thread-safe: they may run concurrently on several transport threads.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Collection
from dataclasses import dataclass
from typing import Any

from posekit.msgs.errors import UnknownMessageTypeError
from posekit.runtime.logging import RcutilsLogger, get_logger
from posekit.runtime.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    QoSProfile,
    ReliabilityPolicy,
)
from posekit.runtime.ratelimit import RateLimitedLog
from posekit.runtime.transport import (
    EndpointInfo,
    MessageSink,
    SubscriptionEndpoint,
    TopicTypeMismatchError,
    Transport,
)

__all__ = [
    "ObservedTopic",
    "TopicObserver",
    "TopicSkipped",
    "observing_qos",
    "offered_qos_profiles",
]

#: Static transforms: what tf2_ros's StaticTransformBroadcaster offers.
TF_STATIC_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
#: Depth of a KEEP_LAST transient-local request: room for every latched sample of a topic
#: (several static broadcasters on ``/tf_static``).
_LATCHED_DEPTH = 100


class TopicSkipped(Exception):  # noqa: N818 - a verdict, not an error condition
    """Raised by a ``sink_for`` callback: the owner does not observe this topic.

    The message is the reason, kept in :attr:`TopicObserver.skipped`.
    """


@dataclass(frozen=True)
class ObservedTopic:
    """A topic being observed.

    Its name, type, message class, the publishers' offers and the profile the observer
    subscribed with.
    """

    name: str
    type_name: str
    msg_type: type
    offered: tuple[QoSProfile, ...]
    qos: QoSProfile


def offered_qos_profiles(transport: Transport, topic: str) -> list[QoSProfile]:
    """The QoS each publisher on ``topic`` offers, as far as ``transport`` tells.

    Without an answer from the transport, ``/tf_static`` gets tf2_ros's static profile
    (transient local, depth 1) and every other topic rclpy's default (reliable, depth 10),
    one per publisher counted. A topic without publishers has no offers: ``[]``.
    """
    count = transport.count_publishers(topic)
    if count <= 0:
        return []
    profiles = transport.publisher_qos_profiles(topic)
    if profiles:
        return list(profiles)
    fallback = TF_STATIC_QOS if topic == "/tf_static" else QoSProfile(depth=10)
    return [fallback] * count


def observing_qos(offered: Collection[QoSProfile], depth: int | None = 10) -> QoSProfile:
    """A subscription profile every offer in ``offered`` matches (rosbag2's adaptive QoS).

    TRANSIENT_LOCAL only when every publisher is transient local, BEST_EFFORT as soon as one
    publisher is best effort. ``depth`` None requests KEEP_ALL; a transient-local KEEP_LAST
    request keeps at least 100 samples (every latched sample of several publishers).
    """
    transient = bool(offered) and all(
        p.resolved_durability == DurabilityPolicy.TRANSIENT_LOCAL for p in offered
    )
    best_effort = any(p.resolved_reliability == ReliabilityPolicy.BEST_EFFORT for p in offered)
    if depth is None:
        history, depth = HistoryPolicy.KEEP_ALL, 0
    else:
        history = HistoryPolicy.KEEP_LAST
        depth = max(depth, _LATCHED_DEPTH) if transient else max(depth, 1)
    return QoSProfile(
        history=history,
        depth=depth,
        reliability=ReliabilityPolicy.BEST_EFFORT if best_effort else ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if transient else DurabilityPolicy.VOLATILE,
    )


def _resolve(type_name: str) -> type:
    from posekit.msgs.registry import find_message_class

    return find_message_class(type_name)


def _same_request(a: QoSProfile, b: QoSProfile) -> bool:
    return (a.resolved_reliability == b.resolved_reliability
            and a.resolved_durability == b.resolved_durability)


@dataclass
class _Entry:
    topic: ObservedTopic
    sink: MessageSink
    endpoint: SubscriptionEndpoint
    missing: int = 0  # refreshes in a row without a publisher


class TopicObserver:
    """Subscribes to every wanted topic of ``transport`` (see the module docstring).

    Args:
        transport: the graph to observe.
        sink_for: called once per topic when the observer starts observing it; returns the
            sink for its messages or raises :class:`TopicSkipped`.
        select: ``select(topic, type_name)``: whether to observe a topic (default: all).
        on_removed: called with a topic's name after it stopped being observed because its
            publishers left or its type changed (not on :meth:`close`).
        on_skipped: called with a topic's name and the reason it is not observed (once per
            topic and type; default: one warning line on ``logger``).
        node_name: the name the subscriptions carry on the graph.
        node_namespace: their node namespace.
        depth: KEEP_LAST depth of the requests (None: KEEP_ALL, as a recorder wants).
        max_topics: observe at most this many topics (None: no limit); the others are
            skipped with the reason.
        priority: topics observed before any other when ``max_topics`` is reached.
        resolve: type name -> message class (default: posekit's class, else rosbags'
            Jazzy typestore; raise LookupError/ValueError for unknown types).
        grace_refreshes: refreshes without publishers before a topic is let go.
        subscribe: creates a subscription (default ``transport.subscribe``: sinks run on
            the transport's threads); a recorder passes one that creates a node's
            subscription, so its callbacks run on the node's executor, in its order of
            events and on its clock.
        logger: where problems are logged (one line each).
    """

    def __init__(
        self,
        transport: Transport,
        sink_for: Callable[[ObservedTopic], MessageSink],
        *,
        select: Callable[[str, str], bool] | None = None,
        on_removed: Callable[[str], None] | None = None,
        on_skipped: Callable[[str, str], None] | None = None,
        node_name: str = "posekit_observer",
        node_namespace: str = "/",
        depth: int | None = 10,
        max_topics: int | None = None,
        priority: Collection[str] = (),
        resolve: Callable[[str], type] = _resolve,
        grace_refreshes: int = 2,
        logger: RcutilsLogger | None = None,
        subscribe: Callable[[EndpointInfo, MessageSink], SubscriptionEndpoint] | None = None,
    ) -> None:
        if max_topics is not None and max_topics < 0:
            raise ValueError(f"max_topics must be >= 0, got {max_topics}")
        if grace_refreshes < 1:
            raise ValueError(f"grace_refreshes must be >= 1, got {grace_refreshes}")
        self.transport = transport
        self.logger = logger or get_logger(node_name)
        self._sink_for = sink_for
        self._select = select
        self._on_removed = on_removed
        self._on_skipped = on_skipped
        self._node_name = node_name
        self._node_namespace = node_namespace
        self._depth = depth
        self._max_topics = max_topics
        self._priority = frozenset(priority)
        self._resolve = resolve
        self._grace = grace_refreshes
        self._subscribe = subscribe or transport.subscribe
        self._lock = threading.Lock()
        self._refreshing = threading.Lock()
        self._entries: dict[str, _Entry] = {}
        self._skipped: dict[str, tuple[str, str]] = {}  # topic -> (type name, reason)
        self._graph: list[tuple[str, str]] = []
        self._closed = False
        self._warn = RateLimitedLog(self.logger.warning)
        # Topic names are the peers': one line per topic, but a flood of new names shares
        # the limiter's overflow slot (one line a second).
        self._skip_log = RateLimitedLog(self.logger.warning)

    # -- what is observed --------------------------------------------------------------------
    @property
    def closed(self) -> bool:
        """True after :meth:`close`."""
        return self._closed

    def topics(self) -> dict[str, ObservedTopic]:
        """The topics observed now, by name."""
        with self._lock:
            return {name: e.topic for name, e in self._entries.items()}

    def graph(self) -> list[tuple[str, str]]:
        """Every topic of the graph at the last :meth:`refresh`, observed or not.

        Each with its (first) type name.
        """
        with self._lock:
            return list(self._graph)

    @property
    def skipped(self) -> dict[str, str]:
        """Topics not observed, with the reason."""
        with self._lock:
            return {name: reason for name, (_, reason) in self._skipped.items()}

    # -- discovery ---------------------------------------------------------------------------
    def refresh(self) -> list[str]:
        """Follow the graph once; returns the topics added.

        Observe new topics, let go of those whose publishers left, re-subscribe topics whose
        offers need another request.
        """
        if self._closed:
            return []
        with self._refreshing:
            try:
                names_and_types = self.transport.get_topic_names_and_types()
            except Exception as exc:  # a failing graph query must not stop the owner
                self._warn(f"{self._node_name}: graph query failed", str(exc))
                return []
            priority = self._priority
            names_and_types = sorted(names_and_types, key=lambda nt: nt[0] not in priority)
            seen: set[str] = set()
            added: list[str] = []
            for topic, types in names_and_types:
                seen.add(topic)
                type_name = types[0] if types else ""
                if self._follow(topic, type_name):
                    added.append(topic)
            for topic in [t for t in list(self._entries) if t not in seen]:
                self._gone(topic)
            with self._lock:
                for topic in [t for t in self._skipped if t not in seen]:
                    del self._skipped[topic]
                self._graph = [(name, types[0] if types else "")
                               for name, types in names_and_types]
            return added

    def _follow(self, topic: str, type_name: str) -> bool:
        """One topic of a refresh; True when it started being observed."""
        entry = self._entries.get(topic)
        skipped = self._skipped.get(topic)
        if skipped is not None:
            if skipped[0] == type_name:
                return False
            with self._lock:
                self._skipped.pop(topic, None)  # its type changed: decide afresh
        offered = offered_qos_profiles(self.transport, topic)
        if entry is not None:
            if entry.topic.type_name != type_name and offered:
                self._let_go(topic)  # another type now: observe it afresh below
            elif not offered:
                entry.missing += 1
                if entry.missing >= self._grace:
                    self._let_go(topic)
                return False
            else:
                entry.missing = 0
                wanted = observing_qos(offered, self._depth)
                if not _same_request(wanted, entry.topic.qos):
                    self._resubscribe(entry, offered, wanted)
                return False
        if not offered:
            return False
        if self._select is not None and not self._select(topic, type_name):
            return False
        if self._max_topics is not None and len(self._entries) >= self._max_topics:
            self._skip(topic, type_name,
                       f"not subscribed: at most {self._max_topics} topics are observed")
            return False
        return self._observe(topic, type_name, offered)

    def _gone(self, topic: str) -> None:
        entry = self._entries.get(topic)
        if entry is not None:
            entry.missing += 1
            if entry.missing >= self._grace:
                self._let_go(topic)

    def _skip(self, topic: str, type_name: str, reason: str) -> None:
        with self._lock:
            self._skipped[topic] = (type_name, reason)
        if self._on_skipped is not None:
            self._on_skipped(topic, reason)
        else:
            self._skip_log(f"not observing '{topic}'", reason)

    def _info(self, topic: str, msg_type: type, qos: QoSProfile) -> EndpointInfo:
        return EndpointInfo(topic, msg_type, qos, self._node_name, self._node_namespace,
                            self.logger)

    def _observe(self, topic: str, type_name: str, offered: list[QoSProfile]) -> bool:
        try:
            msg_type = self._resolve(type_name)
        except (LookupError, ValueError, UnknownMessageTypeError) as exc:
            self._skip(topic, type_name, str(exc) or f"unknown message type {type_name!r}")
            return False
        qos = observing_qos(offered, self._depth)
        observed = ObservedTopic(topic, type_name, msg_type, tuple(offered), qos)
        try:
            sink = self._sink_for(observed)
        except TopicSkipped as exc:
            self._skip(topic, type_name, str(exc))
            return False
        guarded = self._guard(sink)
        try:
            endpoint = self._subscribe(self._info(topic, msg_type, qos), guarded)
        except (TopicTypeMismatchError, ValueError) as exc:
            self._skip(topic, type_name, str(exc))
            if self._on_removed is not None:
                self._on_removed(topic)
            return False
        with self._lock:
            if self._closed:
                closed = True
            else:
                closed = False
                self._entries[topic] = _Entry(observed, guarded, endpoint)
        if closed:
            endpoint.destroy()
            return False
        return True

    def _guard(self, sink: MessageSink) -> MessageSink:
        def guarded(msg: Any) -> None:
            if not self._closed:
                sink(msg)

        return guarded

    def _resubscribe(self, entry: _Entry, offered: list[QoSProfile], wanted: QoSProfile) -> None:
        """Replace a subscription whose request no longer matches every publisher."""
        old = entry.topic
        entry.endpoint.destroy()
        topic = ObservedTopic(old.name, old.type_name, old.msg_type, tuple(offered), wanted)
        try:
            endpoint = self._subscribe(self._info(old.name, old.msg_type, wanted), entry.sink)
        except (TopicTypeMismatchError, ValueError) as exc:
            self.logger.warning(f"not observing '{old.name}' any more: {exc}")
            with self._lock:
                self._entries.pop(old.name, None)
            return
        with self._lock:
            entry.topic = topic
            entry.endpoint = endpoint
        self.logger.info(f"'{old.name}': publishers changed their QoS; subscribed again "
                         f"({wanted.resolved_reliability.name.lower()}, "
                         f"{wanted.resolved_durability.name.lower()})")

    def _let_go(self, topic: str) -> None:
        with self._lock:
            entry = self._entries.pop(topic, None)
        if entry is None:
            return
        try:
            entry.endpoint.destroy()
        except Exception as exc:  # a closing transport: nothing more to do
            self.logger.debug(f"destroying the subscription of '{topic}' failed: {exc}")
        if self._on_removed is not None:
            self._on_removed(topic)

    def release(self, topic: str) -> None:
        """Stop observing ``topic`` now, as when its publishers leave.

        Its subscription is destroyed and ``on_removed`` called; a later :meth:`refresh`
        observes it again when ``select`` still wants it.
        """
        self._let_go(topic)

    # -- teardown ----------------------------------------------------------------------------
    def close(self) -> None:
        """Destroy every subscription (idempotent); sinks ignore messages still arriving."""
        with self._lock:
            self._closed = True
            entries = list(self._entries.values())
            self._entries.clear()
        for entry in entries:
            try:
                entry.endpoint.destroy()
            except Exception as exc:  # a closing transport: nothing more to do
                self.logger.debug(f"destroying a subscription failed: {exc}")

    def __enter__(self) -> TopicObserver:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
