"""``~/get_type_description``: the type description service every Jazzy node offers.

The node declares the read-only parameter ``start_type_description_service`` (default True;
an override of False leaves the service out) and serves
``type_description_interfaces/srv/GetTypeDescription`` as rcl does: the request's
``type_hash`` (``RIHS01_<64 hex>``) picks one of the types the node uses now (its
publishers, subscriptions, services and clients, ``/rosout``'s ``Log`` included), and the
answer is that type's description (:func:`posekit.msgs.type_description.describe_type`).
The ``type_name`` is not looked at. An unparsable hash fails with "Failed to parse type
hash" (logged on the ``rcl`` logger, as rcl does), a hash of no type in use with "Type not
currently in use by this node". ``type_sources`` stays empty: posekit carries no ``.msg``
files (a real node sends their text when ``include_type_sources`` is set).
"""

from __future__ import annotations

import re
import weakref
from typing import TYPE_CHECKING, Any

from posekit.msgs.type_description_interfaces import (
    GetTypeDescription,
    GetTypeDescription_Request,
    GetTypeDescription_Response,
)
from posekit.runtime.logging import get_logger
from posekit.runtime.parameters import Parameter, ParameterDescriptor

if TYPE_CHECKING:
    from posekit.runtime.node import Node

__all__ = ["START_TYPE_DESCRIPTION_SERVICE_PARAM", "TypeDescriptionService", "parse_type_hash"]

#: The parameter that switches the service on (read-only; rclpy's name).
START_TYPE_DESCRIPTION_SERVICE_PARAM = "start_type_description_service"

_HASH = re.compile(r"RIHS([0-9]{2})_([0-9a-fA-F]{64})")


def parse_type_hash(text: str) -> tuple[int, bytes]:
    """``(version, 32 bytes)`` of a type hash ``RIHS01_<64 hex>``; ValueError if malformed."""
    match = _HASH.fullmatch(text)
    if match is None:
        raise ValueError(f"not a type hash (RIHSvv_ and 64 hex digits): {text!r}")
    return int(match[1]), bytes.fromhex(match[2])


class TypeDescriptionService:
    """Answers ``~/get_type_description`` for a node (made by every Node, as rclpy's)."""

    def __init__(self, node: Node, *, with_rosout: bool) -> None:
        self._node_ref = weakref.ref(node)
        self._with_rosout = with_rosout
        if not node.has_parameter(START_TYPE_DESCRIPTION_SERVICE_PARAM):
            node.declare_parameter(START_TYPE_DESCRIPTION_SERVICE_PARAM, True, ParameterDescriptor(
                name=START_TYPE_DESCRIPTION_SERVICE_PARAM, type=Parameter.Type.BOOL.value,
                description="If enabled, start the ~/get_type_description service.",
                read_only=True))
        param = node.get_parameter(START_TYPE_DESCRIPTION_SERVICE_PARAM)
        #: Whether the service runs (the parameter's value when the node was made).
        self.enabled = param.type_ == Parameter.Type.BOOL and bool(param.value)
        if param.type_ not in (Parameter.Type.BOOL, Parameter.Type.NOT_SET):
            node.get_logger().error(
                f"Invalid type for parameter '{START_TYPE_DESCRIPTION_SERVICE_PARAM}' "
                f"{param.value!r} should be bool")
        if self.enabled:
            node.create_service(GetTypeDescription, "~/get_type_description", self._answer)

    def _types_in_use(self, node: Node) -> set[str]:
        types: set[Any] = {p.msg_type for p in node.publishers}
        types |= {s.msg_type for s in node.subscriptions}
        types |= {s.srv_type for s in node.services}
        types |= {c.srv_type for c in node.clients}
        names = {getattr(t, "__msgtype__", None) or t.__srvtype__ for t in types}
        if self._with_rosout:
            names.add("rcl_interfaces/msg/Log")
        return names

    def _answer(self, request: GetTypeDescription_Request,
                response: GetTypeDescription_Response) -> GetTypeDescription_Response:
        node = self._node_ref()
        if node is None:
            response.failure_reason = "the node is gone"
            return response
        try:
            wanted = parse_type_hash(request.type_hash)
        except ValueError:
            get_logger("rcl").error(f"Failed to parse type hash '{request.type_hash}'")
            response.failure_reason = "Failed to parse type hash"
            return response
        from posekit.msgs.cdr import type_hash_rihs01

        for type_name in sorted(self._types_in_use(node)):
            if parse_type_hash(type_hash_rihs01(type_name)) == wanted:
                from posekit.msgs.type_description import describe_type

                response.type_description = describe_type(type_name)
                response.successful = True
                return response
        response.failure_reason = "Type not currently in use by this node"
        return response
