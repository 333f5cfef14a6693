"""rclpy.executors (re-exported from posekit.runtime.executors)."""

from posekit.runtime.executors import (
    Executor,
    ExternalShutdownException,
    MultiThreadedExecutor,
    SimulatedTimeExecutor,
    SingleThreadedExecutor,
)

__all__ = [
    "Executor",
    "ExternalShutdownException",
    "MultiThreadedExecutor",
    "SimulatedTimeExecutor",
    "SingleThreadedExecutor",
]
