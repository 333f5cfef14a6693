"""A SingleThreadedExecutor waiting in a Zenoh subscription's channel (ChannelWaiter).

Two contexts on two Zenoh sessions and a loopback router, in one process: a talker in the
first, the executor under test in the second. Oracles: the sequence numbers the talker wrote
(every message arrives, in order, however the channel changes hands), the thread that runs
the callbacks, the waiter's own record of which channel the executor is blocked in, a
wall clock for timers and wake-ups (generous bounds: "not stuck", never "fast"), and a raw
zenoh-python subscriber on the router, which must see no poke (the DELETE that wakes the
executor stays in its session).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from _support.ports import free_port
from _support.waiting import wait_for
from posekit.msgs.std_msgs import String
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy

zenoh = pytest.importorskip("zenoh")

from posekit.transport.zenoh_session import SessionOptions, WireSubscription  # noqa: E402
from posekit.transport.zenoh_transport import ZenohTransport  # noqa: E402
from posekit.transport.zenoh_wait import PROMOTE_AFTER, ChannelWaiter  # noqa: E402

pytestmark = pytest.mark.slow

KEEP_ALL = QoSProfile(depth=1000, history=HistoryPolicy.KEEP_ALL,
                      reliability=ReliabilityPolicy.RELIABLE)


class Sides:
    """The talker's context and the listener's, each with its own Zenoh session."""

    def __init__(self, endpoint: str) -> None:
        self.endpoint = endpoint
        options = SessionOptions(router_endpoint=endpoint)
        self.contexts: list[Context] = []
        self.transports: list[ZenohTransport] = []
        for _ in range(2):
            context = Context()
            context.init()
            self.contexts.append(context)
            self.transports.append(ZenohTransport(options))

    def node(self, side: int, name: str) -> Node:
        return Node(name, context=self.contexts[side], transport=self.transports[side])

    def close(self) -> None:
        for context in reversed(self.contexts):
            context.try_shutdown()
        for transport in reversed(self.transports):
            transport.close()


@pytest.fixture
def sides(monkeypatch: pytest.MonkeyPatch) -> Iterator[Sides]:
    for var in ("ZENOH_SESSION_CONFIG_URI", "ZENOH_CONFIG_OVERRIDE", "ROS_DOMAIN_ID"):
        monkeypatch.delenv(var, raising=False)
    s = Sides(f"tcp/127.0.0.1:{free_port()}")
    yield s
    s.close()


class Stream:
    """A talker on ``topic`` in context 0 and a listener subscription in context 1."""

    def __init__(self, sides: Sides, topic: str, listener: Node | None = None) -> None:
        self.talker = sides.node(0, f"talker{abs(hash(topic)) % 1000}")
        self.pub = self.talker.create_publisher(String, topic, KEEP_ALL)
        self.listener = listener or sides.node(1, "listener")
        self.got: list[int] = []
        self.threads: set[int] = set()
        self.sub = self.listener.create_subscription(String, topic, self._on, KEEP_ALL)
        self.sent = 0
        assert wait_for(lambda: self.pub.get_subscription_count() > 0, 10)

    def _on(self, msg: String) -> None:
        self.got.append(int(msg.data.split()[0]))
        self.threads.add(threading.get_ident())

    def send(self, n: int = 1) -> None:
        for _ in range(n):
            self.pub.publish(String(data=str(self.sent)))
            self.sent += 1

    @property
    def wire(self) -> WireSubscription:
        endpoint: Any = self.sub.endpoint
        return endpoint.wire  # type: ignore[no-any-return]


class Spinner:
    """``executor.spin()`` on a thread of its own; ``stop()`` shuts the executor down."""

    def __init__(self, executor: SingleThreadedExecutor) -> None:
        self.executor = executor
        self.thread = threading.Thread(target=executor.spin, daemon=True)
        self.thread.start()

    def stop(self) -> None:
        self.executor.shutdown()
        self.thread.join(timeout=5)
        assert not self.thread.is_alive()


def _waiter(executor: SingleThreadedExecutor) -> ChannelWaiter:
    waiter = executor.inbox.waiter
    assert isinstance(waiter, ChannelWaiter)
    return waiter


def _spinning(sides: Sides, stream: Stream) -> tuple[ChannelWaiter, Spinner]:
    """An executor of the listener's context with ``stream``'s listener, spinning."""
    executor = SingleThreadedExecutor(context=sides.contexts[1])
    executor.add_node(stream.listener)
    return _waiter(executor), Spinner(executor)


def test_the_executor_waits_in_the_channel_of_its_first_subscription(sides: Sides) -> None:
    stream = Stream(sides, "/count")
    executor = SingleThreadedExecutor(context=sides.contexts[1])
    executor.add_node(stream.listener)
    waiter = _waiter(executor)
    assert waiter.primary is stream.wire
    spinner = Spinner(executor)
    try:
        # The receive thread hands the channel over with the first sample; from then on,
        # while nothing arrives, the spinning thread is blocked in the channel itself.
        stream.send()
        assert wait_for(lambda: stream.got == [0], 10)
        assert wait_for(lambda: waiter.inside_of is stream.wire, 5)
        for burst in (1, 1, 200, 1, 1000):
            stream.send(burst)
            assert wait_for(lambda: len(stream.got) == stream.sent, 20)
            assert wait_for(lambda: waiter.inside_of is stream.wire, 5)
        assert stream.got == list(range(stream.sent))
        assert stream.threads == {spinner.thread.ident}
    finally:
        spinner.stop()
    assert executor.inbox.sources == ()
    assert waiter.inside_of is None


def test_a_blocked_executor_wakes_for_timers_tasks_and_other_subscriptions(
        sides: Sides, monkeypatch: pytest.MonkeyPatch) -> None:
    # /second stays a secondary here however much it gets (the promotion has its own test)
    monkeypatch.setattr("posekit.transport.zenoh_wait.PROMOTE_AFTER", 1 << 30)
    first = Stream(sides, "/first")
    second = Stream(sides, "/second", listener=first.listener)  # a secondary source
    same = Stream(sides, "/first", listener=sides.node(1, "listener2"))  # same key
    ticks: list[float] = []
    first.listener.create_timer(0.05, lambda: ticks.append(time.monotonic()))
    executor = SingleThreadedExecutor(context=sides.contexts[1])
    executor.add_node(first.listener)
    executor.add_node(same.listener)
    waiter = _waiter(executor)
    assert waiter.primary is first.wire
    spinner = Spinner(executor)
    try:
        first.send()  # hands /first's channel to the executor
        assert wait_for(lambda: len(first.got) == 1 and len(same.got) == 1, 10)
        # Timer deadlines end the wait in the channel (the helper thread's poke).
        n = len(ticks)
        assert wait_for(lambda: len(ticks) >= n + 5, 5)
        gaps = [b - a for a, b in zip(ticks[n:], ticks[n + 1:], strict=False)]
        assert all(0.02 < g < 0.5 for g in gaps), gaps
        # A secondary subscription's samples, in order, on the spinning thread.
        for _ in range(5):
            second.send(20)
            assert wait_for(lambda: len(second.got) == second.sent, 10)
        assert second.got == list(range(second.sent))
        assert second.threads == {spinner.thread.ident}
        # A task created on another thread runs on the spinning one.
        task = executor.create_task(threading.get_ident)
        assert wait_for(task.done, 5)
        assert task.result() == spinner.thread.ident
        # Two subscriptions of one key in one executor: pokes for the one do not wake the
        # other in a loop. With only the timer left, pokes follow the ticks (20 a second).
        assert wait_for(lambda: waiter.inside_of is first.wire, 5)
        pokes = _count_pokes(sides, 1.0)
        assert pokes <= 40, pokes
        first.send(50)
        assert wait_for(lambda: len(first.got) == 51 and len(same.got) == 51, 10)
        assert first.got == list(range(51))
        assert same.got == list(range(51))
    finally:
        spinner.stop()


def _one_at_a_time(stream: Stream, n: int, until: Callable[[], bool] | None = None) -> int:
    """Send ``n`` messages, each after the previous was delivered (each wakes the executor
    on its own); stop early once ``until()`` is true. How many were sent."""
    for i in range(n):
        stream.send()
        assert wait_for(lambda: len(stream.got) == stream.sent, 10)
        if until is not None and until():
            return i + 1
    return n


def test_the_subscription_the_samples_come_on_becomes_the_primary(sides: Sides) -> None:
    # The first subscription is the primary. Samples on another cost two wake-ups each (its
    # receive thread, then the executor): after PROMOTE_AFTER of them with nothing on the
    # primary, that one becomes the primary, and back when the traffic moves back.
    quiet = Stream(sides, "/quiet")
    busy = Stream(sides, "/busy", listener=quiet.listener)
    waiter, spinner = _spinning(sides, quiet)
    try:
        assert waiter.primary is quiet.wire
        for stream in (busy, quiet, busy):
            sent = _one_at_a_time(stream, 3 * PROMOTE_AFTER,
                                  until=lambda s=stream: waiter.primary is s.wire)
            assert waiter.primary is stream.wire
            assert sent <= 2 * PROMOTE_AFTER, sent  # (earlier hand-overs may count too)
            # its receive thread hands the channel over with the next sample; from then on
            # the executor waits in that channel, and nothing is lost or reordered
            _one_at_a_time(stream, 1)
            assert wait_for(lambda s=stream: waiter.inside_of is s.wire, 5)
            stream.send(300)
            quiet.send(20)
            assert wait_for(lambda: len(busy.got) == busy.sent
                            and len(quiet.got) == quiet.sent, 20)
        # Traffic on both: every sample of the primary resets the count, so one sample on
        # each in turn never moves the primary back and forth.
        for _ in range(2 * PROMOTE_AFTER):
            _one_at_a_time(quiet, 1)
            _one_at_a_time(busy, 1)
        assert waiter.primary is busy.wire
        assert busy.got == list(range(busy.sent))
        assert quiet.got == list(range(quiet.sent))
        assert busy.threads | quiet.threads == {spinner.thread.ident}
    finally:
        spinner.stop()
    assert waiter.inside_of is None


def test_promotions_racing_the_node_leaving_and_joining(
        sides: Sides, monkeypatch: pytest.MonkeyPatch) -> None:
    # Promotions every few samples (PROMOTE_AFTER 2) while another thread moves the node
    # out of the executor and back, often while the executor is in a channel that has just
    # delivered: every sample of both topics arrives once, in order.
    monkeypatch.setattr("posekit.transport.zenoh_wait.PROMOTE_AFTER", 2)
    quiet = Stream(sides, "/quiet")
    busy = Stream(sides, "/busy", listener=quiet.listener)
    _, spinner = _spinning(sides, quiet)
    executor = spinner.executor
    stop = threading.Event()

    def churn() -> None:
        while not stop.is_set():
            executor.remove_node(quiet.listener)
            time.sleep(0.002)
            executor.add_node(quiet.listener)
            time.sleep(0.005)

    mover = threading.Thread(target=churn, daemon=True)
    mover.start()
    try:
        for round_ in range(30):
            stream = busy if round_ % 3 else quiet
            for _ in range(5):
                stream.send()
                time.sleep(0.001)  # mostly one sample per wake-up: hand-overs count up
            (quiet if stream is busy else busy).send(3)
    finally:
        stop.set()
        mover.join(timeout=5)
    try:
        assert not mover.is_alive()
        assert wait_for(lambda: len(busy.got) == busy.sent and len(quiet.got) == quiet.sent,
                        20), (len(busy.got), busy.sent, len(quiet.got), quiet.sent)
        assert busy.got == list(range(busy.sent))
        assert quiet.got == list(range(quiet.sent))
        assert busy.wire.lost == quiet.wire.lost == {}  # no sample went missing on the way
        assert busy.threads | quiet.threads == {spinner.thread.ident}
        waiter = _waiter(executor)  # (the node left and joined: maybe a new waiter)
        assert waiter.primary in (quiet.wire, busy.wire)
        busy.send(40)
        assert wait_for(lambda: len(busy.got) == busy.sent, 10)
        assert busy.got == list(range(busy.sent))
    finally:
        spinner.stop()


def _count_pokes(sides: Sides, seconds: float) -> int:
    """How many pokes the listener's session sends in ``seconds`` (counted at the source)."""
    counted = [0]
    original = WireSubscription.poke

    def counting(self: WireSubscription) -> None:
        counted[0] += 1
        original(self)

    WireSubscription.poke = counting  # type: ignore[method-assign]
    try:
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            time.sleep(0.01)
    finally:
        WireSubscription.poke = original  # type: ignore[method-assign]
    return counted[0]


