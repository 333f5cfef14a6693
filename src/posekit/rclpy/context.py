"""rclpy.context: ``Context`` (re-exported from posekit.runtime.context)."""

from posekit.runtime.context import Context

__all__ = ["Context"]
