"""rclpy.validate_namespace: ``validate_namespace(namespace)``."""

from __future__ import annotations

from typing import Literal

from posekit.runtime.names import validate_namespace as _validate

__all__ = ["validate_namespace"]


def validate_namespace(namespace: str) -> Literal[True]:
    """True for a valid absolute namespace; else ``InvalidNamespaceException``."""
    _validate(namespace)
    return True
