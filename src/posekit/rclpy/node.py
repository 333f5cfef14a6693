"""rclpy.node: ``Node``, ``NodeNameNonExistentError`` and ``HIDDEN_NODE_PREFIX``.

Re-exported from posekit.runtime.node.
"""

from posekit.runtime.node import Node, NodeNameNonExistentError

__all__ = ["HIDDEN_NODE_PREFIX", "Node", "NodeNameNonExistentError"]

#: A node whose name starts with this is hidden from ``node list`` (as rclpy's).
HIDDEN_NODE_PREFIX = "_"
