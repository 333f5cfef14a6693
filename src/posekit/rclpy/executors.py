"""rclpy.executors (re-exported from posekit.runtime.executors)."""

from posekit.runtime.executors import (
    Executor,
    ExternalShutdownException,
    MultiThreadedExecutor,
    SingleThreadedExecutor,
)
from posekit.runtime.sim_executor import SimulatedTimeExecutor

__all__ = [
    "Executor",
    "ExternalShutdownException",
    "MultiThreadedExecutor",
    "SimulatedTimeExecutor",
    "SingleThreadedExecutor",
]
