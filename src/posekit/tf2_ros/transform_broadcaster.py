"""tf2_ros.transform_broadcaster: ``TransformBroadcaster``.

``TransformBroadcaster(node)`` publishes on ``/tf`` (KEEP_LAST 100, RELIABLE, VOLATILE);
``sendTransform(t | [t, ...])`` publishes one ``TFMessage``.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.tf2_msgs import TFMessage
from posekit.runtime.node import Node
from posekit.runtime.qos import QoSProfile
from posekit.tf2_ros.qos import DynamicBroadcasterQoS

__all__ = ["TransformBroadcaster"]


def as_transform_list(transform: TransformStamped | Iterable[TransformStamped]) -> list[Any]:
    """One transform or an iterable of them, as a list."""
    if isinstance(transform, list | tuple):
        return list(transform)
    if hasattr(transform, "child_frame_id"):
        return [transform]
    return list(transform)


class TransformBroadcaster:
    """Publishes dynamic transforms on /tf."""

    def __init__(
        self, node: Node, qos: QoSProfile | int | None = None, *, topic: str = "/tf"
    ) -> None:
        self.node = node
        self.pub_tf = node.create_publisher(
            TFMessage, topic, qos if qos is not None else DynamicBroadcasterQoS()
        )

    def sendTransform(self, transform: TransformStamped | Iterable[TransformStamped]) -> None:
        """Publish one TFMessage holding ``transform`` (one or a list)."""
        self.pub_tf.publish(TFMessage(transforms=as_transform_list(transform)))

    send_transform = sendTransform
