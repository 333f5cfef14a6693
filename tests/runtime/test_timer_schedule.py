"""TimerSchedule: which timer is called next, and when.

Oracles: rcl's timer semantics in closed form. A timer of period p started at t0 is due at
t0 + k p; among due timers the one due first runs first, ties in creation order (rclpy's
executor takes ready timers in that order); missed periods are skipped on the original grid;
a backward clock jump restarts the period from the new time. The heap (driven clocks) and
the scan (any clock) must both give exactly the closed-form sequence.
"""

from __future__ import annotations

from collections.abc import Callable

import pytest

from posekit.runtime.clock import Clock
from posekit.runtime.context import Context
from posekit.runtime.entities import Timer
from posekit.runtime.node import Node
from posekit.runtime.parameters import Parameter
from posekit.runtime.timer_schedule import TimerSchedule
from posekit.time import ClockType

MS = 1_000_000


def _sim_node(ctx: Context, name: str) -> Node:
    node = Node(name, context=ctx)
    node.handoff.time_source.set_driven(True)  # time set by hand below, no /clock
    node.set_parameters([Parameter("use_sim_time", value=True)])
    return node


def _set_time(nodes: list[Node], ns: int) -> None:
    for node in nodes:
        node.handoff.time_source.set_time_ns(ns)


def _fleet(ctx: Context, tag: str) -> tuple[list[Node], list[Timer], dict[int, str]]:
    """3 nodes with 4 timers each (periods 10-50 ms), all created at sim time 0."""
    nodes = [_sim_node(ctx, f"{tag}{i}") for i in range(3)]
    timers: list[Timer] = []
    names: dict[int, str] = {}
    for i, node in enumerate(nodes):
        for j in range(4):
            period_ms = 10 * (1 + (i * 4 + j) % 5)
            timer = node.create_timer(period_ms / 1000, lambda: None)
            names[id(timer)] = f"n{i}t{j}"
            timers.append(timer)
    return nodes, timers, names


def _run(schedule: TimerSchedule, nodes: list[Node], names: dict[int, str],
         until_ns: int) -> list[tuple[int, str]]:
    calls: list[tuple[int, str]] = []
    now = 0
    while True:
        while (timer := schedule.claim_due()) is not None:
            calls.append((now, names[id(timer)]))
            timer.callback_group.ending_execution()
        nxt = schedule.next_due_ns(now)
        if nxt is None or nxt > until_ns:
            return calls
        now = nxt
        _set_time(nodes, now)


