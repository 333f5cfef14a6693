"""rclpy.node: ``Node`` (re-exported from posekit.runtime.node)."""

from posekit.runtime.node import Node

__all__ = ["Node"]
