"""rclpy.clock_type: ``ClockType`` (re-exported from posekit.time)."""

from posekit.time import ClockType

__all__ = ["ClockType"]
