"""Executors are context managers, as in rclpy.

Oracle: rclpy's ``Executor.__enter__`` returns the executor itself and ``__exit__`` calls
``shutdown()`` (whether the block ends normally or by an exception, which propagates).
After shutdown an executor holds no nodes (rclpy's shutdown clears its node set) and its
spin methods return at once instead of running callbacks.
"""

from __future__ import annotations

import pytest

from posekit.runtime.context import Context
from posekit.runtime.executors import Executor, MultiThreadedExecutor, SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.sim_executor import SimulatedTimeExecutor


def _make(kind: str, ctx: Context) -> Executor:
    if kind == "single":
        return SingleThreadedExecutor(context=ctx)
    if kind == "multi":
        return MultiThreadedExecutor(2, context=ctx)
    return SimulatedTimeExecutor(context=ctx, publish_clock=False)


KINDS = ["single", "multi", "sim"]


@pytest.mark.parametrize("kind", KINDS)
def test_with_block_returns_the_executor_and_shuts_it_down(ctx: Context, kind: str) -> None:
    node = Node("ctx_node", context=ctx)
    calls: list[int] = []
    node.create_timer(0.0, lambda: calls.append(1))
    executor = _make(kind, ctx)
    with executor as entered:
        assert entered is executor
        assert entered.add_node(node)
        entered.spin_once(timeout_sec=1.0)
        assert calls == [1]  # usable inside the block
    assert executor.get_nodes() == []
    assert node.executor is None
    executor.spin()  # shut down: returns at once, runs nothing
    executor.spin_once(timeout_sec=0.0)
    assert calls == [1]


@pytest.mark.parametrize("kind", KINDS)
def test_exception_in_the_block_still_shuts_down_and_propagates(ctx: Context,
                                                                kind: str) -> None:
    node = Node("raiser", context=ctx)
    executor = _make(kind, ctx)

    def use_and_fail() -> None:
        with executor:
            executor.add_node(node)
            raise RuntimeError("inside the block")

    with pytest.raises(RuntimeError, match="inside the block"):
        use_and_fail()
    assert executor.get_nodes() == []
    assert node.executor is None


def test_sim_executor_in_a_with_block_runs_to_a_time(ctx: Context) -> None:
    node = Node("stepped", context=ctx)
    stamps: list[int] = []
    node.create_timer(0.25, lambda: stamps.append(node.get_clock().now_ns()))
    with SimulatedTimeExecutor(context=ctx, publish_clock=False) as executor:
        executor.add_node(node)
        executor.run_until(1.0)
    assert stamps == [250_000_000, 500_000_000, 750_000_000, 1_000_000_000]
    assert executor.get_nodes() == []
