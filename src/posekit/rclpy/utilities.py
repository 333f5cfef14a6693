"""rclpy.utilities: ``remove_ros_args``, the context helpers and ``timeout_sec_to_nsec``."""

from __future__ import annotations

from posekit.runtime.arguments import remove_ros_args
from posekit.runtime.context import get_default_context, ok, shutdown, try_shutdown

__all__ = ["get_default_context", "ok", "remove_ros_args", "shutdown", "timeout_sec_to_nsec",
           "try_shutdown"]


def timeout_sec_to_nsec(timeout_sec: float | None) -> int:
    """A timeout in seconds as nanoseconds; None or negative is -1 (wait forever), as rclpy."""
    if timeout_sec is None or timeout_sec < 0:
        return -1
    return int(float(timeout_sec) * 1e9)
