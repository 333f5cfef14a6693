"""``from posekit import rclpy``: rclpy's top-level names, re-exported from posekit.runtime.

Submodules mirror rclpy: ``posekit.rclpy.node``, ``.time``, ``.duration``, ``.qos``,
``.executors``, ``.parameter``, ``.clock``, ``.logging``, ``.callback_groups``, ``.task``,
``.exceptions``, ``.utilities``.
``.exceptions``, ``.service``, ``.client``, ``.timer``, ``.wait_for_message``.
"""

from __future__ import annotations

from posekit.rclpy import (
    callback_groups,
    client,
    clock,
    duration,
    exceptions,
    executors,
    logging,
    node,
    parameter,
    qos,
    service,
    task,
    time,
    timer,
    utilities,
    wait_for_message,
)
from posekit.runtime import create_node
from posekit.runtime.context import Context, get_default_context, init, ok, shutdown, try_shutdown
from posekit.runtime.executors import (
    get_global_executor,
    spin,
    spin_once,
    spin_until_future_complete,
)
from posekit.runtime.logging import get_logger

__all__ = [
    "Context",
    "callback_groups",
    "client",
    "clock",
    "create_node",
    "duration",
    "exceptions",
    "executors",
    "get_default_context",
    "get_global_executor",
    "get_logger",
    "init",
    "logging",
    "node",
    "ok",
    "parameter",
    "qos",
    "service",
    "shutdown",
    "spin",
    "spin_once",
    "spin_until_future_complete",
    "task",
    "time",
    "timer",
    "try_shutdown",
    "utilities",
    "wait_for_message",
]
