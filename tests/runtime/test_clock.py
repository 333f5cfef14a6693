"""Clocks: system/steady/ROS time, sim-time override and jump callbacks."""

from __future__ import annotations

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
from posekit.time import Duration


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


def test_ros_time_type_needs_rosclock() -> None:
    with pytest.raises(TypeError):
        Clock(clock_type=ClockType.ROS_TIME)


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
