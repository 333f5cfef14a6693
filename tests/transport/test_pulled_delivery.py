"""A SingleThreadedExecutor reading network subscriptions itself (DDS: waiting on the
middleware's wait set, as rclpy's executor; Zenoh: reading the channel after its receive
thread handed over the first sample): two contexts (two Cyclone participants, or two Zenoh
sessions on a loopback router) in one process.

Oracles: the sequence numbers a publisher in the other context wrote (every message arrives,
in order, whatever mode the subscription is in and however often it changes), the identity of
the thread that runs the callbacks (the spinning one), the executor's list of pulled sources
and, for DDS, the names of the live threads (a subscription the executor reads has no
delivery thread of its own; one in no executor, or in a MultiThreadedExecutor, has).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from typing import Any

import pytest

from _support.dds import dds_context, dds_domain, spin_until
from _support.ports import free_port
from posekit.msgs.std_msgs import String
from posekit.runtime.context import Context
from posekit.runtime.executors import MultiThreadedExecutor, SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy

pytestmark = pytest.mark.slow

KEEP_ALL = QoSProfile(depth=1000, history=HistoryPolicy.KEEP_ALL,
                      reliability=ReliabilityPolicy.RELIABLE)


class Side:
    """A context and the transport its nodes use (a name, or a ZenohTransport object)."""

    def __init__(self, context: Context, transport: Any) -> None:
        self.context, self.transport = context, transport

    def node(self, name: str) -> Node:
        return Node(name, context=self.context, transport=self.transport)


@pytest.fixture(params=["dds", "zenoh"])
def two(request: pytest.FixtureRequest,
        monkeypatch: pytest.MonkeyPatch) -> Iterator[tuple[Side, Side]]:
    if request.param == "dds":
        dds_domain(monkeypatch)
        a, b = Side(dds_context(), "dds"), Side(dds_context(), "dds")
    else:
        from posekit.transport.zenoh_session import SessionOptions
        from posekit.transport.zenoh_transport import ZenohTransport

        for var in ("ZENOH_SESSION_CONFIG_URI", "ZENOH_CONFIG_OVERRIDE", "ROS_DOMAIN_ID"):
            monkeypatch.delenv(var, raising=False)
        options = SessionOptions(router_endpoint=f"tcp/127.0.0.1:{free_port()}")
        sides = []
        for _ in range(2):
            context = Context()
            context.init()
            sides.append(Side(context, ZenohTransport(options)))
        a, b = sides
    yield a, b
    b.context.try_shutdown()
    a.context.try_shutdown()
    if not isinstance(b.transport, str):
        b.transport.close()
        a.transport.close()


def _delivery_threads(side: Side, topic: str) -> list[str]:
    """DDS: the subscription's own delivery threads (a Zenoh one keeps its receive thread)."""
    if side.transport != "dds":
        return []
    return [t.name for t in threading.enumerate() if t.name == f"posekit-dds {topic}"]


class Counter:
    """A talker in context ``a`` and a listener in context ``b`` on /count (numbers as
    ``std_msgs/String``)."""

    def __init__(self, a: Side, b: Side) -> None:
        self.talker = a.node("talker")
        self.pub = self.talker.create_publisher(String, "/count", KEEP_ALL)
        self.listener = b.node("listener")
        self.got: list[int] = []
        self.threads: set[int] = set()
        self.sub = self.listener.create_subscription(String, "/count", self._on, KEEP_ALL)
        self.sent = 0

    def _on(self, msg: String) -> None:
        self.got.append(int(msg.data))
        self.threads.add(threading.get_ident())

    def send(self, n: int = 1) -> None:
        for _ in range(n):
            self.pub.publish(String(data=str(self.sent)))
            self.sent += 1

    def matched(self, timeout: float = 10.0) -> bool:
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            if self.pub.get_subscription_count() > 0:
                return True
            time.sleep(0.01)
        return False


def test_the_spinning_thread_takes_every_sample_in_order(two: tuple[Side, Side]) -> None:
    a, b = two
    c = Counter(a, b)
    dds = b.transport == "dds"
    assert _delivery_threads(b, "/count") or not dds  # in no executor: the transport delivers
    executor = SingleThreadedExecutor(context=b.context)
    executor.add_node(c.listener)
    assert len(executor.inbox.sources) == 1
    assert not _delivery_threads(b, "/count")  # the executor reads the reader itself
    assert c.matched()
    c.send(500)
    assert spin_until(executor, lambda: len(c.got) >= 500, 20)
    assert c.got == list(range(500))
    assert c.threads == {threading.get_ident()}

    # Out of the executor: the delivery thread is back and loses nothing meanwhile.
    executor.remove_node(c.listener)
    assert executor.inbox.sources == ()
    assert _delivery_threads(b, "/count") or not dds
    c.send(50)
    deadline = time.monotonic() + 10
    while len(c.sub.queue) < 50 and time.monotonic() < deadline:
        time.sleep(0.01)
    assert [int(m.data) for _, m in c.sub.queue] == list(range(500, 550))
    executor.add_node(c.listener)  # queued ones first, then what the reader holds
    c.send(50)
    assert spin_until(executor, lambda: len(c.got) >= 600, 20)
    assert c.got == list(range(600))
    # Handed back and forth while samples flow: still every one, in order.
    for _ in range(10):
        c.send(20)
        executor.spin_once(timeout_sec=0.01)
        executor.remove_node(c.listener)
        c.send(20)
        executor.add_node(c.listener)
    assert spin_until(executor, lambda: len(c.got) >= 1000, 20)
    assert c.got == list(range(1000))
    executor.shutdown()
    assert executor.inbox.sources == ()
    assert _delivery_threads(b, "/count") or not dds  # a shut-down executor hands it back


