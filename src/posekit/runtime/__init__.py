"""posekit's rclpy-style runtime: contexts, nodes, executors, clocks, QoS and the in-process bus.

See docs/runtime.md.

The rclpy-named facade :mod:`posekit.rclpy` re-exports from here; :mod:`posekit.tf2_ros`
(the listener and broadcasters) is built on it, one layer up.
"""

from __future__ import annotations

from posekit.runtime.clock import Clock, JumpThreshold, ROSClock, TimeJump
from posekit.runtime.context import Context, get_default_context, init, ok, shutdown
from posekit.runtime.executors import (
    Executor,
    Future,
    MultiThreadedExecutor,
    SingleThreadedExecutor,
    spin,
    spin_once,
    spin_until_future_complete,
)
from posekit.runtime.logging import get_logger
from posekit.runtime.node import Node
from posekit.runtime.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    QoSProfile,
    ReliabilityPolicy,
    qos_profile_sensor_data,
)
from posekit.runtime.sim_executor import SimulatedTimeExecutor

__all__ = [
    "Clock",
    "Context",
    "DurabilityPolicy",
    "Executor",
    "Future",
    "HistoryPolicy",
    "JumpThreshold",
    "MultiThreadedExecutor",
    "Node",
    "QoSProfile",
    "ROSClock",
    "ReliabilityPolicy",
    "SimulatedTimeExecutor",
    "SingleThreadedExecutor",
    "TimeJump",
    "create_node",
    "get_default_context",
    "get_logger",
    "init",
    "ok",
    "qos_profile_sensor_data",
    "shutdown",
    "spin",
    "spin_once",
    "spin_until_future_complete",
]


def create_node(node_name: str, **kwargs: object) -> Node:
    """rclpy.create_node: ``Node(node_name, **kwargs)``."""
    return Node(node_name, **kwargs)  # type: ignore[arg-type]
