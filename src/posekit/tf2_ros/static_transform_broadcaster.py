"""tf2_ros.static_transform_broadcaster: ``StaticTransformBroadcaster``.

``StaticTransformBroadcaster(node)`` publishes on ``/tf_static`` (KEEP_LAST 1,
TRANSIENT_LOCAL: latched). It keeps ONE cumulative TFMessage and republishes everything it
was ever given on every call; a transform whose ``child_frame_id`` was already sent
**replaces** the old entry in place (as C++ tf2_ros and current Rolling do; Python Jazzy
ignores re-sends). Transforms are copied when sent, so editing the object afterwards has no
effect.
"""

from __future__ import annotations

from collections.abc import Iterable

from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.tf2_msgs import TFMessage
from posekit.runtime.bus import snapshot
from posekit.runtime.node import Node
from posekit.runtime.qos import QoSProfile
from posekit.tf2_ros.qos import StaticBroadcasterQoS
from posekit.tf2_ros.transform_broadcaster import as_transform_list

__all__ = ["StaticTransformBroadcaster"]


class StaticTransformBroadcaster:
    """Publishes a latched, cumulative TFMessage on /tf_static (replace by child_frame_id)."""

    def __init__(
        self, node: Node, qos: QoSProfile | int | None = None, *, topic: str = "/tf_static"
    ) -> None:
        self.node = node
        self.pub_tf = node.create_publisher(
            TFMessage, topic, qos if qos is not None else StaticBroadcasterQoS()
        )
        self._by_child: dict[str, TransformStamped] = {}

    def sendTransform(self, transform: TransformStamped | Iterable[TransformStamped]) -> None:
        """Add/replace ``transform`` (one or a list) and republish all static transforms."""
        for t in as_transform_list(transform):
            # Replacing keeps the entry's position (dict order), as C++ replaces in place.
            self._by_child[t.child_frame_id] = snapshot(t)
        self.pub_tf.publish(TFMessage(transforms=list(self._by_child.values())))

    send_transform = sendTransform

    @property
    def transforms(self) -> list[TransformStamped]:
        """The cumulative list currently latched."""
        return list(self._by_child.values())