def test_pokes_never_leave_the_session(sides: Sides) -> None:
    """A raw zenoh subscriber on the router sees the talker's samples but no DELETE."""
    from posekit.transport.zenoh_session import build_peer_config

    raw = zenoh.open(build_peer_config(SessionOptions(router_endpoint=sides.endpoint)))
    kinds: list[Any] = []
    raw_sub = raw.declare_subscriber("**", lambda s: kinds.append(s.kind))
    try:
        stream = Stream(sides, "/count")
        stream.listener.create_timer(0.01, lambda: None)  # a poke every 10 ms
        waiter, spinner = _spinning(sides, stream)
        try:
            stream.send()
            assert wait_for(lambda: stream.got == [0], 10)
            assert wait_for(lambda: waiter.inside_of is stream.wire, 5)
            assert _count_pokes(sides, 0.5) >= 10  # the executor was poked meanwhile
            stream.send(10)
            assert wait_for(lambda: len(stream.got) == 11, 10)
            assert wait_for(lambda: kinds.count(zenoh.SampleKind.PUT) >= 11, 10)
        finally:
            spinner.stop()
        assert zenoh.SampleKind.DELETE not in kinds
    finally:
        raw_sub.undeclare()
        raw.close()


def test_release_and_destroy_while_the_executor_is_in_the_channel(sides: Sides) -> None:
    stream = Stream(sides, "/count")
    waiter, spinner = _spinning(sides, stream)
    executor = spinner.executor
    try:
        stream.send(10)
        assert wait_for(lambda: len(stream.got) == 10, 10)
        assert wait_for(lambda: waiter.inside_of is stream.wire, 5)
        # Removing the node from another thread: the executor leaves the channel and the
        # receive thread takes over; what arrives meanwhile waits in the queue, in order.
        executor.remove_node(stream.listener)
        assert wait_for(lambda: waiter.inside_of is None, 5)
        assert executor.inbox.sources == ()
        stream.send(50)
        assert wait_for(lambda: len(stream.sub.queue) == 50, 10)
        assert [int(m.data) for _, m in stream.sub.queue] == list(range(10, 60))
        executor.add_node(stream.listener)
        stream.send(10)
        assert wait_for(lambda: len(stream.got) == 70, 10)
        assert stream.got == list(range(70))
        # Destroying the subscription while the executor is blocked in its channel: the
        # executor moves on (a timer created afterwards still runs), the callback is not
        # called again.
        waiter = _waiter(executor)
        assert wait_for(lambda: waiter.inside_of is stream.wire, 5)
        stream.listener.destroy_subscription(stream.sub)
        assert wait_for(lambda: waiter.inside_of is None, 5)
        ticked = threading.Event()
        stream.listener.create_timer(0.01, ticked.set)
        assert ticked.wait(5)
        stream.send(5)
        assert not wait_for(lambda: len(stream.got) > 70, 0.3)
        # A new subscription on the topic becomes the next primary and gets what follows.
        again = Stream(sides, "/count", listener=sides.node(1, "again"))
        executor.add_node(again.listener)
        again.send(20)  # from a second talker, numbered from 0
        assert wait_for(lambda: again.got == list(range(20)), 10)
    finally:
        spinner.stop()


