"""Registry of posekit's message and service classes by ROS 2 type name.

``"geometry_msgs/msg/TransformStamped"`` <-> :class:`posekit.msgs.geometry_msgs.TransformStamped`.
The ROS 1 / short form ``"geometry_msgs/TransformStamped"`` is accepted on lookup as well.
Services: ``"std_srvs/srv/SetBool"`` <-> :class:`posekit.msgs.std_srvs.SetBool`; their request
and response classes are messages (``std_srvs/srv/SetBool_Request``) in MESSAGE_CLASSES.
"""

from __future__ import annotations

from types import MappingProxyType
from typing import Any

from posekit.msgs import (
    action_msgs,
    builtin_interfaces,
    geometry_msgs,
    lifecycle_msgs,
    nav_msgs,
    posekit_interfaces,
    rcl_interfaces,
    rosgraph_msgs,
    sensor_msgs,
    std_msgs,
    std_srvs,
    tf2_msgs,
    type_description_interfaces,
    unique_identifier_msgs,
)
from posekit.msgs._service import is_service_type
from posekit.msgs.errors import UnknownMessageTypeError
from posekit.msgs.introspection import install_introspection

__all__ = [
    "ACTION_CLASSES",
    "MESSAGE_CLASSES",
    "SERVICE_CLASSES",
    "find_message_class",
    "get_action_class",
    "get_message_class",
    "get_service_class",
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
    std_srvs,
    unique_identifier_msgs,
    action_msgs,
    posekit_interfaces,
    type_description_interfaces,
    lifecycle_msgs,
)


def _is_action_type(cls: object) -> bool:
    return isinstance(getattr(cls, "__actiontype__", None), str)


def _collect() -> tuple[dict[str, type[Any]], dict[str, type[Any]]]:
    classes: dict[str, type[Any]] = {}
    services: dict[str, type[Any]] = {}
    for module in _MODULES:
        for name in module.__all__:
            cls = getattr(module, name)
            if _is_action_type(cls):
                continue  # ACTION_CLASSES
            if is_service_type(cls):
                services[cls.__srvtype__] = cls
            else:
                classes[cls.__msgtype__] = cls
                install_introspection(cls)
    return classes, services


_messages, _services = _collect()

#: Every posekit message class keyed by its full ROS 2 type name (read-only mapping),
#: service requests and responses (``std_srvs/srv/SetBool_Request``) included.
MESSAGE_CLASSES: MappingProxyType[str, type[Any]] = MappingProxyType(_messages)

#: Every posekit service class keyed by its ROS 2 type name (``std_srvs/srv/SetBool``).
SERVICE_CLASSES: MappingProxyType[str, type[Any]] = MappingProxyType(_services)


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


def get_service_class(name: str) -> type[Any]:
    """Return posekit's service class for ``name``.

    ``"std_srvs/srv/SetBool"``; the short form ``"std_srvs/SetBool"`` works too.
    """
    parts = name.strip("/").split("/")
    if len(parts) == 2 and all(parts):
        parts = [parts[0], "srv", parts[1]]
    full = "/".join(parts)
    if len(parts) != 3 or parts[1] not in ("srv", "action") or not all(parts):
        raise UnknownMessageTypeError(
            f"malformed service type name {name!r} (expected 'pkg/srv/Type')"
        )
    try:
        return SERVICE_CLASSES[full]
    except KeyError:
        raise UnknownMessageTypeError(
            f"posekit has no service class for {full!r}; known: {sorted(SERVICE_CLASSES)}"
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


def find_message_class(name: str) -> type[Any]:
    """posekit's class for ``name``, else the class from rosbags' typestore.

    Any ROS 2 Jazzy type; rosbags is imported only here. Never imports a module named by
    ``name``: type names often come from other peers. Raises :class:`UnknownMessageTypeError`.
    """
    try:
        return get_message_class(name)
    except UnknownMessageTypeError:
        full = normalize_type_name(name)
    try:
        from posekit.msgs.cdr import get_typestore

        cls: type[Any] = get_typestore().types[full]
    except (ImportError, KeyError):
        raise UnknownMessageTypeError(
            f"The passed message type '{name}' is invalid (no definition known)"
        ) from None
    return cls


#: Every posekit action class keyed by its full ROS 2 type name
#: (``"posekit_interfaces/action/NavigateToPose"``).
ACTION_CLASSES: MappingProxyType[str, type[Any]] = MappingProxyType({
    cls.__actiontype__: cls
    for module in _MODULES for name in module.__all__
    if _is_action_type(cls := getattr(module, name))
})


def get_action_class(name: str) -> type[Any]:
    """Return posekit's action class for ``name`` (``"pkg/action/Name"`` or ``"pkg/Name"``)."""
    parts = name.strip("/").split("/")
    full = "/".join(parts) if len(parts) == 3 else (
        f"{parts[0]}/action/{parts[1]}" if len(parts) == 2 else name)
    try:
        return ACTION_CLASSES[full]
    except KeyError:
        raise UnknownMessageTypeError(
            f"posekit has no action class for {full!r}; known: {sorted(ACTION_CLASSES)}"
        ) from None
