"""std_msgs: every ROS 2 Jazzy std_msgs message.

Header, the scalar wrappers, ColorRGBA, Empty, MultiArrayLayout / MultiArrayDimension and
the MultiArrays.

Field names, order and defaults are Jazzy's. As elsewhere in posekit.msgs, numeric sequences
(the MultiArrays' ``data``) are 1-D numpy arrays of the element type (rclpy: ``array.array``
or a list), and ``byte`` values are ints, as rosbags decodes them: ``Byte.data`` is an int
(rclpy: ``bytes`` of length 1) and ``ByteMultiArray.data`` an int8 array. ``Empty`` carries
rosidl's placeholder field ``structure_needs_at_least_one_member`` (one byte on the wire).
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
    "Bool",
    "Byte",
    "ByteMultiArray",
    "Char",
    "ColorRGBA",
    "Empty",
    "Float32",
    "Float32MultiArray",
    "Float64",
    "Float64MultiArray",
    "Header",
    "Int8",
    "Int8MultiArray",
    "Int16",
    "Int16MultiArray",
    "Int32",
    "Int32MultiArray",
    "Int64",
    "Int64MultiArray",
    "MultiArrayDimension",
    "MultiArrayLayout",
    "String",
    "UInt8",
    "UInt8MultiArray",
    "UInt16",
    "UInt16MultiArray",
    "UInt32",
    "UInt32MultiArray",
    "UInt64",
    "UInt64MultiArray",
]


def _empty(dtype: type[np.generic]) -> Callable[[], npt.NDArray[Any]]:
    def make() -> npt.NDArray[Any]:
        return np.zeros(0, dtype=dtype)

    return make


@dataclass(slots=True)
class Header:
    """std_msgs/msg/Header: ``stamp`` and the ``frame_id`` the data is expressed in."""

    stamp: Time = field(default_factory=Time)
    frame_id: str = ""
    __msgtype__: ClassVar[str] = "std_msgs/msg/Header"


@dataclass(slots=True)
class Bool:
    """std_msgs/msg/Bool."""

    data: bool = False
    __msgtype__: ClassVar[str] = "std_msgs/msg/Bool"


@dataclass(slots=True)
class String:
    """std_msgs/msg/String."""

    data: str = ""
    __msgtype__: ClassVar[str] = "std_msgs/msg/String"


@dataclass(slots=True)
class Float64:
    """std_msgs/msg/Float64."""

    data: float = 0.0
    __msgtype__: ClassVar[str] = "std_msgs/msg/Float64"


@dataclass(slots=True)
class Byte:
    """std_msgs/msg/Byte: an int 0..255, as rosbags decodes it (rclpy: ``bytes`` of length 1)."""

    data: int = 0
    __msgtype__: ClassVar[str] = "std_msgs/msg/Byte"


@dataclass(slots=True)
class Char:
    """std_msgs/msg/Char: an int 0..255."""

    data: int = 0
    __msgtype__: ClassVar[str] = "std_msgs/msg/Char"


@dataclass(slots=True)
class Int8:
    """std_msgs/msg/Int8."""

    data: int = 0
    __msgtype__: ClassVar[str] = "std_msgs/msg/Int8"


@dataclass(slots=True)
class UInt8:
    """std_msgs/msg/UInt8."""

    data: int = 0
    __msgtype__: ClassVar[str] = "std_msgs/msg/UInt8"


@dataclass(slots=True)
class Int16:
    """std_msgs/msg/Int16."""

    data: int = 0
    __msgtype__: ClassVar[str] = "std_msgs/msg/Int16"


@dataclass(slots=True)
class UInt16:
    """std_msgs/msg/UInt16."""

    data: int = 0
    __msgtype__: ClassVar[str] = "std_msgs/msg/UInt16"


@dataclass(slots=True)
class Int32:
    """std_msgs/msg/Int32."""

    data: int = 0
    __msgtype__: ClassVar[str] = "std_msgs/msg/Int32"


@dataclass(slots=True)
class UInt32:
    """std_msgs/msg/UInt32."""

    data: int = 0
    __msgtype__: ClassVar[str] = "std_msgs/msg/UInt32"


@dataclass(slots=True)
class Int64:
    """std_msgs/msg/Int64."""

    data: int = 0
    __msgtype__: ClassVar[str] = "std_msgs/msg/Int64"


@dataclass(slots=True)
class UInt64:
    """std_msgs/msg/UInt64."""

    data: int = 0
    __msgtype__: ClassVar[str] = "std_msgs/msg/UInt64"


@dataclass(slots=True)
class Float32:
    """std_msgs/msg/Float32."""

    data: float = 0.0
    __msgtype__: ClassVar[str] = "std_msgs/msg/Float32"


@dataclass(slots=True)
class ColorRGBA:
    """std_msgs/msg/ColorRGBA: red, green, blue and alpha, each in [0, 1] (float32)."""

    r: float = 0.0
    g: float = 0.0
    b: float = 0.0
    a: float = 0.0
    __msgtype__: ClassVar[str] = "std_msgs/msg/ColorRGBA"


@dataclass(slots=True)
class Empty:
    """std_msgs/msg/Empty (no fields; CDR carries one placeholder byte)."""

    structure_needs_at_least_one_member: int = 0
    __msgtype__: ClassVar[str] = "std_msgs/msg/Empty"


@dataclass(slots=True)
class MultiArrayDimension:
    """std_msgs/msg/MultiArrayDimension: a ``label``, its ``size`` and ``stride`` (elements)."""

    label: str = ""
    size: int = 0
    stride: int = 0
    __msgtype__: ClassVar[str] = "std_msgs/msg/MultiArrayDimension"


@dataclass(slots=True)
class MultiArrayLayout:
    """std_msgs/msg/MultiArrayLayout: the dimensions (outermost first) and ``data_offset``."""

    dim: list[MultiArrayDimension] = field(default_factory=list)
    data_offset: int = 0
    __msgtype__: ClassVar[str] = "std_msgs/msg/MultiArrayLayout"


@dataclass(slots=True, eq=False)
class ByteMultiArray:
    """std_msgs/msg/ByteMultiArray: ``data`` a 1-D int8 array (as rosbags decodes bytes)."""

    layout: MultiArrayLayout = field(default_factory=MultiArrayLayout)
    data: npt.NDArray[np.int8] = field(default_factory=_empty(np.int8))
    __msgtype__: ClassVar[str] = "std_msgs/msg/ByteMultiArray"
    __eq__ = array_aware_eq


@dataclass(slots=True, eq=False)
class Int8MultiArray:
    """std_msgs/msg/Int8MultiArray: ``data`` a 1-D int8 array laid out by ``layout``."""

    layout: MultiArrayLayout = field(default_factory=MultiArrayLayout)
    data: npt.NDArray[np.int8] = field(default_factory=_empty(np.int8))
    __msgtype__: ClassVar[str] = "std_msgs/msg/Int8MultiArray"
    __eq__ = array_aware_eq


@dataclass(slots=True, eq=False)
class UInt8MultiArray:
    """std_msgs/msg/UInt8MultiArray: ``data`` a 1-D uint8 array laid out by ``layout``."""

    layout: MultiArrayLayout = field(default_factory=MultiArrayLayout)
    data: npt.NDArray[np.uint8] = field(default_factory=_empty(np.uint8))
    __msgtype__: ClassVar[str] = "std_msgs/msg/UInt8MultiArray"
    __eq__ = array_aware_eq


@dataclass(slots=True, eq=False)
class Int16MultiArray:
    """std_msgs/msg/Int16MultiArray: ``data`` a 1-D int16 array laid out by ``layout``."""

    layout: MultiArrayLayout = field(default_factory=MultiArrayLayout)
    data: npt.NDArray[np.int16] = field(default_factory=_empty(np.int16))
    __msgtype__: ClassVar[str] = "std_msgs/msg/Int16MultiArray"
    __eq__ = array_aware_eq


@dataclass(slots=True, eq=False)
class UInt16MultiArray:
    """std_msgs/msg/UInt16MultiArray: ``data`` a 1-D uint16 array laid out by ``layout``."""

    layout: MultiArrayLayout = field(default_factory=MultiArrayLayout)
    data: npt.NDArray[np.uint16] = field(default_factory=_empty(np.uint16))
    __msgtype__: ClassVar[str] = "std_msgs/msg/UInt16MultiArray"
    __eq__ = array_aware_eq


@dataclass(slots=True, eq=False)
class Int32MultiArray:
    """std_msgs/msg/Int32MultiArray: ``data`` a 1-D int32 array laid out by ``layout``."""

    layout: MultiArrayLayout = field(default_factory=MultiArrayLayout)
    data: npt.NDArray[np.int32] = field(default_factory=_empty(np.int32))
    __msgtype__: ClassVar[str] = "std_msgs/msg/Int32MultiArray"
    __eq__ = array_aware_eq


@dataclass(slots=True, eq=False)
class UInt32MultiArray:
    """std_msgs/msg/UInt32MultiArray: ``data`` a 1-D uint32 array laid out by ``layout``."""

    layout: MultiArrayLayout = field(default_factory=MultiArrayLayout)
    data: npt.NDArray[np.uint32] = field(default_factory=_empty(np.uint32))
    __msgtype__: ClassVar[str] = "std_msgs/msg/UInt32MultiArray"
    __eq__ = array_aware_eq


@dataclass(slots=True, eq=False)
class Int64MultiArray:
    """std_msgs/msg/Int64MultiArray: ``data`` a 1-D int64 array laid out by ``layout``."""

    layout: MultiArrayLayout = field(default_factory=MultiArrayLayout)
    data: npt.NDArray[np.int64] = field(default_factory=_empty(np.int64))
    __msgtype__: ClassVar[str] = "std_msgs/msg/Int64MultiArray"
    __eq__ = array_aware_eq


@dataclass(slots=True, eq=False)
class UInt64MultiArray:
    """std_msgs/msg/UInt64MultiArray: ``data`` a 1-D uint64 array laid out by ``layout``."""

    layout: MultiArrayLayout = field(default_factory=MultiArrayLayout)
    data: npt.NDArray[np.uint64] = field(default_factory=_empty(np.uint64))
    __msgtype__: ClassVar[str] = "std_msgs/msg/UInt64MultiArray"
    __eq__ = array_aware_eq


@dataclass(slots=True, eq=False)
class Float32MultiArray:
    """std_msgs/msg/Float32MultiArray: ``data`` a 1-D float32 array laid out by ``layout``."""

    layout: MultiArrayLayout = field(default_factory=MultiArrayLayout)
    data: npt.NDArray[np.float32] = field(default_factory=_empty(np.float32))
    __msgtype__: ClassVar[str] = "std_msgs/msg/Float32MultiArray"
    __eq__ = array_aware_eq


@dataclass(slots=True, eq=False)
class Float64MultiArray:
    """std_msgs/msg/Float64MultiArray: ``data`` a 1-D float64 array laid out by ``layout``."""

    layout: MultiArrayLayout = field(default_factory=MultiArrayLayout)
    data: npt.NDArray[np.float64] = field(default_factory=_empty(np.float64))
    __msgtype__: ClassVar[str] = "std_msgs/msg/Float64MultiArray"
    __eq__ = array_aware_eq
