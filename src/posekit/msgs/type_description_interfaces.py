"""type_description_interfaces: what a node's ``~/get_type_description`` service answers.

Jazzy's messages for REP-2011 type descriptions (a type's fields, the types it nests) and the
``GetTypeDescription`` service; field order, constants and types as ROS 2 Jazzy's.
:func:`posekit.msgs.type_description.describe_type` fills them for any type of posekit's
type store.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

__all__ = [
    "Field",
    "FieldType",
    "GetTypeDescription",
    "GetTypeDescription_Request",
    "GetTypeDescription_Response",
    "IndividualTypeDescription",
    "KeyValue",
    "TypeDescription",
    "TypeSource",
]


@dataclass(slots=True)
class FieldType:
    """type_description_interfaces/msg/FieldType: a field's type as rosidl numbers it.

    ``type_id`` is a ``FIELD_TYPE_*`` constant: a base id (1 nested type, 2-22 primitives and
    strings) plus 48 for a fixed array, 96 for a bounded and 144 for an unbounded sequence.
    ``capacity``: the array size or sequence bound; ``string_capacity``: a bounded string's
    bound; ``nested_type_name``: the nested type (``pkg/msg/Name``) or ``""``.
    """

    type_id: int = 0
    capacity: int = 0
    string_capacity: int = 0
    nested_type_name: str = ""
    __msgtype__: ClassVar[str] = "type_description_interfaces/msg/FieldType"
    FIELD_TYPE_NOT_SET: ClassVar[int] = 0
    FIELD_TYPE_NESTED_TYPE: ClassVar[int] = 1
    FIELD_TYPE_INT8: ClassVar[int] = 2
    FIELD_TYPE_UINT8: ClassVar[int] = 3
    FIELD_TYPE_INT16: ClassVar[int] = 4
    FIELD_TYPE_UINT16: ClassVar[int] = 5
    FIELD_TYPE_INT32: ClassVar[int] = 6
    FIELD_TYPE_UINT32: ClassVar[int] = 7
    FIELD_TYPE_INT64: ClassVar[int] = 8
    FIELD_TYPE_UINT64: ClassVar[int] = 9
    FIELD_TYPE_FLOAT: ClassVar[int] = 10
    FIELD_TYPE_DOUBLE: ClassVar[int] = 11
    FIELD_TYPE_LONG_DOUBLE: ClassVar[int] = 12
    FIELD_TYPE_CHAR: ClassVar[int] = 13
    FIELD_TYPE_WCHAR: ClassVar[int] = 14
    FIELD_TYPE_BOOLEAN: ClassVar[int] = 15
    FIELD_TYPE_BYTE: ClassVar[int] = 16
    FIELD_TYPE_STRING: ClassVar[int] = 17
    FIELD_TYPE_WSTRING: ClassVar[int] = 18
    FIELD_TYPE_FIXED_STRING: ClassVar[int] = 19
    FIELD_TYPE_FIXED_WSTRING: ClassVar[int] = 20
    FIELD_TYPE_BOUNDED_STRING: ClassVar[int] = 21
    FIELD_TYPE_BOUNDED_WSTRING: ClassVar[int] = 22
    FIELD_TYPE_NESTED_TYPE_ARRAY: ClassVar[int] = 49
    FIELD_TYPE_INT8_ARRAY: ClassVar[int] = 50
    FIELD_TYPE_UINT8_ARRAY: ClassVar[int] = 51
    FIELD_TYPE_INT16_ARRAY: ClassVar[int] = 52
    FIELD_TYPE_UINT16_ARRAY: ClassVar[int] = 53
    FIELD_TYPE_INT32_ARRAY: ClassVar[int] = 54
    FIELD_TYPE_UINT32_ARRAY: ClassVar[int] = 55
    FIELD_TYPE_INT64_ARRAY: ClassVar[int] = 56
    FIELD_TYPE_UINT64_ARRAY: ClassVar[int] = 57
    FIELD_TYPE_FLOAT_ARRAY: ClassVar[int] = 58
    FIELD_TYPE_DOUBLE_ARRAY: ClassVar[int] = 59
    FIELD_TYPE_LONG_DOUBLE_ARRAY: ClassVar[int] = 60
    FIELD_TYPE_CHAR_ARRAY: ClassVar[int] = 61
    FIELD_TYPE_WCHAR_ARRAY: ClassVar[int] = 62
    FIELD_TYPE_BOOLEAN_ARRAY: ClassVar[int] = 63
    FIELD_TYPE_BYTE_ARRAY: ClassVar[int] = 64
    FIELD_TYPE_STRING_ARRAY: ClassVar[int] = 65
    FIELD_TYPE_WSTRING_ARRAY: ClassVar[int] = 66
    FIELD_TYPE_FIXED_STRING_ARRAY: ClassVar[int] = 67
    FIELD_TYPE_FIXED_WSTRING_ARRAY: ClassVar[int] = 68
    FIELD_TYPE_BOUNDED_STRING_ARRAY: ClassVar[int] = 69
    FIELD_TYPE_BOUNDED_WSTRING_ARRAY: ClassVar[int] = 70
    FIELD_TYPE_NESTED_TYPE_BOUNDED_SEQUENCE: ClassVar[int] = 97
    FIELD_TYPE_INT8_BOUNDED_SEQUENCE: ClassVar[int] = 98
    FIELD_TYPE_UINT8_BOUNDED_SEQUENCE: ClassVar[int] = 99
    FIELD_TYPE_INT16_BOUNDED_SEQUENCE: ClassVar[int] = 100
    FIELD_TYPE_UINT16_BOUNDED_SEQUENCE: ClassVar[int] = 101
    FIELD_TYPE_INT32_BOUNDED_SEQUENCE: ClassVar[int] = 102
    FIELD_TYPE_UINT32_BOUNDED_SEQUENCE: ClassVar[int] = 103
    FIELD_TYPE_INT64_BOUNDED_SEQUENCE: ClassVar[int] = 104
    FIELD_TYPE_UINT64_BOUNDED_SEQUENCE: ClassVar[int] = 105
    FIELD_TYPE_FLOAT_BOUNDED_SEQUENCE: ClassVar[int] = 106
    FIELD_TYPE_DOUBLE_BOUNDED_SEQUENCE: ClassVar[int] = 107
    FIELD_TYPE_LONG_DOUBLE_BOUNDED_SEQUENCE: ClassVar[int] = 108
    FIELD_TYPE_CHAR_BOUNDED_SEQUENCE: ClassVar[int] = 109
    FIELD_TYPE_WCHAR_BOUNDED_SEQUENCE: ClassVar[int] = 110
    FIELD_TYPE_BOOLEAN_BOUNDED_SEQUENCE: ClassVar[int] = 111
    FIELD_TYPE_BYTE_BOUNDED_SEQUENCE: ClassVar[int] = 112
    FIELD_TYPE_STRING_BOUNDED_SEQUENCE: ClassVar[int] = 113
    FIELD_TYPE_WSTRING_BOUNDED_SEQUENCE: ClassVar[int] = 114
    FIELD_TYPE_FIXED_STRING_BOUNDED_SEQUENCE: ClassVar[int] = 115
    FIELD_TYPE_FIXED_WSTRING_BOUNDED_SEQUENCE: ClassVar[int] = 116
    FIELD_TYPE_BOUNDED_STRING_BOUNDED_SEQUENCE: ClassVar[int] = 117
    FIELD_TYPE_BOUNDED_WSTRING_BOUNDED_SEQUENCE: ClassVar[int] = 118
    FIELD_TYPE_NESTED_TYPE_UNBOUNDED_SEQUENCE: ClassVar[int] = 145
    FIELD_TYPE_INT8_UNBOUNDED_SEQUENCE: ClassVar[int] = 146
    FIELD_TYPE_UINT8_UNBOUNDED_SEQUENCE: ClassVar[int] = 147
    FIELD_TYPE_INT16_UNBOUNDED_SEQUENCE: ClassVar[int] = 148
    FIELD_TYPE_UINT16_UNBOUNDED_SEQUENCE: ClassVar[int] = 149
    FIELD_TYPE_INT32_UNBOUNDED_SEQUENCE: ClassVar[int] = 150
    FIELD_TYPE_UINT32_UNBOUNDED_SEQUENCE: ClassVar[int] = 151
    FIELD_TYPE_INT64_UNBOUNDED_SEQUENCE: ClassVar[int] = 152
    FIELD_TYPE_UINT64_UNBOUNDED_SEQUENCE: ClassVar[int] = 153
    FIELD_TYPE_FLOAT_UNBOUNDED_SEQUENCE: ClassVar[int] = 154
    FIELD_TYPE_DOUBLE_UNBOUNDED_SEQUENCE: ClassVar[int] = 155
    FIELD_TYPE_LONG_DOUBLE_UNBOUNDED_SEQUENCE: ClassVar[int] = 156
    FIELD_TYPE_CHAR_UNBOUNDED_SEQUENCE: ClassVar[int] = 157
    FIELD_TYPE_WCHAR_UNBOUNDED_SEQUENCE: ClassVar[int] = 158
    FIELD_TYPE_BOOLEAN_UNBOUNDED_SEQUENCE: ClassVar[int] = 159
    FIELD_TYPE_BYTE_UNBOUNDED_SEQUENCE: ClassVar[int] = 160
    FIELD_TYPE_STRING_UNBOUNDED_SEQUENCE: ClassVar[int] = 161
    FIELD_TYPE_WSTRING_UNBOUNDED_SEQUENCE: ClassVar[int] = 162
    FIELD_TYPE_FIXED_STRING_UNBOUNDED_SEQUENCE: ClassVar[int] = 163
    FIELD_TYPE_FIXED_WSTRING_UNBOUNDED_SEQUENCE: ClassVar[int] = 164
    FIELD_TYPE_BOUNDED_STRING_UNBOUNDED_SEQUENCE: ClassVar[int] = 165
    FIELD_TYPE_BOUNDED_WSTRING_UNBOUNDED_SEQUENCE: ClassVar[int] = 166


@dataclass(slots=True)
class Field:
    """type_description_interfaces/msg/Field: a field's name, type and default (text)."""

    name: str = ""
    type: FieldType = field(default_factory=FieldType)
    default_value: str = ""
    __msgtype__: ClassVar[str] = "type_description_interfaces/msg/Field"


