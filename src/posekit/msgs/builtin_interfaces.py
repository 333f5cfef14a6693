"""builtin_interfaces: Time and Duration (ROS 2 field layout: int32 sec, uint32 nanosec)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

__all__ = ["Duration", "Time"]


@dataclass(slots=True)
class Time:
    """builtin_interfaces/msg/Time: seconds and nanoseconds since the epoch (or sim start)."""

    sec: int = 0
    nanosec: int = 0
    __msgtype__: ClassVar[str] = "builtin_interfaces/msg/Time"


@dataclass(slots=True)
class Duration:
    """builtin_interfaces/msg/Duration: a signed span; ``nanosec`` is always in [0, 1e9)."""

    sec: int = 0
    nanosec: int = 0
    __msgtype__: ClassVar[str] = "builtin_interfaces/msg/Duration"
