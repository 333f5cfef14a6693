"""rclpy.clock (re-exported from posekit.runtime.clock)."""

from posekit.runtime.clock import (
    Clock,
    ClockChange,
    ClockType,
    JumpHandle,
    JumpThreshold,
    ROSClock,
    TimeJump,
)

__all__ = [
    "Clock",
    "ClockChange",
    "ClockType",
    "JumpHandle",
    "JumpThreshold",
    "ROSClock",
    "TimeJump",
]
