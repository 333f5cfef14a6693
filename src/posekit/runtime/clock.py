"""Clocks as in rclpy: system, steady and ROS time (which follows /clock under use_sim_time).

* ``Clock(clock_type=ClockType.SYSTEM_TIME)``: wall time (``time.time_ns``).
* ``Clock(clock_type=ClockType.STEADY_TIME)``: monotonic time.
* :class:`ROSClock` (``ClockType.ROS_TIME``, what ``node.get_clock()`` returns): system time
  until ROS time is activated (``use_sim_time``), then the last time received on ``/clock``
  (or set by a :class:`~posekit.runtime.sim_executor.SimulatedTimeExecutor`); 0 before the first.

Jump callbacks (``create_jump_callback``) fire on a ROS clock when the simulated time moves by
more than a threshold (backwards: ``delta <= min_backward``, a negative Duration; forwards:
``delta >= min_forward``) or when ROS time is (de)activated (``on_clock_change``).
"""

from __future__ import annotations

import enum
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

from posekit.time import ClockType, Duration, Time

__all__ = [
    "Clock",
    "ClockChange",
    "ClockType",
    "JumpHandle",
    "JumpThreshold",
    "ROSClock",
    "TimeJump",
]


class ClockChange(enum.IntEnum):
    """rcl_clock_change_t."""

    ROS_TIME_NO_CHANGE = 1
    ROS_TIME_ACTIVATED = 2
    ROS_TIME_DEACTIVATED = 3
    SYSTEM_TIME_NO_CHANGE = 4


@dataclass(frozen=True, slots=True)
class TimeJump:
    """What happened: ``clock_change`` and the signed ``delta`` (new - old)."""

    clock_change: ClockChange
    delta: Duration


@dataclass(frozen=True, slots=True)
class JumpThreshold:
    """When a jump callback fires. ``None`` disables that direction.

    ``min_backward`` must be negative (e.g. ``Duration(nanoseconds=-1)`` = any backward jump).
    """

    min_forward: Duration | None = None
    min_backward: Duration | None = None
    on_clock_change: bool = True

    def __post_init__(self) -> None:
        if self.min_forward is not None and self.min_forward.nanoseconds <= 0:
            raise ValueError("min_forward must be a positive duration")
        if self.min_backward is not None and self.min_backward.nanoseconds >= 0:
            raise ValueError("min_backward must be a negative duration")

    def triggers(self, jump: TimeJump) -> bool:
        """Whether a jump exceeds this threshold."""
        if jump.clock_change in (ClockChange.ROS_TIME_ACTIVATED, ClockChange.ROS_TIME_DEACTIVATED):
            return self.on_clock_change
        d = jump.delta.nanoseconds
        if d < 0 and self.min_backward is not None:
            return d <= self.min_backward.nanoseconds
        if d > 0 and self.min_forward is not None:
            return d >= self.min_forward.nanoseconds
        return False


JumpCallback = Callable[[TimeJump], None]


class JumpHandle:
    """Returned by ``create_jump_callback``; ``unregister()`` removes the callback."""

    def __init__(
        self,
        clock: Clock,
        threshold: JumpThreshold,
        pre_callback: Callable[[], None] | None,
        post_callback: JumpCallback | None,
    ) -> None:
        self._clock = clock
        self.threshold = threshold
        self.pre_callback = pre_callback
        self.post_callback = post_callback

    def unregister(self) -> None:
        """Stop receiving jumps."""
        self._clock._remove_jump_handle(self)


class Clock:
    """A clock of one type; ``now()`` returns :class:`posekit.time.Time` with that type."""

    def __init__(self, *, clock_type: ClockType = ClockType.SYSTEM_TIME) -> None:
        clock_type = ClockType(clock_type)
        if clock_type == ClockType.UNINITIALIZED:
            raise ValueError("cannot create a clock of type UNINITIALIZED")
        if clock_type == ClockType.ROS_TIME and type(self) is Clock:
            raise TypeError("use ROSClock() for ROS_TIME")
        self._clock_type = clock_type
        self._jump_handles: list[JumpHandle] = []
        self._lock = threading.Lock()

    @property
    def clock_type(self) -> ClockType:
        """Which time this clock reads."""
        return self._clock_type

    def now_ns(self) -> int:
        """Current time in integer nanoseconds (the fast path used by timers)."""
        if self._clock_type == ClockType.STEADY_TIME:
            return time.monotonic_ns()
        return time.time_ns()

    def now(self) -> Time:
        """Current time as a Time of this clock's type."""
        return Time(nanoseconds=self.now_ns(), clock_type=self._clock_type)

    def create_jump_callback(
        self,
        threshold: JumpThreshold,
        *,
        pre_callback: Callable[[], None] | None = None,
        post_callback: JumpCallback | None = None,
    ) -> JumpHandle:
        """Register callbacks for time jumps exceeding ``threshold`` (only ROS clocks jump)."""
        handle = JumpHandle(self, threshold, pre_callback, post_callback)
        with self._lock:
            self._jump_handles.append(handle)
        return handle

    def _remove_jump_handle(self, handle: JumpHandle) -> None:
        with self._lock:
            if handle in self._jump_handles:
                self._jump_handles.remove(handle)

    def __repr__(self) -> str:
        return f"Clock(clock_type={self._clock_type.name})"


class ROSClock(Clock):
    """ROS_TIME clock: system time, or the simulated time once ROS time is active."""

    def __init__(self) -> None:
        super().__init__(clock_type=ClockType.ROS_TIME)
        self._ros_time_active = False
        self._override_ns = 0

    @property
    def ros_time_is_active(self) -> bool:
        """True while the clock follows simulated time."""
        return self._ros_time_active

    def now_ns(self) -> int:
        """The current time (ns): simulated time while ROS time is active, else system time."""
        if self._ros_time_active:
            return self._override_ns
        return time.time_ns()

    def _set_ros_time_is_active(self, active: bool) -> None:
        if active == self._ros_time_active:
            return
        change = ClockChange.ROS_TIME_ACTIVATED if active else ClockChange.ROS_TIME_DEACTIVATED
        before = self.now_ns()
        self._ros_time_active = active
        self._fire(TimeJump(change, Duration(nanoseconds=self.now_ns() - before)))

    def _set_ros_time_override(self, ns: int) -> None:
        """Set the simulated time (ns); fires jump callbacks when active and thresholds hit."""
        old = self._override_ns
        self._override_ns = int(ns)
        if self._ros_time_active and ns != old and self._jump_handles:
            self._fire(TimeJump(ClockChange.ROS_TIME_NO_CHANGE, Duration(nanoseconds=ns - old)))

    def _fire(self, jump: TimeJump) -> None:
        with self._lock:
            handles = [h for h in self._jump_handles if h.threshold.triggers(jump)]
        for h in handles:
            if h.pre_callback is not None:
                h.pre_callback()
        for h in handles:
            if h.post_callback is not None:
                h.post_callback(jump)
