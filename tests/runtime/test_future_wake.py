"""spin_until_future_complete ends when another thread completes the future.

Oracle: rclpy's Executor.spin_until_future_complete, which waits with
``condition=future.done`` and so returns as soon as any thread completes the future, even
when the executor has no timers, subscriptions or tasks of its own. Each wait here has a
long timeout (or none, run in a thread joined with a bound): returning well before it is
the behaviour under test.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

import pytest

from posekit.msgs.geometry_msgs import TransformStamped
from posekit.runtime.context import Context
from posekit.runtime.executors import Executor, MultiThreadedExecutor, SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.sim_executor import SimulatedTimeExecutor
from posekit.runtime.task import Future
from posekit.tf2.buffer import Buffer

LONG_TIMEOUT_S = 60.0


def _later(action: Callable[[], None], delay_s: float = 0.05) -> threading.Thread:
    thread = threading.Thread(target=lambda: (time.sleep(delay_s), action()))
    thread.start()
    return thread


def _make(kind: str, ctx: Context) -> Executor:
    if kind == "single":
        return SingleThreadedExecutor(context=ctx)
    if kind == "multi":
        return MultiThreadedExecutor(2, context=ctx)
    return SimulatedTimeExecutor(context=ctx, publish_clock=False)


@pytest.mark.parametrize("kind", ["single", "multi", "sim"])
def test_plain_future_completed_by_thread_with_timeout(ctx: Context, kind: str) -> None:
    ex = _make(kind, ctx)
    ex.add_node(Node("idle", context=ctx))  # no timers, no subscriptions
    future = Future()
    setter = _later(lambda: future.set_result("ok"))
    start = time.monotonic()
    ex.spin_until_future_complete(future, timeout_sec=LONG_TIMEOUT_S)
    elapsed = time.monotonic() - start
    setter.join()
    assert future.done()
    assert future.result() == "ok"
    assert elapsed < LONG_TIMEOUT_S / 2  # returned on completion, not at the timeout
    ex.shutdown()


@pytest.mark.parametrize("kind", ["single", "multi", "sim"])
def test_plain_future_completed_by_thread_without_timeout(ctx: Context, kind: str) -> None:
    ex = _make(kind, ctx)
    future = Future()
    spinner = threading.Thread(target=ex.spin_until_future_complete, args=(future,), daemon=True)
    spinner.start()
    _later(lambda: future.set_result(1)).join()
    spinner.join(timeout=LONG_TIMEOUT_S / 2)
    hung = spinner.is_alive()
    ex.shutdown()  # releases a hung spinner so the test ends either way
    spinner.join(timeout=5.0)
    assert not hung


def _tf(parent: str, child: str) -> TransformStamped:
    t = TransformStamped()
    t.header.frame_id = parent
    t.child_frame_id = child
    t.transform.rotation.w = 1.0
    return t


@pytest.mark.parametrize("timeout", [LONG_TIMEOUT_S, None])
def test_wait_for_transform_async_completed_from_thread(ctx: Context,
                                                        timeout: float | None) -> None:
    buffer = Buffer()
    ex = SingleThreadedExecutor(context=ctx)
    future = buffer.wait_for_transform_async("map", "base_link", 0)
    assert not future.done()
    _later(lambda: buffer.set_transform_static(_tf("map", "base_link"), "test"))
    spinner = threading.Thread(
        target=ex.spin_until_future_complete, args=(future, timeout), daemon=True
    )
    spinner.start()
    spinner.join(timeout=LONG_TIMEOUT_S / 2)
    hung = spinner.is_alive()
    ex.shutdown()
    spinner.join(timeout=5.0)
    assert not hung
    assert future.result() is True


def test_spin_once_until_future_complete_returns_on_completion(ctx: Context) -> None:
    ex = SingleThreadedExecutor(context=ctx)
    future = Future()
    setter = _later(lambda: future.set_result(3))
    start = time.monotonic()
    ex.spin_once_until_future_complete(future, timeout_sec=LONG_TIMEOUT_S)
    setter.join()
    assert future.done()
    assert time.monotonic() - start < LONG_TIMEOUT_S / 2
