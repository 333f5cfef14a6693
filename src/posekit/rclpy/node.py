"""rclpy.node: ``Node`` and ``NodeNameNonExistentError`` (re-exported from posekit.runtime.node)."""

from posekit.runtime.node import Node, NodeNameNonExistentError

__all__ = ["Node", "NodeNameNonExistentError"]
