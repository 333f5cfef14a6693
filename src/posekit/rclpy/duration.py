"""rclpy.duration: ``Duration`` (re-exported from posekit.time)."""

from posekit.time import Duration

__all__ = ["Duration"]
