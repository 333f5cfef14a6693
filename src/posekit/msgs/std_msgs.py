"""std_msgs: Header and the scalar wrappers the system uses."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

from posekit.msgs.builtin_interfaces import Time

__all__ = ["Bool", "Float64", "Header", "String"]


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
