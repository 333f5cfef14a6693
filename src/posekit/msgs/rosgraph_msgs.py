"""rosgraph_msgs: Clock, the payload of ``/clock`` for simulated time."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

from posekit.msgs.builtin_interfaces import Time

__all__ = ["Clock"]


@dataclass(slots=True)
class Clock:
    """rosgraph_msgs/msg/Clock."""

    clock: Time = field(default_factory=Time)
    __msgtype__: ClassVar[str] = "rosgraph_msgs/msg/Clock"
