"""rclpy.action: ``ActionServer``, ``ActionClient`` and friends (from posekit.runtime.action)."""

from posekit.runtime.action import (
    ActionClient,
    ActionServer,
    CancelResponse,
    GoalResponse,
)

__all__ = ["ActionClient", "ActionServer", "CancelResponse", "GoalResponse"]
