"""Executors: exception isolation, ordering, futures, async callbacks, callback groups.

Oracles: rclpy's documented executor behaviour, and the reference runner ``Executor._call``
for the inlined message loop (both paths run the same callbacks to the same outcome).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

import pytest

from posekit.msgs.std_msgs import String
from posekit.runtime.callback_groups import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from posekit.runtime.context import Context
from posekit.runtime.executors import MultiThreadedExecutor, SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.sim_executor import SimulatedTimeExecutor
from posekit.runtime.task import Future


def test_callback_exception_is_logged_and_isolated(ctx, logs) -> None:
    bad = Node("bad_node", context=ctx)
    good = Node("good_node", context=ctx)
    good_ticks: list[int] = []
    bad_calls: list[int] = []

    def explode() -> None:
        bad_calls.append(1)
        raise ZeroDivisionError("boom")

    bad.create_timer(0.1, explode)
    good.create_timer(0.1, lambda: good_ticks.append(good.get_clock().now().nanoseconds))
    received: list[str] = []
    bad.create_subscription(String, "t", lambda m: 1 / 0, 10)
    good.create_subscription(String, "t", lambda m: received.append(m.data), 10)
    pub = good.create_publisher(String, "t", 10)
    pub.publish(String(data="x"))
    ex = SimulatedTimeExecutor(context=ctx)
    ex.add_node(bad)
    ex.add_node(good)
    ex.run_until(1.0)
    assert len(good_ticks) == 10
    assert len(bad_calls) == 10
    assert received == ["x"]
    errors = [r for r in logs if r.severity.name == "ERROR"]
    assert len(errors) == 11 == ex.callback_exceptions
    assert all(r.name == "bad_node" for r in errors)
    timer_errors = [r for r in errors if "Exception in timer callback" in r.message]
    assert len(timer_errors) == 10
    assert "Traceback" in timer_errors[0].message
    assert "ZeroDivisionError: boom" in timer_errors[0].message
    assert any("subscription callback on '/t'" in r.message for r in errors)


def test_messages_delivered_in_publish_order_across_subscriptions(ctx) -> None:
    node = Node("n", context=ctx)
    order: list[str] = []
    pubs = {}
    for topic in ["a", "b", "c"]:
        pubs[topic] = node.create_publisher(String, topic, 10)
        node.create_subscription(String, topic, lambda m, t=topic: order.append(t + m.data), 10)
    sequence = ["b1", "a1", "c1", "a2", "b2"]
    for item in sequence:
        pubs[item[0]].publish(String(data=item[1]))
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(node)
    ex.spin_some()
    assert order == sequence


def test_spin_until_future_complete_and_async_callbacks(ctx) -> None:
    node = Node("n", context=ctx)
    future = Future()
    node.create_timer(0.001, lambda: future.set_result(42))
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(node)
    ex.spin_until_future_complete(future, timeout_sec=5.0)
    assert future.done()
    assert future.result() == 42

    gate = Future()
    results: list[str] = []

    async def on_msg(msg: String) -> None:
        value = await gate
        results.append(f"{msg.data}:{value}")

    node.create_subscription(String, "t", on_msg, 10)
    node.create_publisher(String, "t", 10).publish(String(data="m"))
    ex.spin_some()
    assert results == []  # waiting on the gate
    gate.set_result("open")
    ex.spin_some()
    assert results == ["m:open"]
    task = ex.create_task(lambda: 7)
    ex.spin_until_future_complete(task, timeout_sec=1.0)
    assert task.result() == 7


def test_spin_returns_on_shutdown() -> None:
    context = Context()
    context.init()
    node = Node("n", context=context)
    ex = SingleThreadedExecutor(context=context)
    ex.add_node(node)
    node.create_timer(0.01, context.shutdown)
    thread = threading.Thread(target=ex.spin)
    thread.start()
    thread.join(timeout=5.0)
    assert not thread.is_alive()
    assert not context.ok()


@pytest.mark.parametrize("kind", ["single", "multi"])
def test_shutdown_just_before_the_wait_is_announced_still_ends_spin(
        ctx, monkeypatch: pytest.MonkeyPatch, kind: str) -> None:
    """shutdown() on another thread after the spinning thread's last check of the flag but
    before it announced its wait (``Inbox.prepare_wait`` clears the wake-up): the flag must be
    looked at again after the announcement, or the wake-up is lost and spin() never returns."""
    from posekit.runtime.inbox import Inbox

    node = Node("n", context=ctx)
    ex = (SingleThreadedExecutor if kind == "single" else MultiThreadedExecutor)(context=ctx)
    ex.add_node(node)
    prepare_wait = Inbox.prepare_wait
    interleaved = threading.Event()

    def shutdown_lands_first(inbox: Inbox) -> None:
        if inbox is ex.inbox and not interleaved.is_set():
            interleaved.set()
            ex._is_shutdown = True  # what shutdown() does first ...
            ex.wake()  # ... and last
        prepare_wait(inbox)

    monkeypatch.setattr(Inbox, "prepare_wait", shutdown_lands_first)
    thread = threading.Thread(target=ex.spin, daemon=True)
    thread.start()
    thread.join(timeout=5.0)
    stuck = thread.is_alive()
    if stuck:  # release it before failing
        monkeypatch.undo()
        ex.wake()
        thread.join(timeout=5.0)
    assert interleaved.is_set()
    assert not stuck, "spin() missed a shutdown that came before its wait"


def test_spin_runs_callbacks_and_calls_a_subclass_own_spin_once(ctx) -> None:
    """spin() runs spin_once's steps itself, unless a subclass overrides spin_once (rclpy's
    Executor.spin calls self.spin_once(): code that overrides it must keep working)."""
    node = Node("n", context=ctx)
    pub = node.create_publisher(String, "/s", 10)
    got: list[str] = []

    class Overriding(SingleThreadedExecutor):
        def spin_once(self, timeout_sec: float | None = None) -> None:
            calls.append(timeout_sec)
            super().spin_once(timeout_sec=0.01)
            if len(got) == 3:
                self.shutdown()

    calls: list[float | None] = []
    node.create_subscription(String, "/s", lambda m: got.append(m.data), 10)
    for word in ("a", "b", "c"):
        pub.publish(String(data=word))
    overriding = Overriding(context=ctx)
    overriding.add_node(node)
    overriding.spin()
    assert got == ["a", "b", "c"]
    assert calls  # spin() went through the override
    assert all(t is None for t in calls)
    overriding.remove_node(node)

    plain = SingleThreadedExecutor(context=ctx)
    plain.add_node(node)
    for word in ("d", "e"):
        pub.publish(String(data=word))
    node.create_timer(0.01, lambda: plain.shutdown() if len(got) == 5 else None)
    plain.spin()
    assert got == ["a", "b", "c", "d", "e"]


@pytest.mark.parametrize("kind", ["single", "multi"])
def test_shutdown_waits_for_the_callback_running_on_another_thread(ctx, kind: str) -> None:
    """rclpy's Executor.shutdown(timeout_sec): stop, then wait for the callbacks running now;
    False while one still runs after ``timeout_sec``, True once every spinning thread has
    returned. A node destroyed after that is never met by a callback of the executor."""
    node = Node("n", context=ctx)
    entered, release = threading.Event(), threading.Event()
    finished: list[bool] = []

    def slow() -> None:
        entered.set()
        release.wait(10.0)
        finished.append(True)

    node.create_timer(0.001, slow)
    ex = SingleThreadedExecutor(context=ctx) if kind == "single" else MultiThreadedExecutor(
        num_threads=2, context=ctx)
    ex.add_node(node)
    spinner = threading.Thread(target=ex.spin)
    spinner.start()
    try:
        assert entered.wait(5.0)
        assert ex.shutdown(timeout_sec=0.05) is False  # the callback is still running
        assert not finished
        release.set()
        assert ex.shutdown(timeout_sec=5.0) is True
        assert finished == [True]  # done before shutdown returned, and not run again
        spinner.join(timeout=5.0)
        assert not spinner.is_alive()
    finally:
        release.set()
        spinner.join(timeout=5.0)


def test_shutdown_from_a_callback_does_not_wait_for_itself(ctx) -> None:
    node = Node("n", context=ctx)
    results: list[bool] = []
    ex = SingleThreadedExecutor(context=ctx)
    node.create_timer(0.001, lambda: results.append(ex.shutdown()))  # no timeout
    ex.add_node(node)
    spinner = threading.Thread(target=ex.spin, daemon=True)
    spinner.start()
    spinner.join(timeout=5.0)
    assert not spinner.is_alive()
    assert results == [True]


def test_shutdown_ends_a_paced_simulated_run_waiting_for_the_wall_clock(ctx) -> None:
    """A run paced to the wall clock waits (wall time) for its next timer, here 30 s away;
    shutdown ends that wait at once and time stays where it was."""
    node = Node("n", context=ctx)
    ticks: list[int] = []
    node.create_timer(30.0, lambda: ticks.append(1))
    ex = SimulatedTimeExecutor(context=ctx, real_time_factor=1.0)
    ex.add_node(node)
    spinner = threading.Thread(target=ex.spin, daemon=True)
    spinner.start()
    try:
        started = time.monotonic()
        assert ex.shutdown(timeout_sec=20.0) is True
        assert time.monotonic() - started < 15.0  # not the 30 s wait
        assert ticks == []
        assert ex.now_ns == 0
    finally:
        spinner.join(timeout=5.0)
    assert not spinner.is_alive()


def test_wall_timer_fires_repeatedly(ctx) -> None:
    node = Node("n", context=ctx)
    ticks: list[int] = []
    node.create_timer(0.005, lambda: ticks.append(1))
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(node)
    end = time.monotonic() + 0.1
    while len(ticks) < 3 and time.monotonic() < end + 2.0:
        ex.spin_once(timeout_sec=0.05)
    assert len(ticks) >= 3


def test_multithreaded_groups(ctx) -> None:
    node = Node("n", context=ctx)
    active = [0]
    peak = [0]
    lock = threading.Lock()
    done = threading.Event()
    counts = [0]

    def exclusive() -> None:
        with lock:
            active[0] += 1
            peak[0] = max(peak[0], active[0])
        time.sleep(0.005)
        with lock:
            active[0] -= 1
            counts[0] += 1
            if counts[0] >= 6:
                done.set()

    node.create_timer(0.001, exclusive)
    node.create_timer(0.001, exclusive)  # same default (mutually exclusive) group
    barrier = threading.Barrier(2, timeout=5.0)
    met: list[bool] = []
    group = ReentrantCallbackGroup()

    def reentrant() -> None:
        if len(met) < 2:
            try:
                barrier.wait()  # only passes if both run at the same time
                met.append(True)
            except threading.BrokenBarrierError:
                met.append(False)

    node.create_timer(0.001, reentrant, callback_group=group)
    node.create_timer(0.001, reentrant, callback_group=group)
    ex = MultiThreadedExecutor(num_threads=4, context=ctx)
    ex.add_node(node)
    thread = threading.Thread(target=ex.spin, daemon=True)
    thread.start()
    done.wait(5.0)
    deadline = time.monotonic() + 5.0
    while len(met) < 2 and time.monotonic() < deadline:
        time.sleep(0.01)
    ex.shutdown()
    thread.join(timeout=5.0)
    assert counts[0] >= 6
    assert peak[0] == 1
    assert met[:2] == [True, True]


@pytest.mark.parametrize("path", ["spin_once", "spin_some"])
def test_message_callbacks_run_alike_through_both_paths(ctx, logs, path: str) -> None:
    # spin_once takes one item and runs it with Executor._call (the reference); spin_some
    # drains the queue with the same steps inlined. Same callbacks, same outcome: the
    # exception reported by the node's logger and counted, a coroutine run as a task, and
    # the mutually exclusive group released after each (the next message runs).
    node = Node("paths", context=ctx)
    group = MutuallyExclusiveCallbackGroup()
    gate: Future = Future()
    seen: list[str] = []

    async def later(msg: String) -> None:
        seen.append(f"{msg.data}:{await gate}")

    def on_msg(msg: String) -> object:
        if msg.data == "bad":
            raise ValueError("bad message")
        if msg.data == "async":
            return later(msg)
        seen.append(msg.data)
        return None

    node.create_subscription(String, "t", on_msg, 10, callback_group=group)
    pub = node.create_publisher(String, "t", 10)
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(node)
    for data in ("a", "bad", "async", "b"):
        pub.publish(String(data=data))
    if path == "spin_once":  # one item per call (a message or the coroutine's task step)
        for _ in range(8):
            if "b" in seen:
                break
            ex.spin_once(timeout_sec=0)
    else:
        ex.spin_some()
    gate.set_result("open")
    ex.spin_some()
    assert seen == ["a", "b", "async:open"]
    assert ex.callback_exceptions == 1
    errors = [r.message for r in logs if r.severity.name == "ERROR"]
    assert len(errors) == 1
    assert errors[0].startswith("Exception in subscription callback on '/t'")
    assert "ValueError: bad message" in errors[0]
    ex.shutdown()


def _burst(ctx: Context, count: int, on_msg: Callable[[int], None],
           depth: int = 1000) -> tuple[Node, SingleThreadedExecutor]:
    """A node with ``count`` messages queued on /burst for ``on_msg(index)``, in an executor."""
    node = Node("burst", context=ctx)
    node.create_subscription(String, "burst", lambda m: on_msg(int(m.data)), depth)
    pub = node.create_publisher(String, "burst", depth)
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(node)
    for i in range(count):
        pub.publish(String(data=str(i)))
    return node, ex


def _run(ex: SingleThreadedExecutor, how: str) -> None:
    if how == "spin":
        ex.spin()  # until a callback shuts the executor down
    else:
        ex.spin_some()


@pytest.mark.parametrize("how", ["spin", "spin_some"])
def test_queued_messages_yield_to_a_timer_as_it_comes_due(ctx, how: str) -> None:
    # Queued messages run back to back (as rclpy runs what one wait found ready), but a
    # timer coming due runs after at most the one message in progress. Each message keeps
    # the thread busy for 1 ms of wall time and the timer's period is 10 ms, so at most
    # 10 + 1 messages start between two ticks (a slower machine only lowers the count); a
    # batch that missed the timer would run 64.
    events: list[str] = []
    count = 150
    ex: list[SingleThreadedExecutor] = []

    def on_msg(index: int) -> None:
        events.append("m")
        end = time.perf_counter() + 0.001
        while time.perf_counter() < end:
            pass
        if index == count - 1 and how == "spin":
            ex[0].shutdown()

    node, executor = _burst(ctx, count, on_msg)
    ex.append(executor)
    node.create_timer(0.010, lambda: events.append("T"))
    _run(executor, how)
    assert events.count("m") == count
    runs = "".join(events).split("T")
    assert len(runs) >= 4, "the timer ran during the burst"
    assert max(len(r) for r in runs[:-1]) <= 12, [len(r) for r in runs]


@pytest.mark.parametrize("how", ["spin", "spin_some"])
def test_shutdown_in_a_callback_stops_the_messages_queued_behind_it(ctx, how: str) -> None:
    # (shutdown removes the nodes: what they queued is stale at once)
    ran: list[int] = []
    ex: list[SingleThreadedExecutor] = []

    def on_msg(index: int) -> None:
        ran.append(index)
        if index == 4:
            ex[0].shutdown()

    _, executor = _burst(ctx, 50, on_msg)
    ex.append(executor)
    _run(executor, how)
    assert ran == [0, 1, 2, 3, 4]


@pytest.mark.parametrize("how", ["spin", "spin_some"])
def test_a_task_made_by_a_callback_runs_before_the_next_queued_message(ctx, how: str) -> None:
    # Tasks come first at every look (rclpy's executor yields them before it waits again,
    # and takes one message of a subscription per wait).
    order: list[str] = []
    ex: list[SingleThreadedExecutor] = []

    def on_msg(index: int) -> None:
        order.append(f"m{index}")
        if index == 1:  # in the middle of the queued messages
            ex[0].create_task(lambda: order.append("task"))
        if index == 3 and how == "spin":
            ex[0].shutdown()

    _, executor = _burst(ctx, 4, on_msg)
    ex.append(executor)
    _run(executor, how)
    assert order == ["m0", "m1", "task", "m2", "m3"]


def test_the_context_holds_executors_and_bound_callbacks_weakly() -> None:
    # As rclpy's Context.on_shutdown: a bound method is held by a weak reference, so an
    # executor dropped by its owner is not kept alive by the context; plain functions are
    # held and still run at shutdown.
    import gc
    import weakref

    context = Context()
    context.init()
    ran: list[str] = []
    context.on_shutdown(lambda: ran.append("function"))
    executor = SingleThreadedExecutor(context=context)
    gone = weakref.ref(executor)
    del executor
    gc.collect()
    assert gone() is None
    context.shutdown()
    assert ran == ["function"]