def test_closing_the_session_under_a_blocked_executor(sides: Sides) -> None:
    stream = Stream(sides, "/count")
    waiter, spinner = _spinning(sides, stream)
    stream.send()
    assert wait_for(lambda: waiter.inside_of is stream.wire, 10)
    sides.transports[1].close()  # waits for the executor to leave the closed channel
    assert waiter.inside_of is None
    ticked = threading.Event()
    stream.listener.create_timer(0.01, ticked.set)
    assert ticked.wait(5)  # the executor goes on (timers, tasks) without the channel
    spinner.stop()


def test_large_messages_are_taken_a_few_at_a_time(sides: Sides) -> None:
    """A look at a channel of 100 KB messages takes about 256 KB of them (their callbacks
    then run while the payloads are still in cache), never fewer than one, and every one
    arrives in order over the looks."""
    from posekit.runtime.inbox import Inbox

    stream = Stream(sides, "/big")
    inbox = Inbox()
    assert stream.wire.pull_into(inbox)  # the subscription's node is in no executor
    pad = "x" * 100_000
    for i in range(10):
        stream.pub.publish(String(data=f"{i} {pad}"))
    assert wait_for(stream.wire.pending, 10)  # the receive thread handed over
    looks = []
    deadline = time.monotonic() + 10
    while sum(looks) < 10 and time.monotonic() < deadline:
        n = stream.wire.pull(64)
        if n:
            looks.append(n)
    assert sum(looks) == 10
    assert max(looks) <= 4, looks  # 3 x 100 KB reach the 256 KB budget
    assert [int(m.data.split()[0]) for _, m in stream.sub.queue] == list(range(10))
    stream.wire.release_pull(inbox)


