"""rcl_interfaces: the parameter messages and services every ROS 2 node serves, and Log.

Field order, constants and types are ROS 2 Jazzy's. Primitive sequence fields
(``ParameterValue.integer_array_value``...) are numpy arrays (``byte[]`` as int8, the dtype
rosbags decodes it to) and accept lists too; string sequences are lists. Service classes
follow rosidl: ``GetParameters.Request`` is :class:`GetParameters_Request`
(``rcl_interfaces/srv/GetParameters_Request``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt

from posekit.msgs._base import array_aware_eq
from posekit.msgs.builtin_interfaces import Time

__all__ = [
    "DescribeParameters",
    "DescribeParameters_Request",
    "DescribeParameters_Response",
    "FloatingPointRange",
    "GetParameterTypes",
    "GetParameterTypes_Request",
    "GetParameterTypes_Response",
    "GetParameters",
    "GetParameters_Request",
    "GetParameters_Response",
    "IntegerRange",
    "ListParameters",
    "ListParametersResult",
    "ListParameters_Request",
    "ListParameters_Response",
    "Log",
    "Parameter",
    "ParameterDescriptor",
    "ParameterEvent",
    "ParameterType",
    "ParameterValue",
    "SetParameters",
    "SetParametersAtomically",
    "SetParametersAtomically_Request",
    "SetParametersAtomically_Response",
    "SetParametersResult",
    "SetParameters_Request",
    "SetParameters_Response",
]


def _empty(dtype: type[np.generic]) -> Callable[[], npt.NDArray[Any]]:
    return lambda: np.zeros(0, dtype=dtype)


# -- messages ---------------------------------------------------------------------------
@dataclass(slots=True)
class ParameterType:
    """rcl_interfaces/msg/ParameterType: only the ``PARAMETER_*`` constants (0..9)."""

    structure_needs_at_least_one_member: int = 0
    PARAMETER_NOT_SET: ClassVar[int] = 0
    PARAMETER_BOOL: ClassVar[int] = 1
    PARAMETER_INTEGER: ClassVar[int] = 2
    PARAMETER_DOUBLE: ClassVar[int] = 3
    PARAMETER_STRING: ClassVar[int] = 4
    PARAMETER_BYTE_ARRAY: ClassVar[int] = 5
    PARAMETER_BOOL_ARRAY: ClassVar[int] = 6
    PARAMETER_INTEGER_ARRAY: ClassVar[int] = 7
    PARAMETER_DOUBLE_ARRAY: ClassVar[int] = 8
    PARAMETER_STRING_ARRAY: ClassVar[int] = 9
    __msgtype__: ClassVar[str] = "rcl_interfaces/msg/ParameterType"


@dataclass(slots=True, eq=False)
class ParameterValue:
    """rcl_interfaces/msg/ParameterValue.

    ``type`` (a ParameterType constant) says which ``*_value`` field holds the value.
    """

    type: int = 0
    bool_value: bool = False
    integer_value: int = 0
    double_value: float = 0.0
    string_value: str = ""
    byte_array_value: npt.NDArray[np.int8] = field(default_factory=_empty(np.int8))
    bool_array_value: npt.NDArray[np.bool_] = field(default_factory=_empty(np.bool_))
    integer_array_value: npt.NDArray[np.int64] = field(default_factory=_empty(np.int64))
    double_array_value: npt.NDArray[np.float64] = field(default_factory=_empty(np.float64))
    string_array_value: list[str] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "rcl_interfaces/msg/ParameterValue"
    __eq__ = array_aware_eq


@dataclass(slots=True)
class Parameter:
    """rcl_interfaces/msg/Parameter: a ``name`` and its ParameterValue."""

    name: str = ""
    value: ParameterValue = field(default_factory=ParameterValue)
    __msgtype__: ClassVar[str] = "rcl_interfaces/msg/Parameter"


@dataclass(slots=True)
class FloatingPointRange:
    """rcl_interfaces/msg/FloatingPointRange.

    Inclusive [from_value, to_value], ``step`` 0 for a continuous range.
    """

    from_value: float = 0.0
    to_value: float = 0.0
    step: float = 0.0
    __msgtype__: ClassVar[str] = "rcl_interfaces/msg/FloatingPointRange"


@dataclass(slots=True)
class IntegerRange:
    """rcl_interfaces/msg/IntegerRange.

    Inclusive [from_value, to_value], ``step`` 0 for any integer in it.
    """

    from_value: int = 0
    to_value: int = 0
    step: int = 0
    __msgtype__: ClassVar[str] = "rcl_interfaces/msg/IntegerRange"


@dataclass(slots=True)
class ParameterDescriptor:
    """rcl_interfaces/msg/ParameterDescriptor. At most one range (a list of length <= 1)."""

    name: str = ""
    type: int = 0
    description: str = ""
    additional_constraints: str = ""
    read_only: bool = False
    dynamic_typing: bool = False
    floating_point_range: list[FloatingPointRange] = field(default_factory=list)
    integer_range: list[IntegerRange] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "rcl_interfaces/msg/ParameterDescriptor"


@dataclass(slots=True)
class SetParametersResult:
    """rcl_interfaces/msg/SetParametersResult: ``successful`` or the ``reason`` why not."""

    successful: bool = False
    reason: str = ""
    __msgtype__: ClassVar[str] = "rcl_interfaces/msg/SetParametersResult"


@dataclass(slots=True)
class ListParametersResult:
    """rcl_interfaces/msg/ListParametersResult: parameter ``names`` and their ``prefixes``."""

    names: list[str] = field(default_factory=list)
    prefixes: list[str] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "rcl_interfaces/msg/ListParametersResult"


@dataclass(slots=True)
class ParameterEvent:
    """rcl_interfaces/msg/ParameterEvent (``/parameter_events``).

    What changed on ``node`` (its fully qualified name) at ``stamp``.
    """

    stamp: Time = field(default_factory=Time)
    node: str = ""
    new_parameters: list[Parameter] = field(default_factory=list)
    changed_parameters: list[Parameter] = field(default_factory=list)
    deleted_parameters: list[Parameter] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "rcl_interfaces/msg/ParameterEvent"


@dataclass(slots=True)
class Log:
    """rcl_interfaces/msg/Log (``/rosout``): one log record; ``level`` is a constant below."""

    stamp: Time = field(default_factory=Time)
    level: int = 0
    name: str = ""
    msg: str = ""
    file: str = ""
    function: str = ""
    line: int = 0
    DEBUG: ClassVar[int] = 10
    INFO: ClassVar[int] = 20
    WARN: ClassVar[int] = 30
    ERROR: ClassVar[int] = 40
    FATAL: ClassVar[int] = 50
    __msgtype__: ClassVar[str] = "rcl_interfaces/msg/Log"


# -- services ---------------------------------------------------------------------------
@dataclass(slots=True)
class ListParameters_Request:  # noqa: N801 - rosidl name
    """Names under ``prefixes`` (all if empty) down to ``depth`` dots (0: recursive)."""

    prefixes: list[str] = field(default_factory=list)
    depth: int = 0
    DEPTH_RECURSIVE: ClassVar[int] = 0
    __msgtype__: ClassVar[str] = "rcl_interfaces/srv/ListParameters_Request"


@dataclass(slots=True)
class ListParameters_Response:  # noqa: N801 - rosidl name
    """The listed names and prefixes."""

    result: ListParametersResult = field(default_factory=ListParametersResult)
    __msgtype__: ClassVar[str] = "rcl_interfaces/srv/ListParameters_Response"


class ListParameters:
    """rcl_interfaces/srv/ListParameters."""

    Request = ListParameters_Request
    Response = ListParameters_Response
    __srvtype__: ClassVar[str] = "rcl_interfaces/srv/ListParameters"


@dataclass(slots=True)
class GetParameters_Request:  # noqa: N801 - rosidl name
    """The parameter ``names`` to read."""

    names: list[str] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "rcl_interfaces/srv/GetParameters_Request"


@dataclass(slots=True)
class GetParameters_Response:  # noqa: N801 - rosidl name
    """One value per requested name (type NOT_SET for an unknown one)."""

    values: list[ParameterValue] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "rcl_interfaces/srv/GetParameters_Response"


class GetParameters:
    """rcl_interfaces/srv/GetParameters."""

    Request = GetParameters_Request
    Response = GetParameters_Response
    __srvtype__: ClassVar[str] = "rcl_interfaces/srv/GetParameters"


@dataclass(slots=True)
class SetParameters_Request:  # noqa: N801 - rosidl name
    """Parameters to set one by one."""

    parameters: list[Parameter] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "rcl_interfaces/srv/SetParameters_Request"


@dataclass(slots=True)
class SetParameters_Response:  # noqa: N801 - rosidl name
    """One result per parameter."""

    results: list[SetParametersResult] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "rcl_interfaces/srv/SetParameters_Response"


class SetParameters:
    """rcl_interfaces/srv/SetParameters."""

    Request = SetParameters_Request
    Response = SetParameters_Response
    __srvtype__: ClassVar[str] = "rcl_interfaces/srv/SetParameters"


@dataclass(slots=True)
class SetParametersAtomically_Request:  # noqa: N801 - rosidl name
    """Parameters to set all together or not at all."""

    parameters: list[Parameter] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "rcl_interfaces/srv/SetParametersAtomically_Request"


@dataclass(slots=True)
class SetParametersAtomically_Response:  # noqa: N801 - rosidl name
    """One result for the whole set."""

    result: SetParametersResult = field(default_factory=SetParametersResult)
    __msgtype__: ClassVar[str] = "rcl_interfaces/srv/SetParametersAtomically_Response"


class SetParametersAtomically:
    """rcl_interfaces/srv/SetParametersAtomically."""

    Request = SetParametersAtomically_Request
    Response = SetParametersAtomically_Response
    __srvtype__: ClassVar[str] = "rcl_interfaces/srv/SetParametersAtomically"


@dataclass(slots=True)
class DescribeParameters_Request:  # noqa: N801 - rosidl name
    """The parameter ``names`` to describe."""

    names: list[str] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "rcl_interfaces/srv/DescribeParameters_Request"


@dataclass(slots=True)
class DescribeParameters_Response:  # noqa: N801 - rosidl name
    """One descriptor per requested name."""

    descriptors: list[ParameterDescriptor] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "rcl_interfaces/srv/DescribeParameters_Response"


class DescribeParameters:
    """rcl_interfaces/srv/DescribeParameters."""

    Request = DescribeParameters_Request
    Response = DescribeParameters_Response
    __srvtype__: ClassVar[str] = "rcl_interfaces/srv/DescribeParameters"


@dataclass(slots=True)
class GetParameterTypes_Request:  # noqa: N801 - rosidl name
    """The parameter ``names`` whose types are wanted."""

    names: list[str] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "rcl_interfaces/srv/GetParameterTypes_Request"


@dataclass(slots=True, eq=False)
class GetParameterTypes_Response:  # noqa: N801 - rosidl name
    """One ParameterType constant per requested name."""

    types: npt.NDArray[np.uint8] = field(default_factory=_empty(np.uint8))
    __msgtype__: ClassVar[str] = "rcl_interfaces/srv/GetParameterTypes_Response"
    __eq__ = array_aware_eq


class GetParameterTypes:
    """rcl_interfaces/srv/GetParameterTypes."""

    Request = GetParameterTypes_Request
    Response = GetParameterTypes_Response
    __srvtype__: ClassVar[str] = "rcl_interfaces/srv/GetParameterTypes"
