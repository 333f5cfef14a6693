"""Clocks: system/steady/ROS time, sim-time override and jump callbacks."""

from __future__ import annotations

import threading
import time

import pytest

from posekit.runtime.clock import (
    Clock,
    ClockChange,
    ClockType,
    JumpThreshold,
    ROSClock,
    TimeJump,
)
from posekit.time import Duration, Time


def test_system_and_inactive_ros_clock_read_wall_time() -> None:
    before = time.time_ns()
    a = Clock().now().nanoseconds
    b = ROSClock().now().nanoseconds
    after = time.time_ns()
    assert before <= a <= after
    assert before <= b <= after
    assert ROSClock().now().clock_type == ClockType.ROS_TIME


def test_steady_clock_is_monotonic_source() -> None:
    c = Clock(clock_type=ClockType.STEADY_TIME)
    t0 = time.monotonic_ns()
    assert t0 <= c.now_ns() <= time.monotonic_ns()


def test_ros_time_clock_is_a_rosclock_as_in_rclpy() -> None:
    clock = Clock(clock_type=ClockType.ROS_TIME)
    assert type(clock) is ROSClock
    assert clock.clock_type == ClockType.ROS_TIME
    assert not clock.ros_time_is_active
    with pytest.raises(TypeError, match="ClockType enum"):
        Clock(clock_type=2)  # type: ignore[arg-type]


def test_sleep_until_a_reached_sim_time_returns_at_once(ctx) -> None:
    # rclpy waits for the next jump here (forever if /clock stopped); posekit checks first
    clock = ROSClock()
    clock._set_ros_time_is_active(True)
    clock.set_ros_time_override(Time(seconds=5, clock_type=ClockType.ROS_TIME))
    assert clock.sleep_until(Time(seconds=4, clock_type=ClockType.ROS_TIME), ctx)
    assert clock.sleep_for(Duration(), ctx)
    assert not clock._jump_handles  # its jump callback is gone again
    assert not ctx._on_shutdown  # and so is its shutdown callback


def test_sleep_for_follows_simulated_time_set_by_another_thread(ctx) -> None:
    clock = ROSClock()
    clock._set_ros_time_is_active(True)
    clock.set_ros_time_override(Time(seconds=1, clock_type=ClockType.ROS_TIME))

    def advance() -> None:
        for s in (2, 3, 4):
            time.sleep(0.02)
            clock.set_ros_time_override(Time(seconds=s, clock_type=ClockType.ROS_TIME))

    mover = threading.Thread(target=advance)
    mover.start()
    started = time.monotonic()
    assert clock.sleep_for(Duration(seconds=2.5), ctx)
    assert clock.now().nanoseconds >= 3_500_000_000
    assert time.monotonic() - started < 5.0
    mover.join()


def test_active_ros_clock_follows_override_and_fires_jumps() -> None:
    clock = ROSClock()
    seen: list[TimeJump] = []
    clock.create_jump_callback(
        JumpThreshold(min_forward=Duration(seconds=5), min_backward=Duration(nanoseconds=-1)),
        post_callback=seen.append,
    )
    clock._set_ros_time_override(1_000)
    clock._set_ros_time_is_active(True)
    assert clock.now().nanoseconds == 1_000
    assert seen[-1].clock_change == ClockChange.ROS_TIME_ACTIVATED
    seen.clear()
    clock._set_ros_time_override(2_000_000_000)  # +2 s: below the forward threshold
    assert seen == []
    clock._set_ros_time_override(8_000_000_000)  # +6 s: forward jump
    assert [j.delta.nanoseconds for j in seen] == [6_000_000_000]
    clock._set_ros_time_override(7_999_999_999)  # back by 1 ns
    assert seen[-1].delta.nanoseconds == -1
    assert seen[-1].clock_change == ClockChange.ROS_TIME_NO_CHANGE


def test_jump_threshold_validation_and_unregister() -> None:
    with pytest.raises(ValueError, match="negative"):
        JumpThreshold(min_backward=Duration(seconds=1))
    with pytest.raises(ValueError, match="positive"):
        JumpThreshold(min_forward=Duration(seconds=-1))
    clock = ROSClock()
    clock._set_ros_time_is_active(True)
    calls: list[TimeJump] = []
    handle = clock.create_jump_callback(
        JumpThreshold(min_backward=Duration(nanoseconds=-1)), post_callback=calls.append
    )
    clock._set_ros_time_override(10)
    clock._set_ros_time_override(5)
    assert len(calls) == 1
    handle.unregister()
    clock._set_ros_time_override(1)
    assert len(calls) == 1
