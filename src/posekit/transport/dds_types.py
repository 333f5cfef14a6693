"""Cyclone DDS topic types for ROS 2 messages, built from the Jazzy message definitions.

Cyclone DDS needs a type description to create a topic: it checks every sample against it
(so a malformed payload is refused before it reaches posekit) and announces it in discovery
(XTypes type information). :func:`idl_struct` builds a ``cyclonedds.idl.IdlStruct`` for a
ROS type from rosbags' Jazzy definitions, named as ROS 2's DDS mapping names it
(``geometry_msgs::msg::dds_::Twist_``), field for field as ``rosidl`` maps ``.msg`` files to
IDL (``char`` is ``uint8``, ``byte`` is ``octet``, bounded strings and sequences keep their
bounds). posekit never uses these classes to (de)serialize: samples travel as the CDR bytes
:mod:`posekit.msgs.cdr` produces.
"""

from __future__ import annotations

import threading
from typing import Any

import cyclonedds.idl as idl
import cyclonedds.idl.types as _types

from posekit.msgs.errors import UnknownMessageTypeError
from posekit.transport.zenoh_wire import dds_type_name

t: Any = _types  # indexed at run time (array[T, n]); the stubs do not say so

__all__ = ["idl_service_struct", "idl_struct"]

_BASE: dict[str, Any] = {
    "bool": bool, "byte": t.byte, "char": t.uint8, "octet": t.byte,
    "int8": t.int8, "uint8": t.uint8, "int16": t.int16, "uint16": t.uint16,
    "int32": t.int32, "uint32": t.uint32, "int64": t.int64, "uint64": t.uint64,
    "float32": t.float32, "float64": t.float64,
}
_BASE_NODE, _NAME_NODE, _ARRAY_NODE, _SEQUENCE_NODE = 1, 2, 3, 4
_lock = threading.RLock()
_cache: dict[str, type] = {}
_service_cache: dict[str, type] = {}


def _field_type(node: tuple[Any, Any]) -> Any:
    kind, detail = node
    kind = int(kind)
    if kind == _BASE_NODE:
        name, bound = detail
        if name == "string":
            return t.bounded_str[bound] if bound else str
        if name not in _BASE:
            raise UnknownMessageTypeError(f"no DDS mapping for the field type {name!r}")
        return _BASE[name]
    if kind == _NAME_NODE:
        return idl_struct(detail)
    inner, size = detail
    if kind == _ARRAY_NODE:
        return t.array[_field_type(inner), size]
    return t.sequence[_field_type(inner), size] if size else t.sequence[_field_type(inner)]


def idl_struct(ros_type: str) -> type:
    """The ``IdlStruct`` class of ``ros_type`` (``pkg/msg/Type``), built once and cached.

    Raises :class:`UnknownMessageTypeError` when Jazzy has no such type.
    """
    with _lock:
        cls = _cache.get(ros_type)
        if cls is not None:
            return cls
        from posekit.msgs.cdr import get_typestore

        store = get_typestore()
        try:
            _consts, fields = store.fielddefs[ros_type]
        except KeyError:
            raise UnknownMessageTypeError(
                f"no ROS 2 Jazzy definition of {ros_type!r} is known"
            ) from None
        members = {name: _field_type(node) for name, node in fields}
        if not members:  # rosidl gives an empty message one placeholder byte
            members = {"structure_needs_at_least_one_member": t.uint8}
        dds_name = dds_type_name(ros_type)
        cls = idl.make_idl_struct(dds_name.replace("::", "_"), dds_name.replace("::", "."),
                                  members)
        _cache[ros_type] = cls
        return cls


def idl_service_struct(ros_type: str) -> type:
    """The topic type of a service request or response (``pkg/srv/Srv_Request``) on DDS.

    rmw_cyclonedds's layout: the 16-byte request header (client id ``uint64``, sequence
    number ``int64``) before the message's fields, under the message's own DDS name
    (``pkg::srv::dds_::Srv_Request_``). Built once and cached.
    """
    with _lock:
        cls = _service_cache.get(ros_type)
        if cls is not None:
            return cls
        message: Any = idl_struct(ros_type)
        fields = dict(message.__annotations__)
        header = {"request_header_client_id": t.uint64,
                  "request_header_sequence_number": t.int64}
        while any(name in fields for name in header):  # never shadow a message field
            header = {f"_{name}": kind for name, kind in header.items()}
        dds_name = dds_type_name(ros_type)
        cls = idl.make_idl_struct(dds_name.replace("::", "_") + "_with_header",
                                  dds_name.replace("::", "."), {**header, **fields})
        _service_cache[ros_type] = cls
        return cls
