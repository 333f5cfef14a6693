"""rclpy.validate_full_topic_name: ``validate_full_topic_name(name, *, is_service=False)``."""

from __future__ import annotations

from typing import Literal

from posekit.runtime.names import (
    InvalidServiceNameException,
    InvalidTopicNameException,
)
from posekit.runtime.names import (
    validate_full_topic_name as _validate,
)

__all__ = ["validate_full_topic_name"]


def validate_full_topic_name(name: str, *, is_service: bool = False) -> Literal[True]:
    """True for a valid fully qualified (absolute, expanded) name; else rclpy's exception."""
    try:
        _validate(name)
    except InvalidTopicNameException as exc:
        if is_service:
            raise InvalidServiceNameException(exc.name, exc.reason, exc.index) from None
        raise
    return True