def test_spin_wakes_for_a_sample_and_for_in_process_work(two: tuple[Side, Side]) -> None:
    """``spin()`` parked on the wait set wakes for a sample from the other participant, for a
    timer and for a task created from another thread; shutdown ends it."""
    a, b = two
    c = Counter(a, b)
    ticks: list[float] = []
    c.listener.create_timer(0.05, lambda: ticks.append(time.monotonic()))
    executor = SingleThreadedExecutor(context=b.context)
    executor.add_node(c.listener)
    assert c.matched()
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    try:
        deadline = time.monotonic() + 10
        while len(c.got) < 20 and time.monotonic() < deadline:
            c.send()
            time.sleep(0.005)
        assert c.got[:20] == list(range(20))
        assert c.threads == {spinner.ident}
        end = time.monotonic() + 5
        while len(ticks) < 3 and time.monotonic() < end:
            time.sleep(0.01)
        assert len(ticks) >= 3
        task = executor.create_task(lambda: threading.get_ident())
        end = time.monotonic() + 5
        while not task.done() and time.monotonic() < end:
            time.sleep(0.01)
        assert task.result() == spinner.ident
    finally:
        executor.shutdown()
        spinner.join(timeout=5)
    assert not spinner.is_alive()


def test_destroying_a_pulled_subscription_and_shutting_down(two: tuple[Side, Side]) -> None:
    a, b = two
    c = Counter(a, b)
    executor = SingleThreadedExecutor(context=b.context)
    executor.add_node(c.listener)
    assert c.matched()
    c.send(10)
    assert spin_until(executor, lambda: len(c.got) >= 10, 20)
    c.listener.destroy_subscription(c.sub)
    assert executor.inbox.sources == ()
    assert not _delivery_threads(b, "/count")  # destroyed: no thread comes back
    c.send(5)
    executor.spin_once(timeout_sec=0.2)
    assert len(c.got) == 10
    # A context shut down under a spinning executor ends spin() (the wait set goes away).
    c2 = b.node("again")
    c2.create_subscription(String, "/count", lambda _m: None, KEEP_ALL)
    executor.add_node(c2)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    b.context.try_shutdown()
    spinner.join(timeout=5)
    assert not spinner.is_alive()


def test_a_multithreaded_executor_leaves_delivery_to_the_transport(
        two: tuple[Side, Side]) -> None:
    a, b = two
    c = Counter(a, b)
    executor = MultiThreadedExecutor(num_threads=2, context=b.context)
    executor.add_node(c.listener)
    assert executor.inbox.sources == ()
    assert _delivery_threads(b, "/count") or b.transport != "dds"
    assert c.matched()
    c.send(20)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    try:
        end = time.monotonic() + 10
        while len(c.got) < 20 and time.monotonic() < end:
            time.sleep(0.01)
        assert sorted(c.got) == list(range(20))
    finally:
        executor.shutdown()
        spinner.join(timeout=5)
    # Moving the node to a single-threaded executor hands the reader over.
    single = SingleThreadedExecutor(context=b.context)
    single.add_node(c.listener)
    assert len(single.inbox.sources) == 1
    assert not _delivery_threads(b, "/count")
    single.shutdown()


def _dds_threads(topic: str) -> list[str]:
    return [t.name for t in threading.enumerate() if t.name == f"posekit-dds {topic}"]


def test_an_executor_shutdown_racing_a_context_shutdown(monkeypatch: pytest.MonkeyPatch) -> None:
    """DDS: the executor hands its readers back (starting delivery threads) while the context
    deletes them, from two threads at once: neither raises, and no delivery thread is left."""
    dds_domain(monkeypatch)
    for _ in range(8):
        ctx = dds_context()
        node = Node("listener", context=ctx, transport="dds")
        for i in range(4):
            node.create_subscription(String, f"/race{i}", lambda _m: None, KEEP_ALL)
        executor = SingleThreadedExecutor(context=ctx)
        executor.add_node(node)
        errors: list[BaseException] = []

        def stop_executor(executor: SingleThreadedExecutor = executor,
                          errors: list[BaseException] = errors) -> None:
            try:
                executor.shutdown()
            except BaseException as exc:
                errors.append(exc)

        racer = threading.Thread(target=stop_executor)
        racer.start()
        ctx.try_shutdown()
        racer.join(timeout=10)
        assert not racer.is_alive()
        assert errors == []
        end = time.monotonic() + 5
        while any(_dds_threads(f"/race{i}") for i in range(4)) and time.monotonic() < end:
            time.sleep(0.01)
        assert not any(_dds_threads(f"/race{i}") for i in range(4))
