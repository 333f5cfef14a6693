"""rclpy.service: ``Service`` (re-exported from posekit.runtime.services)."""

from posekit.runtime.services import Service

__all__ = ["Service"]
