"""rclpy.time: ``Time`` (re-exported from posekit.time)."""

from posekit.time import ClockType, Time

__all__ = ["ClockType", "Time"]
