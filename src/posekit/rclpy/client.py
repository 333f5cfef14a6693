"""rclpy.client: ``Client`` (re-exported from posekit.runtime.services)."""

from posekit.runtime.services import Client

__all__ = ["Client"]
