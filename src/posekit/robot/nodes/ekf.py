"""``ekf_node``: robot_localization's ekf_node in the course's configuration (2D, 20 Hz).

Subscribes ``odom0`` (``odometry/wheels``: fuses vx, vy, vyaw) and ``imu0`` (``imu/data``:
fuses yaw, relative to the first reading, and vyaw); measurements are queued in the
:class:`~posekit.robot.ekf.Ekf2D` model and fused in stamp order at each ``frequency`` tick,
which then predicts to the tick time and publishes ``odometry/filtered`` (nav_msgs/Odometry,
pose in ``world_frame``, twist in ``base_link_frame``) and, with ``publish_tf``, the TF
``odom -> base_link``. Nothing is published before the first measurement arrives (as
robot_localization waits for its first measurement).

``set_pose`` (geometry_msgs/PoseWithCovarianceStamped, robot_localization's topic) resets the
filter to the message's pose and covariance (:meth:`~posekit.robot.ekf.Ekf2D.set_pose`); the
scenarios remap it to ``/initialpose``, where RViz2's (and the viewer's) "2D Pose Estimate"
publishes, as robot_localization is commonly launched. The pose must be in ``world_frame``
(or have an empty frame): a pose in another frame is refused with one logged warning
(robot_localization would transform it through TF).

Parameters (robot_localization names): ``frequency`` (20.0), ``two_d_mode`` (true; only 2D
is implemented), ``world_frame`` (odom), ``odom_frame`` (odom), ``base_link_frame``
(base_link), ``publish_tf`` (true), ``odom0`` (``odometry/wheels``), ``imu0``
(``imu/data``), ``imu0_relative`` (true), ``initial_state`` (15 zeros: x, y, z, roll, pitch,
yaw, then rates; x, y, yaw are used).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from posekit.msgs.geometry_msgs import PoseWithCovarianceStamped
from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.sensor_msgs import Imu
from posekit.robot.ekf import Ekf2D
from posekit.robot.kinematics import yaw_from_quaternion_xyzw
from posekit.robot.nodes._util import period_ns
from posekit.robot.params import DEFAULT_EKF, EkfParams
from posekit.runtime.node import Node
from posekit.runtime.parameters import declare_value
from posekit.tf2_ros import TransformBroadcaster
from posekit.time import stamp_to_seconds

__all__ = ["EkfNode"]


class EkfNode(Node):
    """The EKF node (see the module docstring). ``filter`` is the :class:`Ekf2D` model."""

    def __init__(self, node_name: str = "ekf_node", **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)
        d = DEFAULT_EKF
        frequency = float(declare_value(self, "frequency", d.frequency_hz))
        if not bool(declare_value(self, "two_d_mode", True)):
            raise ValueError("ekf_node: only two_d_mode: true is implemented (planar ROSbot)")
        world_frame = str(declare_value(self, "world_frame", d.world_frame))
        odom_frame = str(declare_value(self, "odom_frame", d.world_frame))
        if world_frame != odom_frame:
            raise ValueError(
                f"ekf_node: world_frame '{world_frame}' must equal odom_frame '{odom_frame}' "
                "(the course fuses continuous data only; no map frame)"
            )
        params = EkfParams(
            frequency_hz=frequency,
            world_frame=world_frame,
            base_link_frame=str(declare_value(self, "base_link_frame", d.base_link_frame)),
            imu_yaw_relative=bool(declare_value(self, "imu0_relative", d.imu_yaw_relative)),
        )
        self._publish_tf = bool(declare_value(self, "publish_tf", True))
        odom_topic = str(declare_value(self, "odom0", "odometry/wheels"))
        imu_topic = str(declare_value(self, "imu0", "imu/data"))
        initial = [float(v) for v in declare_value(self, "initial_state", [0.0] * 15)]
        if len(initial) != 15 or not all(math.isfinite(v) for v in initial):
            raise ValueError(f"ekf_node: initial_state must be 15 finite numbers, got {initial}")
        #: The filter model.
        self.filter = Ekf2D(params, t0=None, initial_pose=(initial[0], initial[1], initial[5]))
        self._have_measurement = False
        self._pub = self.create_publisher(Odometry, "odometry/filtered", 10)
        self._tf = TransformBroadcaster(self) if self._publish_tf else None
        self.create_subscription(Odometry, odom_topic, self._on_odom, 10)
        self.create_subscription(Imu, imu_topic, self._on_imu, 10)
        self._world_frame = world_frame
        self.create_subscription(PoseWithCovarianceStamped, "set_pose", self._on_set_pose, 10)
        self._now_ns = self.get_clock().now_ns
        self.create_timer(period_ns(frequency, "frequency") / 1e9, self._on_tick)

    def _on_odom(self, msg: Odometry) -> None:
        self.filter.add_odometry_msg(msg)
        self._have_measurement = True

    def _on_imu(self, msg: Imu) -> None:
        self.filter.add_imu_msg(msg)
        self._have_measurement = True

    def _on_set_pose(self, msg: PoseWithCovarianceStamped) -> None:
        frame = msg.header.frame_id.lstrip("/")
        if frame and frame != self._world_frame:
            self.get_logger().warning(
                f"set_pose refused: the pose is in '{frame}', not the world frame "
                f"'{self._world_frame}'", throttle_duration_sec=5.0)
            return
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        cov6 = np.asarray(msg.pose.covariance, dtype=np.float64).reshape(6, 6)
        idx = np.array([0, 1, 5])  # x, y, rotation about Z
        try:
            self.filter.set_pose(
                stamp_to_seconds(msg.header.stamp), float(p.x), float(p.y),
                yaw_from_quaternion_xyzw(float(q.x), float(q.y), float(q.z), float(q.w)),
                cov6[np.ix_(idx, idx)])
        except ValueError as exc:
            self.get_logger().warning(f"set_pose refused: {exc}", throttle_duration_sec=5.0)
            return
        self._have_measurement = True
        self.get_logger().info(
            f"set_pose: x={float(p.x):.2f}, y={float(p.y):.2f} in {self._world_frame}")

    def _on_tick(self) -> None:
        if not self._have_measurement:
            return
        self.filter.step(self._now_ns() / 1e9)
        self._pub.publish_transfer(self.filter.to_msg())  # a fresh message: no copy
        # Building the TF is skipped while nobody listens (the bus would drop it anyway).
        if self._tf is not None and self._tf.pub_tf.get_subscription_count():
            self._tf.sendTransform(self.filter.to_transform())
