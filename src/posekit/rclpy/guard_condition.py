"""rclpy.guard_condition: ``GuardCondition`` (re-exported from posekit.runtime)."""

from posekit.runtime.guard_condition import GuardCondition

__all__ = ["GuardCondition"]
