"""The six parameter services every node offers (rclpy's ParameterService).

``<node>/list_parameters``, ``get_parameters``, ``set_parameters``,
``set_parameters_atomically``, ``describe_parameters`` and ``get_parameter_types``
(rcl_interfaces/srv/*), relative to the node's namespace, QoS ``qos_profile_parameters``.
They answer as rclpy's do, including its quirks: a request naming one undeclared parameter
gets an *empty* list of values / descriptors / types, and ``set_parameters`` reports an
undeclared name as an unsuccessful result with the exception text as the reason.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from posekit.msgs.rcl_interfaces import (
    DescribeParameters,
    DescribeParameters_Request,
    DescribeParameters_Response,
    GetParameters,
    GetParameters_Request,
    GetParameters_Response,
    GetParameterTypes,
    GetParameterTypes_Request,
    GetParameterTypes_Response,
    ListParameters,
    ListParameters_Request,
    ListParameters_Response,
    ListParametersResult,
    SetParameters,
    SetParameters_Request,
    SetParameters_Response,
    SetParametersAtomically,
    SetParametersAtomically_Request,
    SetParametersAtomically_Response,
    SetParametersResult,
)
from posekit.runtime.parameters import (
    Parameter,
    ParameterNotDeclaredException,
    ParameterUninitializedException,
)
from posekit.runtime.qos import qos_profile_parameters

if TYPE_CHECKING:
    from posekit.runtime.node import Node

__all__ = ["PARAMETER_SERVICE_SUFFIXES", "ParameterService"]

#: The service names (after ``<node name>/``) and types, in rclpy's creation order.
PARAMETER_SERVICE_SUFFIXES: tuple[tuple[str, type], ...] = (
    ("describe_parameters", DescribeParameters),
    ("get_parameters", GetParameters),
    ("get_parameter_types", GetParameterTypes),
    ("list_parameters", ListParameters),
    ("set_parameters", SetParameters),
    ("set_parameters_atomically", SetParametersAtomically),
)


class ParameterService:
    """Serves a node's parameters (created by ``Node(start_parameter_services=True)``)."""

    def __init__(self, node: Node) -> None:
        self._node_ref = weakref.ref(node)
        handlers: dict[str, Callable[[Any, Any], Any]] = {
            "describe_parameters": self._describe,
            "get_parameters": self._get,
            "get_parameter_types": self._get_types,
            "list_parameters": self._list,
            "set_parameters": self._set,
            "set_parameters_atomically": self._set_atomically,
        }
        for suffix, srv_type in PARAMETER_SERVICE_SUFFIXES:
            node.create_service(
                srv_type, f"{node.get_name()}/{suffix}", handlers[suffix],
                qos_profile=qos_profile_parameters,
            )

    def _node(self) -> Node:
        node = self._node_ref()
        if node is None:
            raise ReferenceError("the node of this parameter service is gone")
        return node

    def _describe(
        self, request: DescribeParameters_Request, response: DescribeParameters_Response
    ) -> DescribeParameters_Response:
        node = self._node()
        for name in request.names:
            try:
                response.descriptors.append(node.describe_parameter(name))
            except ParameterNotDeclaredException:
                response.descriptors = []
                break
        return response

    def _get(
        self, request: GetParameters_Request, response: GetParameters_Response
    ) -> GetParameters_Response:
        node = self._node()
        for name in request.names:
            try:
                response.values.append(node.get_parameter(name).get_parameter_value())
            except (ParameterNotDeclaredException, ParameterUninitializedException):
                response.values = []
                break
        return response

    def _get_types(
        self, request: GetParameterTypes_Request, response: GetParameterTypes_Response
    ) -> GetParameterTypes_Response:
        node = self._node()
        types: list[int] = []
        for name in request.names:
            try:
                types.append(node.get_parameter_type(name))
            except ParameterNotDeclaredException:
                types = []
                break
        response.types = np.array(types, dtype=np.uint8)
        return response

    def _list(
        self, request: ListParameters_Request, response: ListParameters_Response
    ) -> ListParameters_Response:
        try:
            response.result = self._node().list_parameters(
                list(request.prefixes), int(request.depth)
            )
        except (TypeError, ValueError):
            response.result = ListParametersResult()
        return response

    def _set(
        self, request: SetParameters_Request, response: SetParameters_Response
    ) -> SetParameters_Response:
        node = self._node()
        for msg in request.parameters:
            try:
                result = node.set_parameters_atomically([Parameter.from_parameter_msg(msg)])
            except ParameterNotDeclaredException as exc:
                result = SetParametersResult(successful=False, reason=str(exc))
            except (ValueError, RuntimeError) as exc:  # a malformed ParameterValue
                result = SetParametersResult(successful=False, reason=str(exc))
            response.results.append(result)
        return response

    def _set_atomically(
        self, request: SetParametersAtomically_Request,
        response: SetParametersAtomically_Response,
    ) -> SetParametersAtomically_Response:
        node = self._node()
        try:
            response.result = node.set_parameters_atomically(
                [Parameter.from_parameter_msg(msg) for msg in request.parameters]
            )
        except ParameterNotDeclaredException as exc:
            response.result = SetParametersResult(successful=False, reason=str(exc))
        except (ValueError, RuntimeError) as exc:
            response.result = SetParametersResult(successful=False, reason=str(exc))
        return response
