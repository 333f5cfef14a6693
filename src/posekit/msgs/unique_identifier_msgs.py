"""unique_identifier_msgs: ``UUID``, the 16-byte id of an action goal."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np
import numpy.typing as npt

from posekit.msgs._base import array_aware_eq

__all__ = ["UUID"]


def _zero_uuid() -> npt.NDArray[np.uint8]:
    return np.zeros(16, dtype=np.uint8)


@dataclass(slots=True, eq=False)
class UUID:
    """unique_identifier_msgs/msg/UUID: ``uuid`` is a uint8 array of 16 bytes (as rclpy's)."""

    uuid: npt.NDArray[np.uint8] = field(default_factory=_zero_uuid)
    __msgtype__: ClassVar[str] = "unique_identifier_msgs/msg/UUID"
    __eq__ = array_aware_eq
