"""rclpy.validate_node_name: ``validate_node_name(node_name)``."""

from __future__ import annotations

from typing import Literal

from posekit.runtime.names import validate_node_name as _validate

__all__ = ["validate_node_name"]


def validate_node_name(node_name: str) -> Literal[True]:
    """True for a valid node name; else ``InvalidNodeNameException``."""
    _validate(node_name)
    return True