@dataclass(slots=True)
class IndividualTypeDescription:
    """type_description_interfaces/msg/IndividualTypeDescription: one type and its fields."""

    type_name: str = ""
    fields: list[Field] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "type_description_interfaces/msg/IndividualTypeDescription"


@dataclass(slots=True)
class TypeDescription:
    """type_description_interfaces/msg/TypeDescription: a type and every type it nests."""

    type_description: IndividualTypeDescription = field(
        default_factory=IndividualTypeDescription)
    referenced_type_descriptions: list[IndividualTypeDescription] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "type_description_interfaces/msg/TypeDescription"


@dataclass(slots=True)
class TypeSource:
    """type_description_interfaces/msg/TypeSource: the text a type was defined in."""

    type_name: str = ""
    encoding: str = ""
    raw_file_contents: str = ""
    __msgtype__: ClassVar[str] = "type_description_interfaces/msg/TypeSource"


@dataclass(slots=True)
class KeyValue:
    """type_description_interfaces/msg/KeyValue."""

    key: str = ""
    value: str = ""
    __msgtype__: ClassVar[str] = "type_description_interfaces/msg/KeyValue"


@dataclass(slots=True)
class GetTypeDescription_Request:  # noqa: N801 - rosidl name
    """The type asked for: its name and ``RIHS01_...`` hash (the hash decides)."""

    type_name: str = ""
    type_hash: str = ""
    include_type_sources: bool = True
    __msgtype__: ClassVar[str] = "type_description_interfaces/srv/GetTypeDescription_Request"


@dataclass(slots=True)
class GetTypeDescription_Response:  # noqa: N801 - rosidl name
    """The description, or ``successful`` False and the ``failure_reason``."""

    successful: bool = False
    failure_reason: str = ""
    type_description: TypeDescription = field(default_factory=TypeDescription)
    type_sources: list[TypeSource] = field(default_factory=list)
    extra_information: list[KeyValue] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "type_description_interfaces/srv/GetTypeDescription_Response"


class GetTypeDescription:
    """type_description_interfaces/srv/GetTypeDescription."""

    Request = GetTypeDescription_Request
    Response = GetTypeDescription_Response
    __srvtype__: ClassVar[str] = "type_description_interfaces/srv/GetTypeDescription"