def test_a_sample_whose_handling_fails_is_dropped_and_the_look_goes_on(
    sides: Sides, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The last line of defence in the executor's look: a sample whose handling raises
    where it never should is dropped and counted as "internal"; the samples after it in the
    same look still arrive, in order."""
    from posekit.runtime.inbox import Inbox

    stream = Stream(sides, "/faulty")
    wire = stream.wire
    inbox = Inbox()
    assert wire.pull_into(inbox)
    handle = wire._handle
    calls = [0]

    def faulty(sample: Any) -> None:
        calls[0] += 1
        if calls[0] == 3:
            raise RuntimeError("broken")
        handle(sample)

    monkeypatch.setattr(wire, "_handle", faulty)
    stream.send(6)
    assert wait_for(wire.pending, 10)
    handled = 0
    deadline = time.monotonic() + 10
    while handled < 6 and time.monotonic() < deadline:
        handled += wire.pull(64)
    assert handled == 6
    assert [int(m.data) for _, m in stream.sub.queue] == [0, 1, 3, 4, 5]
    assert wire.dropped["internal"] == 1
    wire.release_pull(inbox)


def _helper_threads() -> list[threading.Thread]:
    return [t for t in threading.enumerate() if t.name == "posekit-zenoh wait"]


def test_a_service_request_wakes_the_executor_in_the_channel_from_zenohs_thread(
    sides: Sides,
) -> None:
    """A request (or a response) reaches the executor through zenoh's own thread, which
    holds no posekit lock: it pokes the executor's channel at once, as a subscription's
    receive thread does, so the waiter's helper thread is never started for it."""
    from posekit.msgs.std_srvs import SetBool

    stream = Stream(sides, "/busy")
    stream.listener.create_service(
        SetBool, "/flip", lambda q, r: SetBool.Response(success=not q.data, message="ok")
    )
    client = sides.node(0, "caller").create_client(SetBool, "/flip")
    assert client.wait_for_service(timeout_sec=10)
    waiter, spinner = _spinning(sides, stream)
    try:
        stream.send()
        assert wait_for(lambda: waiter.inside_of is stream.wire, 10)
        assert wait_for(lambda: not _helper_threads(), 5)  # (none left by the set-up)
        answers = [client.call(SetBool.Request(data=i % 2 == 0), timeout_sec=10)
                   for i in range(5)]
        assert [(a.success, a.message) for a in answers] == [
            (i % 2 == 1, "ok") for i in range(5)
        ]
        assert not _helper_threads()
        assert wait_for(lambda: waiter.inside_of is stream.wire, 5)  # waiting there again
    finally:
        spinner.stop()
