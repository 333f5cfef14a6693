"""``ParameterEventHandler``: callbacks on other nodes' parameter changes (rclpy's class).

One ``/parameter_events`` subscription on ``node``; ``add_parameter_callback(name,
node_name, callback)`` calls ``callback(parameter)`` (an ``rcl_interfaces/msg/Parameter``)
whenever node ``node_name`` (relative names in ``node``'s namespace) declares or changes
``name``; ``add_parameter_event_callback(callback)`` gets every ``ParameterEvent``. The most
recently added callback runs first, as in rclpy. Removing a handle that is not there raises
``RuntimeError("Callback doesn't exist")``. tests/rclpy/differential/parameter_events.py
compares it with the real rclpy.
"""

from __future__ import annotations

import itertools
import threading
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, Any

from posekit.msgs.rcl_interfaces import Parameter as ParameterMsg
from posekit.msgs.rcl_interfaces import ParameterEvent
from posekit.runtime.qos import QoSProfile, qos_profile_parameter_events

if TYPE_CHECKING:
    from posekit.runtime.callback_groups import CallbackGroup
    from posekit.runtime.node import Node

__all__ = ["ParameterCallbackHandle", "ParameterEventCallbackHandle", "ParameterEventHandler"]


class ParameterCallbackHandle:
    """What :meth:`ParameterEventHandler.add_parameter_callback` returns (keep it to remove)."""

    def __init__(self, parameter_name: str, node_name: str,
                 callback: Callable[[ParameterMsg], None]) -> None:
        self.parameter_name = parameter_name
        self.node_name = node_name
        self.callback = callback


class ParameterEventCallbackHandle:
    """What :meth:`ParameterEventHandler.add_parameter_event_callback` returns."""

    def __init__(self, callback: Callable[[ParameterEvent], None]) -> None:
        self.callback = callback


class ParameterEventHandler:
    """Monitor and respond to parameter changes of any node, through ``/parameter_events``."""

    def __init__(self, node: Node, qos_profile: QoSProfile = qos_profile_parameter_events,
                 callback_group: CallbackGroup | None = None, **kwargs: Any) -> None:
        self.node = node
        self.qos_profile = qos_profile
        self._lock = threading.Lock()
        self._parameter_callbacks: dict[tuple[str, str], list[ParameterCallbackHandle]] = {}
        self._event_callbacks: list[ParameterEventCallbackHandle] = []
        self.parameter_event_subscription = node.create_subscription(
            ParameterEvent, "/parameter_events", self._on_event, qos_profile,
            callback_group=callback_group, **kwargs)

    def destroy(self) -> None:
        """Stop listening (destroys the subscription)."""
        self.node.destroy_subscription(self.parameter_event_subscription)

    @staticmethod
    def get_parameter_from_event(event: ParameterEvent, parameter_name: str,
                                 node_name: str) -> ParameterMsg | None:
        """``parameter_name`` as declared or changed by node ``node_name`` in ``event``."""
        if event.node == node_name:
            for parameter in ParameterEventHandler.get_parameters_from_event(event):
                if parameter.name == parameter_name:
                    return parameter
        return None

    @staticmethod
    def get_parameters_from_event(event: ParameterEvent) -> Iterator[ParameterMsg]:
        """Every parameter ``event`` declares or changes (deleted ones are not listed)."""
        yield from itertools.chain(event.new_parameters, event.changed_parameters)

    def _on_event(self, event: ParameterEvent) -> None:
        with self._lock:
            watched = [(key, list(handles)) for key, handles in self._parameter_callbacks.items()]
            event_handles = list(self._event_callbacks)
        for (parameter_name, node_name), handles in watched:
            parameter = self.get_parameter_from_event(event, parameter_name, node_name)
            if parameter is not None:
                for handle in handles:
                    handle.callback(parameter)
        for event_handle in event_handles:
            event_handle.callback(event)

    def add_parameter_callback(self, parameter_name: str, node_name: str,
                               callback: Callable[[ParameterMsg], None]
                               ) -> ParameterCallbackHandle:
        """Call ``callback(parameter)`` when node ``node_name`` sets ``parameter_name``."""
        handle = ParameterCallbackHandle(parameter_name, self._resolve_path(node_name), callback)
        with self._lock:
            key = (handle.parameter_name, handle.node_name)
            self._parameter_callbacks.setdefault(key, []).insert(0, handle)
        return handle

    def remove_parameter_callback(self, handle: ParameterCallbackHandle) -> None:
        """Forget a parameter callback (RuntimeError if it is not there)."""
        key = (handle.parameter_name, handle.node_name)
        with self._lock:
            handles = self._parameter_callbacks.get(key, [])
            if handle not in handles:
                raise RuntimeError("Callback doesn't exist")
            handles.remove(handle)
            if not handles:
                del self._parameter_callbacks[key]

    def add_parameter_event_callback(self, callback: Callable[[ParameterEvent], None]
                                     ) -> ParameterEventCallbackHandle:
        """Call ``callback(event)`` for every parameter event."""
        handle = ParameterEventCallbackHandle(callback)
        with self._lock:
            self._event_callbacks.insert(0, handle)
        return handle

    def remove_parameter_event_callback(self, handle: ParameterEventCallbackHandle) -> None:
        """Forget an event callback (RuntimeError if it is not there)."""
        with self._lock:
            if handle not in self._event_callbacks:
                raise RuntimeError("Callback doesn't exist")
            self._event_callbacks.remove(handle)

    def _resolve_path(self, node_path: str | None = None) -> str:
        """A node's fully qualified name: relative names are in this node's namespace."""
        if not node_path:
            return self.node.get_fully_qualified_name()
        if node_path.startswith("/"):
            return node_path
        namespace = self.node.get_namespace().strip("/")
        return f"/{namespace}/{node_path}" if namespace else f"/{node_path}"
