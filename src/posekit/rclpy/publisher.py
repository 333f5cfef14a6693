"""rclpy.publisher: ``Publisher`` (re-exported from posekit.runtime.entities)."""

from posekit.runtime.entities import Publisher

__all__ = ["Publisher"]