def _closed_form(until_ns: int) -> list[tuple[int, str]]:
    expected: list[tuple[int, int, str]] = []
    for index in range(12):
        i, j = divmod(index, 4)
        period = 10 * MS * (1 + index % 5)
        expected += [(k * period, index, f"n{i}t{j}") for k in range(1, until_ns // period + 1)]
    return [(t, name) for t, _, name in sorted(expected)]


@pytest.mark.parametrize("driven", [True, False], ids=["heap", "scan"])
def test_order_is_due_time_then_creation_order(ctx: Context, driven: bool) -> None:
    nodes, timers, names = _fleet(ctx, "heap" if driven else "scan")
    drives: Callable[[Timer], bool] = (lambda _t: True) if driven else (lambda _t: False)
    schedule = TimerSchedule(drives)
    schedule.set_timers(list(reversed(timers)))  # any order in: creation order out
    assert schedule.timers == timers
    until = 200 * MS
    assert _run(schedule, nodes, names, until) == _closed_form(until)


def test_cancel_and_reset_through_invalidate(ctx: Context) -> None:
    node = _sim_node(ctx, "c")
    fast = node.create_timer(0.01, lambda: None)
    slow = node.create_timer(0.03, lambda: None)
    schedule = TimerSchedule(lambda _t: True)
    schedule.set_timers([fast, slow])
    assert schedule.next_due_ns(0) == 10 * MS
    fast.cancel()
    schedule.invalidate()  # what the executor does on the timer's change report
    assert schedule.changed
    assert schedule.next_due_ns(0) == 30 * MS
    assert not schedule.changed
    _set_time([node], 30 * MS)
    assert schedule.claim_due() is slow
    slow.callback_group.ending_execution()
    assert schedule.claim_due() is None  # the cancelled one never runs
    fast.reset()  # restarts one period from now (30 ms)
    schedule.invalidate()
    assert schedule.next_due_ns(30 * MS) == 40 * MS


def test_missed_periods_are_skipped_on_the_grid(ctx: Context) -> None:
    node = _sim_node(ctx, "m")
    timer = node.create_timer(0.01, lambda: None)
    schedule = TimerSchedule(lambda _t: True)
    schedule.set_timers([timer])
    _set_time([node], 35 * MS)  # 10, 20, 30 ms all passed: one call, next on the grid
    assert schedule.claim_due() is timer
    timer.callback_group.ending_execution()
    assert schedule.claim_due() is None
    assert schedule.next_due_ns(35 * MS) == 40 * MS


def test_backward_jump_restarts_the_period(ctx: Context) -> None:
    node = _sim_node(ctx, "j")
    _set_time([node], 100 * MS)
    timer = node.create_timer(0.05, lambda: None)  # due at 150 ms
    schedule = TimerSchedule(lambda _t: True)
    schedule.set_timers([timer])
    assert schedule.next_due_ns(100 * MS) == 150 * MS
    _set_time([node], 20 * MS)  # jump back: rcl restarts the period from 20 ms
    assert schedule.next_due_ns(20 * MS) == 70 * MS


def test_zero_period_timer_runs_once_per_time_value(ctx: Context) -> None:
    node = _sim_node(ctx, "z")
    every = node.create_timer(0.0, lambda: None)
    ticker = node.create_timer(0.01, lambda: None)
    schedule = TimerSchedule(lambda _t: True)
    schedule.set_timers([every, ticker])
    _set_time([node], 1)  # the clock moved: the zero-period timer is ready once
    assert schedule.claim_due() is every
    every.callback_group.ending_execution()
    assert schedule.claim_due() is None
    assert schedule.next_due_ns(1) == 10 * MS  # it does not drive time; the ticker does


def test_wall_wait_counts_only_wall_clock_timers(ctx: Context) -> None:
    node = _sim_node(ctx, "w")
    sim_timer = node.create_timer(0.001, lambda: None)  # on the active ROS clock: ignored
    steady = Clock(clock_type=ClockType.STEADY_TIME)
    wall_timer = node.create_timer(10.0, lambda: None, clock=steady)
    schedule = TimerSchedule()
    schedule.set_timers([sim_timer, wall_timer])
    wait = schedule.wall_wait_s()
    assert wait is not None
    assert 0.0 < wait <= 10.0
    wall_timer.cancel()
    assert schedule.wall_wait_s() is None


def test_quiet_window_ends_at_the_next_wall_timer_and_at_once_with_sim_time(ctx: Context) -> None:
    # What a batch of queued messages may run through without claiming a timer: until the
    # next wall-clock timer is due; not at all while a timer runs on an active ROS clock
    # (a /clock message may make it due at any moment); forever without timers.
    node = _sim_node(ctx, "q")
    steady = Clock(clock_type=ClockType.STEADY_TIME)
    wall_timer = node.create_timer(10.0, lambda: None, clock=steady)
    schedule = TimerSchedule()
    assert schedule.quiet_wall_s() is None
    schedule.set_timers([wall_timer])
    quiet = schedule.quiet_wall_s()
    assert quiet is not None
    assert 9.0 < quiet <= 10.0
    sim_timer = node.create_timer(10.0, lambda: None)
    schedule.set_timers([wall_timer, sim_timer])
    assert schedule.quiet_wall_s() == 0.0
    sim_timer.cancel()
    again = schedule.quiet_wall_s()
    assert again is not None
    assert 9.0 < again <= quiet
