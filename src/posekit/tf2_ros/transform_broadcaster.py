"""tf2_ros.transform_broadcaster: ``TransformBroadcaster``."""

from posekit.runtime.tf2_ros import TransformBroadcaster

__all__ = ["TransformBroadcaster"]
