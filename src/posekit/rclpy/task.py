"""rclpy.task (re-exported from posekit.runtime.task)."""

from posekit.runtime.task import Future, Task

__all__ = ["Future", "Task"]
