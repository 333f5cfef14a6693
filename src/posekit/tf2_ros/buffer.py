"""tf2_ros.buffer: ``Buffer`` (from posekit.tf2)."""

from posekit.tf2 import Buffer

__all__ = ["Buffer"]
