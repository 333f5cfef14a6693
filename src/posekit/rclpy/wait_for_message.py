"""rclpy.wait_for_message (re-exported from posekit.runtime.wait_for_message)."""

from posekit.runtime.wait_for_message import wait_for_message

__all__ = ["wait_for_message"]
