"""``AsyncParameterClient``: another node's parameters through its parameter services.

rclpy's class (rclpy.parameter_client): each call sends one request to
``<remote node>/<service>`` and returns the :class:`~posekit.runtime.task.Future` of the
response (``rcl_interfaces.srv.*.Response``); ``callback`` becomes a done-callback. Spin the
node (or an executor with it) to get the answer. ``wait_for_services`` waits for all six
services, ``on_parameter_event`` subscribes to ``/parameter_events``.
tests/rclpy/differential/parameter_client.py compares it with the real rclpy.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

from posekit.msgs.rcl_interfaces import (
    DescribeParameters,
    GetParameters,
    GetParameterTypes,
    ListParameters,
    ParameterEvent,
    SetParameters,
    SetParametersAtomically,
)
from posekit.msgs.rcl_interfaces import Parameter as ParameterMsg
from posekit.runtime.parameters import Parameter, parameter_dict_from_yaml_file
from posekit.runtime.qos import (
    QoSProfile,
    qos_profile_parameter_events,
    qos_profile_services_default,
)

if TYPE_CHECKING:
    from posekit.runtime.callback_groups import CallbackGroup
    from posekit.runtime.entities import Subscription
    from posekit.runtime.node import Node
    from posekit.runtime.services import Client
    from posekit.runtime.task import Future

__all__ = ["AsyncParameterClient"]


class AsyncParameterClient:
    """The parameters of node ``remote_node_name``, read and changed from ``node``."""

    def __init__(self, node: Node, remote_node_name: str,
                 qos_profile: QoSProfile = qos_profile_services_default,
                 callback_group: CallbackGroup | None = None) -> None:
        self.remote_node_name = remote_node_name
        self.node = node

        def client(srv_type: type, suffix: str) -> Client:
            return node.create_client(srv_type, f"{remote_node_name}/{suffix}",
                                      qos_profile=qos_profile, callback_group=callback_group)

        self._clients: dict[str, Client] = {
            "list": client(ListParameters, "list_parameters"),
            "get": client(GetParameters, "get_parameters"),
            "set": client(SetParameters, "set_parameters"),
            "types": client(GetParameterTypes, "get_parameter_types"),
            "describe": client(DescribeParameters, "describe_parameters"),
            "atomic": client(SetParametersAtomically, "set_parameters_atomically"),
        }

    def services_are_ready(self) -> bool:
        """Whether all six parameter services of the remote node are available."""
        return all(c.service_is_ready() for c in self._clients.values())

    def wait_for_services(self, timeout_sec: float | None = None) -> bool:
        """Wait up to ``timeout_sec`` wall seconds (None: forever) for all six services."""
        deadline = None if timeout_sec is None else time.monotonic() + timeout_sec
        for c in self._clients.values():
            remaining = None if deadline is None else max(0.0, deadline - time.monotonic())
            if not c.wait_for_service(timeout_sec=remaining):
                return False
        return True

    def _send(self, which: str, request: Any, callback: Callable[..., Any] | None) -> Future[Any]:
        future = self._clients[which].call_async(request)
        if callback:
            future.add_done_callback(callback)
        return future

    @staticmethod
    def _messages(parameters: Sequence[Parameter | ParameterMsg]) -> list[ParameterMsg]:
        return [p.to_parameter_msg() if isinstance(p, Parameter) else p for p in parameters]

    def list_parameters(self, prefixes: list[str] | None = None, depth: int | None = None,
                        callback: Callable[..., Any] | None = None) -> Future[Any]:
        """The names (and prefixes) under ``prefixes`` down to ``depth`` (None: all)."""
        request = ListParameters.Request()
        if prefixes:
            request.prefixes = list(prefixes)
        if depth:
            request.depth = depth
        return self._send("list", request, callback)

    def get_parameters(self, names: list[str],
                       callback: Callable[..., Any] | None = None) -> Future[Any]:
        """The values of ``names`` (``ParameterValue``s)."""
        return self._send("get", GetParameters.Request(names=list(names)), callback)

    def set_parameters(self, parameters: Sequence[Parameter | ParameterMsg],
                       callback: Callable[..., Any] | None = None) -> Future[Any]:
        """Set each parameter; a result per parameter."""
        return self._send("set", SetParameters.Request(parameters=self._messages(parameters)),
                          callback)

    def describe_parameters(self, names: list[str],
                            callback: Callable[..., Any] | None = None) -> Future[Any]:
        """The descriptors of ``names``."""
        return self._send("describe", DescribeParameters.Request(names=list(names)), callback)

    def get_parameter_types(self, names: list[str],
                            callback: Callable[..., Any] | None = None) -> Future[Any]:
        """The types of ``names`` (``Parameter.Type`` values)."""
        return self._send("types", GetParameterTypes.Request(names=list(names)), callback)

    def set_parameters_atomically(self, parameters: Sequence[Parameter | ParameterMsg],
                                  callback: Callable[..., Any] | None = None) -> Future[Any]:
        """Set all parameters or none; one result."""
        return self._send("atomic", SetParametersAtomically.Request(
            parameters=self._messages(parameters)), callback)

    def delete_parameters(self, names: list[str],
                          callback: Callable[..., Any] | None = None) -> Future[Any]:
        """Unset ``names`` (only dynamically typed parameters can be); a result per name."""
        return self.set_parameters([Parameter(name) for name in names], callback)

    def load_parameter_file(self, parameter_file: str, use_wildcard: bool = False,
                            callback: Callable[..., Any] | None = None) -> Future[Any]:
        """Set the parameters of a YAML parameter file (``use_wildcard``: its ``/**`` too)."""
        params = parameter_dict_from_yaml_file(parameter_file, use_wildcard)
        return self.set_parameters(list(params.values()), callback)

    def load_parameter_file_atomically(
            self, parameter_file: str, use_wildcard: bool = False,
            callback: Callable[..., Any] | None = None) -> Future[Any]:
        """As :meth:`load_parameter_file`, all parameters or none."""
        params = parameter_dict_from_yaml_file(parameter_file, use_wildcard)
        return self.set_parameters_atomically(list(params.values()), callback)

    def on_parameter_event(self, callback: Callable[..., Any],
                           qos_profile: QoSProfile = qos_profile_parameter_events, *,
                           callback_group: CallbackGroup | None = None,
                           **kwargs: Any) -> Subscription:
        """Subscribe ``callback`` to ``/parameter_events`` (every node's parameter changes)."""
        return self.node.create_subscription(ParameterEvent, "/parameter_events", callback,
                                             qos_profile, callback_group=callback_group,
                                             **kwargs)
