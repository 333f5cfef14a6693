"""tf2_ros.static_transform_broadcaster: ``StaticTransformBroadcaster``."""

from posekit.runtime.tf2_ros import StaticTransformBroadcaster

__all__ = ["StaticTransformBroadcaster"]
