"""Clocks as in rclpy: system, steady and ROS time (which follows /clock under use_sim_time).

* ``Clock(clock_type=ClockType.SYSTEM_TIME)``: wall time (``time.time_ns``).
* ``Clock(clock_type=ClockType.STEADY_TIME)``: monotonic time.
* ``Clock(clock_type=ClockType.ROS_TIME)`` is a :class:`ROSClock`, as in rclpy.
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
from typing import TYPE_CHECKING

from posekit.time import ClockType, Duration, Time

if TYPE_CHECKING:
    from posekit.runtime.context import Context

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
    """A clock of one type; ``now()`` returns :class:`posekit.time.Time` with that type.

    As in rclpy, ``Clock(clock_type=ClockType.ROS_TIME)`` returns a :class:`ROSClock`.
    """

    def __new__(cls, *, clock_type: ClockType = ClockType.SYSTEM_TIME) -> Clock:
        """rclpy's dispatch: a ROS_TIME clock is a :class:`ROSClock`."""
        if type(clock_type) is not ClockType:
            raise TypeError("Clock type must be a ClockType enum")
        if clock_type is ClockType.ROS_TIME and cls is Clock:
            cls = ROSClock
        return super().__new__(cls)

    def __init__(self, *, clock_type: ClockType = ClockType.SYSTEM_TIME) -> None:
        if clock_type == ClockType.UNINITIALIZED:
            raise ValueError("cannot create a clock of type UNINITIALIZED")
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
        return Time._of(self.now_ns(), self._clock_type)

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

    def sleep_until(self, until: Time, context: Context | None = None) -> bool:
        """Sleep until this clock reads ``until`` or later (rclpy's ``Clock.sleep_until``).

        A ROS clock with ROS time active (``use_sim_time``) wakes when the simulated time
        reaches ``until`` (it sleeps forever if that time never comes, as in rclpy). Returns
        True when ``until`` was reached, False when the sleep ended early: ``context`` (default:
        the default context) shut down, or ROS time was activated or deactivated meanwhile.

        Raises:
            NotInitializedException: ``context`` is not initialized (or shut down).
            ValueError: ``until`` is a time of another clock type.
        """
        from posekit.runtime.context import NotInitializedException, get_default_context

        if context is None:
            context = get_default_context()
        if not context.ok():
            raise NotInitializedException("sleep")
        if until.clock_type != self._clock_type:
            raise ValueError("until's clock type does not match this clock's type")
        until_ns = until.nanoseconds
        event = threading.Event()
        source_changed = False

        def on_jump(jump: TimeJump) -> None:
            nonlocal source_changed
            # activating or deactivating ROS time changes the epoch: the sleep loses its meaning
            source_changed = source_changed or jump.clock_change in (
                ClockChange.ROS_TIME_ACTIVATED, ClockChange.ROS_TIME_DEACTIVATED)
            if source_changed or self.now_ns() >= until_ns:
                event.set()

        context.on_shutdown(event.set)
        handle = self.create_jump_callback(
            JumpThreshold(min_forward=Duration(nanoseconds=1), min_backward=None,
                          on_clock_change=True),
            post_callback=on_jump,
        )
        try:
            while not event.is_set() and context.ok():
                remaining = until_ns - self.now_ns()
                if remaining <= 0:
                    break
                # simulated time moves by jumps, which set the event; system time by itself
                event.wait(None if self._follows_ros_time() else remaining / 1e9)
        finally:
            handle.unregister()
            context.remove_on_shutdown(event.set)
        if not context.ok() or source_changed:
            return False
        return self.now_ns() >= until_ns

    def sleep_for(self, rel_time: Duration, context: Context | None = None) -> bool:
        """``sleep_until(now() + rel_time, context)`` (rclpy's ``Clock.sleep_for``)."""
        return self.sleep_until(self.now() + rel_time, context)

    def _follows_ros_time(self) -> bool:
        """True while this clock reads simulated time (only a ROSClock can)."""
        return False

    def __repr__(self) -> str:
        return f"Clock(clock_type={self._clock_type.name})"


class ROSClock(Clock):
    """ROS_TIME clock: system time, or the simulated time once ROS time is active."""

    def __new__(cls, *, clock_type: ClockType = ClockType.ROS_TIME) -> ROSClock:
        """A ROS clock (``clock_type`` is there for ``Clock(clock_type=ROS_TIME)``)."""
        del clock_type
        return object.__new__(cls)

    def __init__(self, *, clock_type: ClockType = ClockType.ROS_TIME) -> None:
        del clock_type
        super().__init__(clock_type=ClockType.ROS_TIME)
        self._ros_time_active = False
        self._override_ns = 0

    @property
    def ros_time_is_active(self) -> bool:
        """True while the clock follows simulated time."""
        return self._ros_time_active

    def _follows_ros_time(self) -> bool:
        return self._ros_time_active

    def set_ros_time_override(self, time: Time) -> None:
        """Set the time the clock reports while ROS time is active (rclpy's).

        A TimeSource does this for every ``/clock`` message; jump callbacks fire as then.
        """
        if not isinstance(time, Time):
            raise TypeError(
                f"Time must be specified as rclpy.time.Time. Received type: {type(time)}")
        self._set_ros_time_override(time.nanoseconds)

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
