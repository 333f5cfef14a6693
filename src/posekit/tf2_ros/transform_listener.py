"""tf2_ros.transform_listener: ``TransformListener``."""

from posekit.runtime.tf2_ros import TransformListener

__all__ = ["TransformListener"]
