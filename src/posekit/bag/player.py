"""Playing a rosbag2 directory back onto topics, on the bag's own time line.

Time: the player's clock *is* the bag's timestamps. A message recorded at bag time ``t`` is
published when the clock reads ``t``, and ``/clock`` carries that time, so nodes with
``use_sim_time`` (tf2 listeners, the viewer) see header stamps and clock agree as in the
recorded run. Two ways to drive it:

* :meth:`Player.run_simulated` steps a :class:`~posekit.runtime.SimulatedTimeExecutor`
  (which publishes ``/clock`` when its nodes are visible to other processes): it jumps the
  executor to the bag's start, then runs it to each message's time and publishes the
  message there, so subscribers' callbacks, timers and tf
  lookups happen at exactly the recorded times, deterministically and as fast as the CPU
  allows (``paced=True`` follows the wall clock at ``rate``).
* :meth:`Player.play` follows the wall clock (``ros2 bag play``): messages go out when
  ``(bag time - start) / rate`` wall seconds have passed, ``/clock`` is published by the
  player at ``clock_frequency`` Hz (and at each message's time), other nodes run in the
  given executor meanwhile.

Damaged bags: storage that cannot be read raises :class:`BagFormatError`. Damage the reader
does not notice (a chunk index pointing elsewhere, a lost chunk) shows as fewer messages
than ``metadata.yaml`` lists: after each pass the player compares what it read with those
counts, logs the shortfall once as an error and adds it to :attr:`Player.missing`;
``posekit bag play`` then exits with 1 and a one-line reason. (``ros2 bag play`` has no such
check and ends silently; posekit says so because a short replay looks like a valid one.)

``loop`` restarts from the beginning after the last message; the clock then jumps back (tf2
listeners clear their buffers, as under ROS 2). Recorded ``/clock`` messages are not
re-published while the player provides the clock. Publisher QoS comes from the recorded
offers (:func:`posekit.bag._qos.playback_qos`): ``/tf_static`` is published transient-local
with enough depth to latch every recorded static message.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Collection, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from types import TracebackType
from typing import Any

from posekit.bag._qos import from_rosbags_qos, playback_qos
from posekit.bag._storage import open_reader
from posekit.bag.errors import BagFormatError, BagOptionError
from posekit.bag.info import SERVICE_EVENT_SUFFIX, is_service_event_topic
from posekit.bag.reader import BagMessage, read_messages
from posekit.runtime.context import Context
from posekit.runtime.executors import Executor
from posekit.runtime.node import Node
from posekit.runtime.qos import QoSProfile
from posekit.runtime.sim_executor import SimulatedTimeExecutor

__all__ = ["PlaybackTopic", "Player"]

_CLOCK_TOPIC = "/clock"


@dataclass(frozen=True)
class PlaybackTopic:
    """A topic the player publishes: name, ROS type, message count and publisher QoS."""

    name: str
    msgtype: str
    message_count: int
    qos: QoSProfile


#: ``service_requests_source`` -> the ServiceEventInfo event type holding the request.
_REQUEST_EVENTS = {"service_introspection": 1, "client_introspection": 0}


def _service_class(event_type: str) -> type[Any]:
    from posekit.msgs.errors import UnknownMessageTypeError
    from posekit.msgs.registry import get_service_class

    try:
        return get_service_class(event_type.removesuffix("_Event"))
    except UnknownMessageTypeError:
        raise BagFormatError(f"service type {event_type.removesuffix('_Event')!r} is not one "
                             "posekit can call") from None


def _message_class(msgtype: str) -> type[Any]:
    from posekit.msgs.cdr import get_typestore
    from posekit.msgs.errors import UnknownMessageTypeError
    from posekit.msgs.registry import get_message_class

    try:
        return get_message_class(msgtype)
    except UnknownMessageTypeError:
        pass
    store = get_typestore()
    cls = store.types.get(msgtype) if msgtype in store.fielddefs else None
    if not isinstance(cls, type):
        raise BagFormatError(f"message type {msgtype!r} is not a ROS 2 Jazzy type posekit knows")
    return cls


class Player:
    """Publishes a recorded bag (see the module docstring).

    Args:
        bag: rosbag2 directory.
        context: context of the player node (default: the default context).
        topics: only these topics (default: all recorded ones).
        rate: playback speed factor (> 0); 2.0 plays twice as fast.
        loop: start over after the last message (until stopped).
        publish_clock: publish ``/clock`` in :meth:`play` (in :meth:`run_simulated` the
            executor publishes it).
        clock_frequency: ``/clock`` messages per wall second in :meth:`play`.
        start_offset: start this many seconds of bag time after the first message.
        start_paused: :meth:`play` starts paused (:meth:`resume`, :meth:`play_next`).
        remap: recorded topic -> topic to publish on (``--remap old:=new``).
        delay: wall seconds to wait before each pass in :meth:`play`.
        node_name: name of the player node.
        transport: transport name for the node (default: the context's).
        publish_service_requests: instead of publishing a recorded service's events on its
            ``<service>/_service_event`` topic, call the service with each recorded request
            (``ros2 bag play --publish-service-requests``); responses are not waited for.
        service_requests_source: which recorded events hold the requests to send:
            ``"service_introspection"`` (the servers' REQUEST_RECEIVED events, default) or
            ``"client_introspection"`` (the clients' REQUEST_SENT events).

    Raises:
        BagNotFoundError, BagFormatError: the bag is missing or unreadable.
        BagOptionError: bad rate, clock frequency or topic.
    """

    def __init__(
        self,
        bag: str | Path,
        *,
        context: Context | None = None,
        topics: Collection[str] | None = None,
        rate: float = 1.0,
        loop: bool = False,
        publish_clock: bool = True,
        clock_frequency: float = 100.0,
        node_name: str = "rosbag2_player",
        transport: str | None = None,
        start_offset: float = 0.0,
        start_paused: bool = False,
        remap: Mapping[str, str] | None = None,
        delay: float = 0.0,
        publish_service_requests: bool = False,
        service_requests_source: str = "service_introspection",
    ) -> None:
        if service_requests_source not in _REQUEST_EVENTS:
            raise BagOptionError(
                f"service_requests_source must be one of {sorted(_REQUEST_EVENTS)}, got "
                f"{service_requests_source!r}")
        self._request_event = _REQUEST_EVENTS[service_requests_source]
        self._request_side = service_requests_source.split("_")[0]
        if not rate > 0:
            raise BagOptionError(f"playback rate must be > 0, got {rate}")
        if not (start_offset >= 0 and delay >= 0):
            raise BagOptionError(
                f"start offset and delay must be >= 0 s, got {start_offset} and {delay}")
        self.start_offset_ns = int(start_offset * 1e9)
        self.delay = float(delay)
        self._paused = bool(start_paused)
        self._steps = 0
        self._control = threading.Lock()
        if publish_clock and not clock_frequency > 0:
            raise BagOptionError(f"clock frequency must be > 0 Hz, got {clock_frequency}")
        self.path = Path(bag)
        self.rate = float(rate)
        self.loop = bool(loop)
        self.publish_clock = publish_clock
        self.clock_frequency = float(clock_frequency)
        with open_reader(self.path) as reader:
            self.start_ns = int(reader.start_time) if reader.message_count else 0
            self.end_ns = int(reader.end_time) - 1 if reader.message_count else 0
            recorded: dict[str, PlaybackTopic] = {}
            for conn in reader.connections:
                offered = [from_rosbags_qos(q) for q in conn.ext.offered_qos_profiles]
                previous = recorded.get(conn.topic)
                count = conn.msgcount + (previous.message_count if previous else 0)
                recorded[conn.topic] = PlaybackTopic(
                    conn.topic, conn.msgtype, count, playback_qos(offered, count)
                )
        wanted = set(topics) if topics else None
        if wanted is not None and (unknown := sorted(wanted - set(recorded))):
            raise BagOptionError(
                f"topics {unknown} are not in bag {str(self.path)!r}; it has {sorted(recorded)}"
            )
        #: Topics this player publishes.
        self.topics: dict[str, PlaybackTopic] = {
            name: info
            for name, info in recorded.items()
            if (wanted is None or name in wanted)
            and not (name == _CLOCK_TOPIC and publish_clock and wanted is None)
        }
        requests = {name for name, info in self.topics.items()
                    if publish_service_requests and is_service_event_topic(name, info.msgtype)}
        classes = {name: _message_class(info.msgtype) for name, info in self.topics.items()
                   if name not in requests}
        services = {name: _service_class(self.topics[name].msgtype) for name in requests}
        self.node = Node(node_name, context=context, transport=transport)
        remap = dict(remap or {})
        if unknown := sorted(set(remap) - set(classes)):
            self.node.destroy_node()
            raise BagOptionError(f"cannot remap {unknown}: not published from this bag")
        self._publishers: dict[str, Any] = {
            name: self.node.create_publisher(classes[name], remap.get(name, name),
                                             self.topics[name].qos)
            for name in classes
        }
        #: Service clients replaying recorded requests, by service event topic.
        self._clients: dict[str, Any] = {
            name: self.node.create_client(srv, name.removesuffix(SERVICE_EVENT_SUFFIX))
            for name, srv in services.items()
        }
        #: Recorded requests sent to services (``publish_service_requests``).
        self.requests_sent = 0
        self._clock_pub: Any = None
        #: Messages published so far.
        self.published = 0
        #: Recorded messages that could not be decoded (each logged, then skipped).
        self.skipped = 0
        #: Completed passes over the bag.
        self.loops_done = 0
        #: Messages metadata.yaml lists for the played topics (one pass).
        self.expected = sum(info.message_count for info in self.topics.values())
        #: Messages listed but not found in the storage, summed over passes (see the module
        #: docstring); non-zero means the bag is damaged.
        self.missing = 0
        self._stopped = False

    # -- common -----------------------------------------------------------------------
    @property
    def duration_ns(self) -> int:
        """Bag time between the first and the last message (ns)."""
        return self.end_ns - self.start_ns

    def messages(self) -> Iterator[BagMessage]:
        """The messages this player publishes, in bag-time order (one pass)."""
        return read_messages(self.path, list(self.topics))

    def _pass_messages(self) -> Iterator[BagMessage]:
        """:meth:`messages`, checking at the end of a full pass that none were missing."""
        read = 0
        for message in self.messages():
            read += 1
            yield message
        if read < self.expected:
            self.missing += self.expected - read
            self.node.get_logger().error(
                f"bag {str(self.path)!r} is damaged: read {read} of the {self.expected} "
                "messages its metadata lists for the played topics"
            )

    def _publish(self, message: BagMessage) -> None:
        from posekit.msgs.errors import MessageError

        try:
            msg = message.decode()
        except MessageError as exc:  # a damaged record: skip it, keep playing
            self.skipped += 1
            self.node.get_logger().error(
                f"skipped the message on '{message.topic}' at {message.timestamp_ns} ns: {exc}"
            )
            return
        client = self._clients.get(message.topic)
        if client is None:
            self._publishers[message.topic].publish(msg)
            self.published += 1
        else:
            self._send_request(client, msg)

    def _send_request(self, client: Any, event: Any) -> None:
        """Call the service with a recorded request event's request (rosbag2's checks)."""
        if int(event.info.event_type) != self._request_event:
            return  # responses, and the other side's requests, are not replayed
        logger = self.node.get_logger()
        if not client.service_is_ready():
            logger.warning(f"Service request hasn't been sent. The '{client.service_name}' "
                           "service isn't ready !", throttle_duration_sec=5.0)
            return
        if not len(event.request):
            logger.warning(f"Can't send service request. The configuration of introspection "
                           f"for '{client.service_name}' was metadata only on "
                           f"{self._request_side} side!", throttle_duration_sec=5.0)
            return
        client.call_async(event.request[0])
        self.requests_sent += 1

    def stop(self) -> None:
        """Make :meth:`play` / :meth:`run_simulated` return before the next message."""
        self._stopped = True

    # -- controls (``ros2 bag play``'s keyboard: pause/resume, next message, rate) ------
    @property
    def paused(self) -> bool:
        """True while :meth:`play` holds the bag time still."""
        return self._paused

    def pause(self) -> None:
        """Hold playback (the clock keeps publishing the paused time)."""
        with self._control:
            self._paused = True

    def resume(self) -> None:
        """Continue playback from where it was paused."""
        with self._control:
            self._paused = False

    def toggle_pause(self) -> bool:
        """Pause if playing, resume if paused; returns the new paused state."""
        with self._control:
            self._paused = not self._paused
            return self._paused

    def play_next(self) -> bool:
        """While paused, publish the next message now; False (nothing done) when playing."""
        with self._control:
            if not self._paused:
                return False
            self._steps += 1
            return True

    def set_rate(self, rate: float) -> None:
        """Change the playback speed factor (> 0) from now on."""
        if not rate > 0:
            raise BagOptionError(f"playback rate must be > 0, got {rate}")
        with self._control:
            self.rate = float(rate)

    def _passes(self, loops: int | None) -> Iterator[int]:
        if loops is not None and loops < 1:
            raise BagOptionError(f"loops must be >= 1, got {loops}")
        count = loops if loops is not None else (None if self.loop else 1)
        index = 0
        while (count is None or index < count) and not self._stopped:
            yield index
            index += 1

    # -- simulated time ---------------------------------------------------------------
    def run_simulated(self, executor: SimulatedTimeExecutor, *, loops: int | None = None,
                      paced: bool = False) -> int:
        """Play by stepping ``executor`` to each message's bag time (deterministic).

        The player node joins ``executor``; the executor jumps to the bag's first timestamp
        (backwards if needed) and ends at the last one. ``loops`` passes over the bag
        (default: 1, or forever with ``loop``); ``paced`` runs at ``rate`` x real time instead
        of as fast as possible. Returns the number of messages published.
        """
        if not isinstance(executor, SimulatedTimeExecutor):
            raise BagOptionError("run_simulated needs a SimulatedTimeExecutor; use play()")
        executor.add_node(self.node)
        saved_factor = executor.real_time_factor
        if paced:
            executor.real_time_factor = self.rate
        before = self.published
        try:
            for _ in self._passes(loops):
                executor.set_time(_ns_time(self.start_ns))
                for message in self._pass_messages():
                    if self._stopped or not executor.context.ok():
                        break
                    if message.timestamp_ns > executor.now_ns:
                        executor.run_until(_ns_time(message.timestamp_ns))
                    self._publish(message)
                executor.run_until(_ns_time(max(executor.now_ns, self.end_ns)))
                self.loops_done += 1
        finally:
            executor.real_time_factor = saved_factor
        return self.published - before

    # -- wall clock -------------------------------------------------------------------
    def play(self, executor: Executor | None = None, *, loops: int | None = None,
             sleep: Callable[[float], None] = time.sleep,
             progress: Callable[[int, bool], None] | None = None) -> int:
        """Play in wall-clock time at ``rate`` (``ros2 bag play``); returns messages published.

        ``executor`` (if given) runs other nodes' callbacks while the player waits; the
        player node is added to it. ``loops`` as in :meth:`run_simulated`. Playback follows
        :meth:`pause`, :meth:`resume`, :meth:`play_next` and :meth:`set_rate` from other
        threads; ``progress(bag_time_ns, paused)`` is called while waiting (for a display).
        """
        from posekit.msgs.rosgraph_msgs import Clock as ClockMsg

        if executor is not None:
            executor.add_node(self.node)
        if self.publish_clock and self._clock_pub is None:
            self._clock_pub = self.node.create_publisher(
                ClockMsg, _CLOCK_TOPIC, QoSProfile(depth=1)
            )
        before = self.published
        period = 1.0 / self.clock_frequency

        def wait(seconds: float) -> None:
            if executor is not None:
                executor.spin_once(timeout_sec=max(0.0, seconds))
            else:
                sleep(max(0.0, seconds))

        for _ in self._passes(loops):
            end_delay = time.monotonic() + self.delay
            while not self._stopped and (left := end_delay - time.monotonic()) > 0:
                wait(left)
            origin = self.start_ns + self.start_offset_ns
            clock = _BagClock(time.monotonic(), origin, self.rate, self._paused)
            next_clock = clock.wall
            for message in self._pass_messages():
                if message.timestamp_ns < origin:
                    continue
                next_clock = self._wait_until_due(
                    message.timestamp_ns, clock, next_clock, period, wait, progress)
                if self._stopped:
                    break
                if self._clock_pub is not None:
                    self._send_clock(message.timestamp_ns)
                self._publish(message)
            if executor is not None:
                executor.spin_some()
            self.loops_done += 1
        return self.published - before

    def _wait_until_due(self, stamp_ns: int, clock: _BagClock, next_clock: float,
                        period: float, wait: Callable[[float], None],
                        progress: Callable[[int, bool], None] | None) -> float:
        """Wait until the bag clock reaches ``stamp_ns`` (pause, step and rate changes from
        other threads honoured), sending ``/clock`` every ``period`` s of wall time on the
        way; returns the wall time of the next ``/clock``."""
        while not self._stopped:
            now = time.monotonic()
            with self._control:
                paused, rate, step = self._paused, self.rate, self._steps > 0
                if step:
                    self._steps -= 1
            bag_now = clock.at(now, paused, rate)
            if progress is not None:
                progress(min(bag_now, stamp_ns), paused)
            if self._clock_pub is not None and now >= next_clock:
                self._send_clock(min(bag_now, stamp_ns))
                next_clock = now + period
            if step:  # play_next: this message now, and the clock continues from it
                clock.bag, clock.wall = stamp_ns, now
                return next_clock
            if not paused and bag_now >= stamp_ns:
                return next_clock
            timeout = 0.05 if paused else (stamp_ns - bag_now) / 1e9 / rate
            if self._clock_pub is not None:
                timeout = min(timeout, max(0.0, next_clock - now))
            wait(min(timeout, 0.05) if progress is not None else timeout)
        return next_clock

    def _send_clock(self, ns: int) -> None:
        from posekit.msgs.rosgraph_msgs import Clock as ClockMsg

        msg = ClockMsg()
        msg.clock.sec, msg.clock.nanosec = divmod(int(ns), 1_000_000_000)
        self._clock_pub.publish(msg)

    # -- lifetime ---------------------------------------------------------------------
    def close(self) -> None:
        """Destroy the player node."""
        self._stopped = True
        self.node.destroy_node()

    def __enter__(self) -> Player:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()


class _BagClock:
    """Bag time (ns) during wall-clock playback: ``bag + (wall_now - wall) * rate * 1e9``.

    Paused, it stands still; a pause, a resume or a new rate re-anchors it at the current
    bag time, so none of them makes the bag time jump.
    """

    def __init__(self, wall: float, bag: int, rate: float, paused: bool = False) -> None:
        self.wall, self.bag, self.rate, self.paused = wall, bag, rate, paused

    def at(self, wall_now: float, paused: bool, rate: float) -> int:
        """The bag time at monotonic wall time ``wall_now`` (s) under ``paused``/``rate``."""
        if (paused, rate) != (self.paused, self.rate):
            self.bag = self._time(wall_now)
            self.wall, self.paused, self.rate = wall_now, paused, rate
        return self._time(wall_now)

    def _time(self, wall_now: float) -> int:
        if self.paused:
            return self.bag
        return self.bag + int((wall_now - self.wall) * self.rate * 1e9)


def _ns_time(ns: int) -> Any:
    from posekit.time import Time

    return Time(nanoseconds=int(ns))
