"""``from posekit import rclpy``: rclpy's top-level names, re-exported from posekit.runtime.

Submodules mirror rclpy: ``posekit.rclpy.node``, ``.time``, ``.duration``, ``.qos``,
``.executors``, ``.parameter``, ``.clock``, ``.logging``, ``.callback_groups``, ``.task``,
``.exceptions``, ``.utilities``, ``.service``, ``.client``, ``.timer``, ``.wait_for_message``,
``.publisher``, ``.subscription``, ``.context``, ``.guard_condition``,
``.topic_endpoint_info``; imported when asked for, as rclpy's: ``.lifecycle``,
``.parameter_client``, ``.parameter_event_handler``, ``.parameter_service``,
``.qos_overriding_options``,
``.serialization``, ``.constants``, ``.clock_type``, ``.type_hash``, ``.expand_topic_name``,
``.topic_or_service_is_hidden`` and the ``.validate_*`` name checks.
"""

from __future__ import annotations

from posekit.rclpy import (
    callback_groups,
    client,
    clock,
    context,
    duration,
    exceptions,
    executors,
    guard_condition,
    logging,
    node,
    parameter,
    publisher,
    qos,
    service,
    subscription,
    task,
    time,
    timer,
    topic_endpoint_info,
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
    "context",
    "create_node",
    "duration",
    "exceptions",
    "executors",
    "get_default_context",
    "get_global_executor",
    "get_logger",
    "guard_condition",
    "init",
    "logging",
    "node",
    "ok",
    "parameter",
    "publisher",
    "qos",
    "service",
    "shutdown",
    "spin",
    "spin_once",
    "spin_until_future_complete",
    "subscription",
    "task",
    "time",
    "timer",
    "topic_endpoint_info",
    "try_shutdown",
    "utilities",
    "wait_for_message",
]
