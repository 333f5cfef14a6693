"""REP-2011 type descriptions of posekit's types, as a Jazzy node's type description service.

:func:`describe_type` gives the ``type_description_interfaces/msg/TypeDescription`` of any
message or service type of posekit's type store: the type's fields, numbered as rosidl
numbers them (:class:`~posekit.msgs.type_description_interfaces.FieldType`), and every type
it nests, each once, sorted by name. The RIHS01 type hash is the SHA-256 of this
description with the default values left out (tests/msgs/test_type_description.py hashes it
and compares with rosbags' hash of the same type).

Default values are the ones the Jazzy ``.msg`` / ``.srv`` files give, as rosidl writes them
(Python's ``str`` of the parsed value: ``1.0``, ``True``). rosbags' definitions drop them,
so :data:`FIELD_DEFAULTS` lists them; the test checks the list against the Jazzy files the
reference ROS 2 install has (``std_msgs``, ``geometry_msgs``, ``sensor_msgs``,
``rcl_interfaces``, ``type_description_interfaces`` and others). Types of packages it does
not install (``tf2_msgs``, ``visualization_msgs``...) are described without defaults.
"""

from __future__ import annotations

import copy
from functools import cache
from typing import Any

from posekit.msgs.type_description_interfaces import (
    Field,
    FieldType,
    IndividualTypeDescription,
    TypeDescription,
)

__all__ = ["FIELD_DEFAULTS", "describe_type"]

#: type -> field -> default value text, for the fields of posekit's types that have one.
FIELD_DEFAULTS: dict[str, dict[str, str]] = {
    "geometry_msgs/msg/Quaternion": {"x": "0.0", "y": "0.0", "z": "0.0", "w": "1.0"},
    "rcl_interfaces/msg/ParameterDescriptor": {"read_only": "False", "dynamic_typing": "False"},
    "sensor_msgs/msg/NavSatStatus": {"status": "-2"},
    "type_description_interfaces/msg/FieldType": {"type_id": "0"},
    "type_description_interfaces/srv/GetTypeDescription_Request": {
        "include_type_sources": "True"},
}

#: rosidl's base type ids (``FieldType.FIELD_TYPE_*``), by rosbags' base type name (no
#: ``char``: posekit's store holds it as ``uint8``, as rosidl's descriptions do).
_BASE_IDS = {
    "int8": 2, "uint8": 3, "int16": 4, "uint16": 5, "int32": 6, "uint32": 7, "int64": 8,
    "uint64": 9, "float32": 10, "float64": 11, "bool": 15, "byte": 16, "string": 17,
}
_NESTED, _BOUNDED_STRING = FieldType.FIELD_TYPE_NESTED_TYPE, FieldType.FIELD_TYPE_BOUNDED_STRING
#: Added to the element's id: a fixed array, a bounded and an unbounded sequence.
_ARRAY, _BOUNDED_SEQUENCE, _SEQUENCE = 48, 96, 144


def _field_type(desc: Any) -> FieldType:
    """The FieldType of a rosbags field description ``(node type, details)``."""
    from rosbags.interfaces import Nodetype

    kind, details = desc
    offset = capacity = 0
    if kind in (Nodetype.ARRAY, Nodetype.SEQUENCE):
        (kind, details), capacity = details
        if desc[0] == Nodetype.ARRAY:
            offset = _ARRAY
        else:
            offset = _BOUNDED_SEQUENCE if capacity else _SEQUENCE
    if kind == Nodetype.NAME:
        return FieldType(type_id=offset + _NESTED, capacity=capacity, nested_type_name=details)
    base, bound = details
    if base == "string" and bound:
        return FieldType(type_id=offset + _BOUNDED_STRING, capacity=capacity,
                         string_capacity=bound)
    return FieldType(type_id=offset + _BASE_IDS[base], capacity=capacity)


def _individual(store: Any, type_name: str) -> IndividualTypeDescription:
    defaults = FIELD_DEFAULTS.get(type_name, {})
    fields = store.fielddefs[type_name][1]
    if not fields:  # rosidl gives an empty type one placeholder member
        return IndividualTypeDescription(type_name, [Field(
            "structure_needs_at_least_one_member", FieldType(type_id=_BASE_IDS["uint8"]))])
    return IndividualTypeDescription(type_name, [
        Field(name, _field_type(desc), defaults.get(name, "")) for name, desc in fields])


@cache
def _description(type_name: str) -> TypeDescription:
    from posekit.msgs.cdr import get_typestore

    store = get_typestore()
    referenced: dict[str, IndividualTypeDescription] = {}
    main = _individual(store, type_name)
    pending = [main]
    while pending:
        for field in pending.pop().fields:
            nested = field.type.nested_type_name
            if nested and nested not in referenced:
                referenced[nested] = _individual(store, nested)
                pending.append(referenced[nested])
    return TypeDescription(main, [referenced[name] for name in sorted(referenced)])


def describe_type(type_name: str) -> TypeDescription:
    """The type description of ``type_name`` (``pkg/msg/Name``, ``pkg/srv/Name``...).

    A fresh message each call (callers may change it). Raises
    :class:`~posekit.msgs.errors.UnknownMessageTypeError` for a type posekit does not know.
    """
    from posekit.msgs.cdr import get_typestore
    from posekit.msgs.errors import UnknownMessageTypeError

    if type_name not in get_typestore().fielddefs:
        raise UnknownMessageTypeError(f"unknown type {type_name!r} (not in ROS 2 Jazzy)")
    return copy.deepcopy(_description(type_name))
