"""rclpy.utilities: ``remove_ros_args`` and the context helpers."""

from posekit.runtime.arguments import remove_ros_args
from posekit.runtime.context import get_default_context, ok, shutdown, try_shutdown

__all__ = ["get_default_context", "ok", "remove_ros_args", "shutdown", "try_shutdown"]
