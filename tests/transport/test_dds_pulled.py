"""A SingleThreadedExecutor reading DDS subscriptions itself, as rclpy's executor waits on
the middleware's wait set: two contexts (two Cyclone participants) in one process.

Oracles: the sequence numbers a publisher in the other participant wrote (every message
arrives, in order, whatever mode the subscription is in), the identity of the thread that
runs the callbacks (the spinning one) and the names of the live threads (a subscription the
executor reads has no delivery thread of its own; one in no executor, or in a
MultiThreadedExecutor, has).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator

import pytest

from _support.dds import dds_context, dds_domain, spin_until
from posekit.msgs.std_msgs import String
from posekit.runtime.context import Context
from posekit.runtime.executors import MultiThreadedExecutor, SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy

pytestmark = pytest.mark.slow

KEEP_ALL = QoSProfile(depth=1000, history=HistoryPolicy.KEEP_ALL,
                      reliability=ReliabilityPolicy.RELIABLE)


@pytest.fixture
def two(monkeypatch: pytest.MonkeyPatch) -> Iterator[tuple[Context, Context]]:
    dds_domain(monkeypatch)
    a, b = dds_context(), dds_context()
    yield a, b
    b.try_shutdown()
    a.try_shutdown()


def _delivery_threads(topic: str) -> list[str]:
    return [t.name for t in threading.enumerate() if t.name == f"posekit-dds {topic}"]


class Counter:
    """A talker in context ``a`` and a listener in context ``b`` on /count (numbers as
    ``std_msgs/String``)."""

    def __init__(self, a: Context, b: Context) -> None:
        self.talker = Node("talker", context=a, transport="dds")
        self.pub = self.talker.create_publisher(String, "/count", KEEP_ALL)
        self.listener = Node("listener", context=b, transport="dds")
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


def test_the_spinning_thread_takes_every_sample_in_order(two: tuple[Context, Context]) -> None:
    a, b = two
    c = Counter(a, b)
    assert _delivery_threads("/count")  # in no executor: the transport delivers
    executor = SingleThreadedExecutor(context=b)
    executor.add_node(c.listener)
    assert c.sub.endpoint in executor.inbox.sources
    assert not _delivery_threads("/count")  # the executor reads the reader itself
    assert c.matched()
    c.send(500)
    assert spin_until(executor, lambda: len(c.got) >= 500, 20)
    assert c.got == list(range(500))
    assert c.threads == {threading.get_ident()}

    # Out of the executor: the delivery thread is back and loses nothing meanwhile.
    executor.remove_node(c.listener)
    assert executor.inbox.sources == ()
    assert _delivery_threads("/count")
    c.send(50)
    deadline = time.monotonic() + 10
    while len(c.sub.queue) < 50 and time.monotonic() < deadline:
        time.sleep(0.01)
    assert [int(m.data) for _, m in c.sub.queue] == list(range(500, 550))
    executor.add_node(c.listener)  # queued ones first, then what the reader holds
    c.send(50)
    assert spin_until(executor, lambda: len(c.got) >= 600, 20)
    assert c.got == list(range(600))
    executor.shutdown()
    assert _delivery_threads("/count")  # a shut-down executor hands the reader back


def test_spin_wakes_for_a_sample_and_for_in_process_work(two: tuple[Context, Context]) -> None:
    """``spin()`` parked on the wait set wakes for a sample from the other participant, for a
    timer and for a task created from another thread; shutdown ends it."""
    a, b = two
    c = Counter(a, b)
    ticks: list[float] = []
    c.listener.create_timer(0.05, lambda: ticks.append(time.monotonic()))
    executor = SingleThreadedExecutor(context=b)
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


def test_destroying_a_pulled_subscription_and_shutting_down(two: tuple[Context, Context]) -> None:
    a, b = two
    c = Counter(a, b)
    executor = SingleThreadedExecutor(context=b)
    executor.add_node(c.listener)
    assert c.matched()
    c.send(10)
    assert spin_until(executor, lambda: len(c.got) >= 10, 20)
    endpoint = c.sub.endpoint
    c.listener.destroy_subscription(c.sub)
    assert endpoint not in executor.inbox.sources
    assert not _delivery_threads("/count")  # destroyed: no thread comes back
    c.send(5)
    executor.spin_once(timeout_sec=0.2)
    assert len(c.got) == 10
    # A context shut down under a spinning executor ends spin() (the wait set goes away).
    c2 = Node("again", context=b, transport="dds")
    c2.create_subscription(String, "/count", lambda _m: None, KEEP_ALL)
    executor.add_node(c2)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    b.try_shutdown()
    spinner.join(timeout=5)
    assert not spinner.is_alive()


def test_a_multithreaded_executor_leaves_delivery_to_the_transport(
        two: tuple[Context, Context]) -> None:
    a, b = two
    c = Counter(a, b)
    executor = MultiThreadedExecutor(num_threads=2, context=b)
    executor.add_node(c.listener)
    assert executor.inbox.sources == ()
    assert _delivery_threads("/count")
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
    single = SingleThreadedExecutor(context=b)
    single.add_node(c.listener)
    assert c.sub.endpoint in single.inbox.sources
    assert not _delivery_threads("/count")
    single.shutdown()


def test_an_executor_shutdown_racing_a_context_shutdown(monkeypatch: pytest.MonkeyPatch) -> None:
    """The executor hands its readers back (starting delivery threads) while the context
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
        while any(_delivery_threads(f"/race{i}") for i in range(4)) and time.monotonic() < end:
            time.sleep(0.01)
        assert not any(_delivery_threads(f"/race{i}") for i in range(4))
