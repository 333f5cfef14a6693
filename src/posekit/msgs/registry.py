"""Registry of posekit's message classes by ROS 2 type name.

``"geometry_msgs/msg/TransformStamped"`` <-> :class:`posekit.msgs.geometry_msgs.TransformStamped`.
The ROS 1 / short form ``"geometry_msgs/TransformStamped"`` is accepted on lookup as well.
"""

from __future__ import annotations

from types import MappingProxyType
from typing import Any

from posekit.msgs import (
    builtin_interfaces,
    geometry_msgs,
    nav_msgs,
    rcl_interfaces,
    rosgraph_msgs,
    sensor_msgs,
    std_msgs,
    tf2_msgs,
)
from posekit.msgs.errors import UnknownMessageTypeError
from posekit.msgs.introspection import install_introspection

__all__ = [
    "MESSAGE_CLASSES",
    "get_message_class",
    "message_type_name",
    "normalize_type_name",
]

_MODULES = (
    builtin_interfaces,
    std_msgs,
    geometry_msgs,
    nav_msgs,
    sensor_msgs,
    tf2_msgs,
    rosgraph_msgs,
    rcl_interfaces,
)


def _collect() -> dict[str, type[Any]]:
    classes: dict[str, type[Any]] = {}
    for module in _MODULES:
        for name in module.__all__:
            cls = getattr(module, name)
            classes[cls.__msgtype__] = cls
            install_introspection(cls)
    return classes


#: Every posekit message class keyed by its full ROS 2 type name (read-only mapping).
MESSAGE_CLASSES: MappingProxyType[str, type[Any]] = MappingProxyType(_collect())


def normalize_type_name(name: str) -> str:
    """Return the full ROS 2 form ``pkg/msg/Type`` of ``name``.

    Accepts ``pkg/msg/Type`` and the short form ``pkg/Type``; anything else raises
    :class:`UnknownMessageTypeError`.
    """
    parts = name.strip("/").split("/")
    if len(parts) == 3 and all(parts) and parts[1] in ("msg", "srv", "action"):
        return "/".join(parts)
    if len(parts) == 2 and all(parts):
        return f"{parts[0]}/msg/{parts[1]}"
    raise UnknownMessageTypeError(
        f"malformed message type name {name!r} (expected 'pkg/msg/Type')"
    )


def get_message_class(name: str) -> type[Any]:
    """Return posekit's class for the ROS 2 type ``name`` (``"tf2_msgs/msg/TFMessage"``)."""
    full = normalize_type_name(name)
    try:
        return MESSAGE_CLASSES[full]
    except KeyError:
        raise UnknownMessageTypeError(
            f"posekit has no message class for {full!r}; known: {sorted(MESSAGE_CLASSES)}"
        ) from None


def message_type_name(msg_or_cls: object) -> str:
    """Return the ROS 2 type name of a message instance or class (its ``__msgtype__``).

    Works for posekit messages and, by duck typing, for rosbags' message classes.
    """
    name = getattr(msg_or_cls, "__msgtype__", None)
    if not isinstance(name, str):
        raise UnknownMessageTypeError(
            f"{type(msg_or_cls).__name__} is not a ROS message (no __msgtype__ attribute)"
        )
    return name
