"""rclpy.type_hash: ``TypeHash`` (re-exported from posekit.runtime.topic_endpoint_info)."""

from posekit.runtime.topic_endpoint_info import TypeHash

__all__ = ["TypeHash"]
