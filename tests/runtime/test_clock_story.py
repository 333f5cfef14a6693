"""One clock per simulation, in process: the stepped executor publishes /clock exactly when
its nodes are visible to other processes, drives its own nodes (a foreign /clock cannot move
them), refuses to claim /clock when another publisher exists, and a follower ignores a second
/clock source. Oracles: the executor's own sim time (set by construction) and the rules
stated in posekit.runtime.time_source / executors; the cross-process behaviour over real
Zenoh is tested in tests/cli/test_sim_clock.py."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

from posekit.msgs.rosgraph_msgs import Clock as ClockMsg
from posekit.runtime import time_source
from posekit.runtime.bus import InProcessBus
from posekit.runtime.context import Context
from posekit.runtime.logging import LogRecord
from posekit.runtime.node import Node
from posekit.runtime.parameters import Parameter
from posekit.runtime.sim_executor import ClockConflictError, SimulatedTimeExecutor
from posekit.runtime.transport import register_transport


class VisibleBus(InProcessBus):
    """An in-process bus that says it is visible to other processes (as Zenoh is)."""

    crosses_processes = True


register_transport("visible_bus_for_tests", VisibleBus)


@pytest.fixture
def visible_ctx() -> Iterator[Context]:
    context = Context()
    context.init(args=[], transport="visible_bus_for_tests")
    yield context
    context.try_shutdown()


def _clock_msg(seconds: int) -> ClockMsg:
    msg = ClockMsg()
    msg.clock.sec = seconds
    return msg


def test_clock_is_published_only_when_the_nodes_are_visible(ctx, visible_ctx) -> None:
    stamps: dict[str, list[int]] = {"inprocess": [], "visible": []}
    for key, context in (("inprocess", ctx), ("visible", visible_ctx)):
        ticker = Node("ticker", context=context)
        ticker.create_timer(0.5, lambda: None)
        observer = Node("observer", context=context)  # a plain /clock subscription
        observer.create_subscription(
            ClockMsg, "/clock", lambda m, k=key: stamps[k].append(m.clock.sec), 10
        )
        ex = SimulatedTimeExecutor(context=context)
        ex.add_node(ticker)
        ex.add_node(observer)
        assert ex.publish_clock is (key == "visible")
        ex.run_until(2.0)
    assert stamps["inprocess"] == []
    # 0.5 s steps: whole seconds 0, 1, 1, 2 (/clock.sec), one message per step.
    assert stamps["visible"] == [0, 1, 1, 2]


def test_simulation_nodes_ignore_a_foreign_clock(ctx) -> None:
    sim_node = Node("sim_node", context=ctx)
    seen: list[int] = []
    sim_node.create_timer(0.25, lambda: seen.append(sim_node.get_clock().now().nanoseconds))
    stray = Node("stray", context=ctx).create_publisher(ClockMsg, "/clock", 10)
    ex = SimulatedTimeExecutor(context=ctx)
    ex.add_node(sim_node)
    assert sim_node.count_subscribers("/clock") == 0  # driven: not even subscribed
    ex.run_until(0.5)
    stray.publish(_clock_msg(1000))
    ex.run_until(1.0)
    assert seen == [250_000_000, 500_000_000, 750_000_000, 1_000_000_000]
    assert sim_node.get_clock().now().nanoseconds == 1_000_000_000
    # Taken off the executor, the node follows /clock again.
    ex.remove_node(sim_node)
    assert sim_node.count_subscribers("/clock") == 1


def test_a_second_simulation_clock_is_refused(visible_ctx) -> None:
    first = SimulatedTimeExecutor(context=visible_ctx)
    first.add_node(Node("world", context=visible_ctx))
    first.claim_clock()
    second = SimulatedTimeExecutor(context=visible_ctx)
    second.add_node(Node("other_world", context=visible_ctx))
    # the in-process graph names the publishing node, as the network graphs do
    with pytest.raises(ClockConflictError, match=r"another clock source already publishes "
                                                 r"/clock \(/posekit_sim_clock\)"):
        second.claim_clock()


def test_a_late_stray_clock_publisher_is_reported_once(visible_ctx, logs: list[LogRecord]
                                                       ) -> None:
    world = Node("world", context=visible_ctx)
    world.create_timer(0.1, lambda: None)
    ex = SimulatedTimeExecutor(context=visible_ctx)
    ex.add_node(world)
    ex.claim_clock()
    ex.run_until(0.5)
    stray = Node("stray", context=visible_ctx).create_publisher(ClockMsg, "/clock", 10)
    ex._foreign_check_at = 0.0  # the next step checks the graph (normally once a wall second)
    ex.run_until(1.0)
    stray.publish(_clock_msg(1000))
    ex._foreign_check_at = 0.0
    ex.run_until(1.5)
    reports = [r for r in logs if "second /clock publisher" in r.message]
    assert len(reports) == 1
    assert ex.now_ns == 1_500_000_000
    assert world.get_clock().now().nanoseconds == 1_500_000_000


def test_a_follower_ignores_a_second_clock_source(ctx, logs: list[LogRecord],
                                                  monkeypatch: Any) -> None:
    node = Node("follower", context=ctx)
    node.set_parameters([Parameter("use_sim_time", value=True)])
    source = node._time_source
    wall = [100.0]
    monkeypatch.setattr(time_source.time, "monotonic", lambda: wall[0])
    source._on_clock((_clock_msg(5), b"simulation"))
    source._on_clock((_clock_msg(1000), b"stray"))
    source._on_clock((_clock_msg(1001), b"stray"))
    wall[0] += 0.5
    source._on_clock((_clock_msg(6), b"simulation"))
    assert node.get_clock().now().nanoseconds == 6_000_000_000
    assert source.ignored_messages == 2
    warnings = [r for r in logs if "second source" in r.message]
    assert len(warnings) == 1
    assert "73747261" in warnings[0].message
    # The simulation stops; after SOURCE_SILENCE_S another source may take over.
    wall[0] += time_source.SOURCE_SILENCE_S + 0.1
    source._on_clock((_clock_msg(2), b"restarted"))
    assert node.get_clock().now().nanoseconds == 2_000_000_000
