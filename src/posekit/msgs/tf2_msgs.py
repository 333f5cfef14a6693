"""tf2_msgs: TFMessage, the payload of ``/tf`` and ``/tf_static``."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

from posekit.msgs.geometry_msgs import TransformStamped

__all__ = ["TFMessage"]


@dataclass(slots=True)
class TFMessage:
    """tf2_msgs/msg/TFMessage: a list of TransformStamped."""

    transforms: list[TransformStamped] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "tf2_msgs/msg/TFMessage"
