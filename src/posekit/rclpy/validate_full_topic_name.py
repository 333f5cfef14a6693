"""rclpy.validate_full_topic_name: ``validate_full_topic_name(name, *, is_service=False)``."""

from __future__ import annotations

from typing import Literal

from posekit.rclpy.validate_topic_name import checked_as
from posekit.runtime.names import validate_full_topic_name as _validate

__all__ = ["validate_full_topic_name"]


def validate_full_topic_name(name: str, *, is_service: bool = False) -> Literal[True]:
    """True for a valid fully qualified (absolute, expanded) name; else rclpy's exception."""
    return checked_as(_validate, name, is_service)
