"""rclpy.duration: ``Duration`` (re-exported from posekit.time) and ``Infinite``."""

from posekit.time import Duration

__all__ = ["Duration", "Infinite"]

#: rclpy's infinite duration (the largest int64 nanoseconds; it prints as ``Infinite``).
Infinite = Duration(nanoseconds=2**63 - 1)
