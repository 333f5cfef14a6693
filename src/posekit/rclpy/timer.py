"""rclpy.timer: ``Timer`` and ``Rate`` (re-exported from posekit.runtime)."""

from posekit.runtime.entities import Timer
from posekit.runtime.rate import Rate

__all__ = ["Rate", "Timer"]
