"""rclpy.topic_or_service_is_hidden: ``topic_or_service_is_hidden(name)``."""

from posekit.runtime.names import is_hidden_name as topic_or_service_is_hidden

__all__ = ["topic_or_service_is_hidden"]
