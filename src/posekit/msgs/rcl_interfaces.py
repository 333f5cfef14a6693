"""rcl_interfaces: ``Log``, the message every node's logger publishes on ``/rosout``."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

from posekit.msgs.builtin_interfaces import Time

__all__ = ["Log"]


@dataclass(slots=True)
class Log:
    """rcl_interfaces/msg/Log: one log line of a node (``/rosout``).

    ``level`` is the rcutils severity (10 DEBUG, 20 INFO, 30 WARN, 40 ERROR, 50 FATAL, also
    the class constants); ``name`` the logger's name; ``file``/``function``/``line`` where
    the log call was made; ``stamp`` when.
    """

    stamp: Time = field(default_factory=Time)
    level: int = 0
    name: str = ""
    msg: str = ""
    file: str = ""
    function: str = ""
    line: int = 0
    __msgtype__: ClassVar[str] = "rcl_interfaces/msg/Log"
    DEBUG: ClassVar[int] = 10
    INFO: ClassVar[int] = 20
    WARN: ClassVar[int] = 30
    ERROR: ClassVar[int] = 40
    FATAL: ClassVar[int] = 50
