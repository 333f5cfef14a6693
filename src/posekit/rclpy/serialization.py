"""rclpy.serialization: a message to its CDR bytes and back (``posekit.msgs.cdr``).

``serialize_message(msg)`` gives the bytes a ROS 2 publisher sends (with the 4-byte
encapsulation header); ``deserialize_message(data, msg_type)`` reads them into a new message
of ``msg_type``. Malformed bytes raise :class:`posekit.msgs.errors.CdrError` (rclpy: its own
error); an argument that is no message or message class raises ``AttributeError``, as rclpy.
"""

from __future__ import annotations

from typing import Any

from posekit.msgs.cdr import from_cdr, to_cdr

__all__ = ["deserialize_message", "serialize_message"]


def _type_name(msg_type: Any) -> str:
    name = getattr(msg_type, "__msgtype__", None)
    if not isinstance(name, str):
        raise AttributeError(f"{msg_type!r} is not a message type (no __msgtype__)")
    return name


def serialize_message(message: Any) -> bytes:
    """The CDR bytes of ``message``."""
    _type_name(type(message))
    return to_cdr(message)


def deserialize_message(serialized_message: bytes, message_type: type[Any]) -> Any:
    """A ``message_type`` read from CDR bytes."""
    _type_name(message_type)
    return from_cdr(serialized_message, message_type)
