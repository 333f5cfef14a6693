"""rclpy.validate_topic_name: ``validate_topic_name(name, *, is_service=False)``."""

from __future__ import annotations

from collections.abc import Callable
from typing import Literal

from posekit.runtime.names import InvalidServiceNameException, InvalidTopicNameException
from posekit.runtime.names import validate_topic_name as _validate

__all__ = ["checked_as", "validate_topic_name"]


def checked_as(check: Callable[[str], object], name: str, is_service: bool) -> Literal[True]:
    """True once ``check(name)`` passed (a service name's error as a service name's).

    With ``is_service``, an InvalidTopicNameException becomes rclpy's
    InvalidServiceNameException.
    """
    try:
        check(name)
    except InvalidTopicNameException as exc:
        if is_service:
            raise InvalidServiceNameException(exc.name, exc.reason, exc.index) from None
        raise
    return True


def validate_topic_name(name: str, *, is_service: bool = False) -> Literal[True]:
    """True for a valid (not necessarily expanded) name; else rclpy's exception.

    ``InvalidTopicNameException``, or ``InvalidServiceNameException`` with ``is_service``.
    """
    return checked_as(_validate, name, is_service)
