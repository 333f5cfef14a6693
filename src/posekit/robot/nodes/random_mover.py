"""``random_mover``: the course's random_mover demo as a node.

Every ``1 / publish_rate`` s (2 Hz) publishes ``cmd_vel`` (geometry_msgs/TwistStamped,
stamped now) with ``linear.x ~ U(-0.5, 0.5)`` m/s and ``angular.z ~ U(-1.0, 1.0)`` rad/s
from :class:`~posekit.robot.random_mover.RandomMover`, and logs the ``odometry/filtered``
pose as ``Odom: x=.., y=.., yaw=..`` at most once per second (sim time).

Parameters: ``publish_rate`` (2.0 Hz); *posekit*: ``seed`` (0; the course's node is
unseeded, -1 draws from the OS).
"""

from __future__ import annotations

from typing import Any

from posekit.msgs.geometry_msgs import TwistStamped
from posekit.msgs.nav_msgs import Odometry
from posekit.robot.kinematics import yaw_from_quaternion_xyzw
from posekit.robot.nodes._util import period_ns
from posekit.robot.random_mover import RandomMover, RandomMoverParams
from posekit.runtime.node import Node
from posekit.runtime.parameters import declare_value
from posekit.time import stamp_from_ns

__all__ = ["RandomMoverNode"]


class RandomMoverNode(Node):
    """The random-mover node (see the module docstring). ``mover`` is the model."""

    def __init__(self, node_name: str = "random_mover", **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)
        rate = float(declare_value(self, "publish_rate", RandomMoverParams().publish_rate))
        seed = int(declare_value(self, "seed", 0))
        #: The command generator.
        self.mover = RandomMover(
            RandomMoverParams(publish_rate=rate, seed=None if seed == -1 else seed)
        )
        self._pub = self.create_publisher(TwistStamped, "cmd_vel", 10)
        self.create_subscription(Odometry, "odometry/filtered", self._on_odom, 10)
        self._now_ns = self.get_clock().now_ns
        self.create_timer(period_ns(rate, "publish_rate") / 1e9, self._on_tick)

    def _on_tick(self) -> None:
        v, w = self.mover.next_command()
        cmd = TwistStamped()
        cmd.header.stamp = stamp_from_ns(self._now_ns())
        cmd.header.frame_id = "base_link"
        cmd.twist.linear.x = v
        cmd.twist.angular.z = w
        self._pub.publish_transfer(cmd)  # built for this publish: no copy

    def _on_odom(self, msg: Odometry) -> None:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        yaw = yaw_from_quaternion_xyzw(float(q.x), float(q.y), float(q.z), float(q.w))
        line = self.mover.pose_log(self._now_ns() / 1e9, float(p.x), float(p.y), yaw)
        if line is not None:
            self.get_logger().info(line)
