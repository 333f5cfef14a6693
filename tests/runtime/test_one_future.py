"""One Future for the whole package: tf2's futures are the runtime's (and rclpy facade's).

Oracle: tf2_ros, whose ``Buffer.wait_for_transform_async`` returns an ``rclpy.task.Future``:
such a future can be awaited in a coroutine callback of an executor (the callback resumes
once the future completes, rclpy's Task semantics) and handed to
``rclpy.spin_until_future_complete`` (which returns once it is done). Sim-time stamps are
exact multiples of the timer periods, so "resumed in the step that completed the future" is
checked against closed-form times.
"""

from __future__ import annotations

import threading

import pytest

from posekit import rclpy
from posekit.msgs.geometry_msgs import TransformStamped
from posekit.rclpy import task as rclpy_task
from posekit.runtime.context import Context
from posekit.runtime.node import Node
from posekit.runtime.sim_executor import SimulatedTimeExecutor
from posekit.runtime.task import CancelledError, Future, Task
from posekit.tf2 import future as tf2_future
from posekit.tf2.buffer import Buffer
from posekit.time import Time

LONG_TIMEOUT_S = 60.0


def _tf(parent: str, child: str, x: float) -> TransformStamped:
    t = TransformStamped()
    t.header.frame_id = parent
    t.child_frame_id = child
    t.transform.translation.x = x
    t.transform.rotation.w = 1.0
    return t


def test_one_class_everywhere() -> None:
    assert Future is tf2_future.Future is rclpy_task.Future
    assert rclpy_task.Task is Task
    assert issubclass(Task, Future)
    assert CancelledError is tf2_future.CancelledError
    assert isinstance(Buffer().wait_for_transform_async("a", "b", Time()), Future)


def test_tf2_future_awaited_in_a_coroutine_timer_callback(
    ctx: Context, executor: SimulatedTimeExecutor
) -> None:
    node = Node("awaiter", context=ctx)
    buffer = Buffer()
    seen: list[tuple[str, int, float]] = []

    async def wait_then_lookup() -> None:
        timer.cancel()
        seen.append(("waiting", node.get_clock().now_ns(), 0.0))
        await buffer.wait_for_transform_async("map", "base", Time())
        t = buffer.lookup_transform("map", "base", Time())
        seen.append(("resumed", node.get_clock().now_ns(), t.transform.translation.x))

    def publish() -> None:
        publisher.cancel()
        buffer.set_transform_static(_tf("map", "base", 2.5), "test")

    timer = node.create_timer(0.1, wait_then_lookup)
    publisher = node.create_timer(0.5, publish)
    executor.add_node(node)
    executor.run_until(1.0)
    # Awaited at 0.1 s, resumed in the step that completed the future (0.5 s), not polled.
    assert seen == [("waiting", 100_000_000, 0.0), ("resumed", 500_000_000, 2.5)]
    assert executor.callback_exceptions == 0


def test_cancelled_tf2_future_raises_in_the_awaiting_coroutine(
    ctx: Context, executor: SimulatedTimeExecutor, logs: list
) -> None:
    node = Node("canceller", context=ctx)
    buffer = Buffer()
    waits: list[Future[bool]] = []
    outcome: list[str] = []

    async def wait() -> None:
        timer.cancel()
        fut = buffer.wait_for_transform_async("map", "nowhere", Time())
        waits.append(fut)
        try:
            await fut
        except CancelledError:
            outcome.append("cancelled")

    timer = node.create_timer(0.1, wait)
    canceller = node.create_timer(0.3, lambda: (canceller.cancel(), waits[0].cancel()))
    executor.add_node(node)
    executor.run_until(1.0)
    assert outcome == ["cancelled"]
    assert waits[0].done()
    assert waits[0].cancelled()
    with pytest.raises(CancelledError):
        waits[0].result()


def test_rclpy_spin_until_future_complete_on_a_tf2_future(ctx: Context) -> None:
    node = Node("spinner", context=ctx)
    buffer = Buffer()
    future = buffer.wait_for_transform_async("map", "base", Time())
    setter = threading.Thread(
        target=lambda: buffer.set_transform_static(_tf("map", "base", 1.0), "test")
    )
    setter.start()
    rclpy.spin_until_future_complete(node, future, timeout_sec=LONG_TIMEOUT_S)
    setter.join()
    assert future.done()
    assert future.result() is True


def test_rclpy_spin_until_future_complete_with_a_timer_completing_it(ctx: Context) -> None:
    node = Node("timed", context=ctx)
    buffer = Buffer()
    future = buffer.wait_for_transform_async("odom", "base", Time())
    node.create_timer(0.01, lambda: buffer.set_transform_static(_tf("odom", "base", 3.0), "t"))
    rclpy.spin_until_future_complete(node, future, timeout_sec=LONG_TIMEOUT_S)
    assert future.result() is True
    assert buffer.lookup_transform("odom", "base", Time()).transform.translation.x == 3.0


def test_future_api_matches_rclpy_names() -> None:
    names = ("done", "result", "exception", "set_result", "set_exception",
             "add_done_callback", "remove_done_callback", "cancel", "cancelled", "__await__")
    for name in names:
        assert callable(getattr(Future, name)), name


def test_wait_blocks_until_another_thread_completes() -> None:
    future: Future[int] = Future()
    assert future.wait(0.0) is False
    setter = threading.Thread(target=lambda: future.set_result(7))
    setter.start()
    assert future.wait(LONG_TIMEOUT_S) is True
    setter.join()
    assert future.result() == 7
    assert future.wait(0.0) is True  # done: returns at once
