"""rclpy.topic_endpoint_info (re-exported from posekit.runtime.topic_endpoint_info)."""

from posekit.runtime.topic_endpoint_info import TopicEndpointInfo, TopicEndpointTypeEnum, TypeHash

__all__ = ["TopicEndpointInfo", "TopicEndpointTypeEnum", "TypeHash"]
