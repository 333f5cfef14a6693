"""rclpy.action.client (re-exported from posekit.runtime.action)."""

from posekit.runtime.action import ActionClient, ClientGoalHandle

__all__ = ["ActionClient", "ClientGoalHandle"]
