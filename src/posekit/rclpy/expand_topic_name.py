"""rclpy.expand_topic_name: ``expand_topic_name(topic_name, node_name, node_namespace)``."""

from __future__ import annotations

from posekit.runtime.names import (
    NameValidationError,
    validate_namespace,
    validate_node_name,
)
from posekit.runtime.names import expand_topic_name as _expand

__all__ = ["expand_topic_name"]


def expand_topic_name(topic_name: str, node_name: str, node_namespace: str) -> str:
    """The fully qualified form of ``topic_name`` for that node (``~``, ``{node}``, ``{ns}``).

    A bad topic name, node name or namespace (it must be absolute) raises ``ValueError``, as
    rclpy. Unlike rclpy's, the result is checked as a full name too (rclpy returns
    ``/a//b`` and refuses it only when it is used).
    """
    try:
        validate_node_name(node_name)
        validate_namespace(node_namespace)
        return _expand(topic_name, node_name, node_namespace)
    except NameValidationError as exc:
        raise ValueError(str(exc)) from None
