"""``wheel_odometry``: the odometry half of diff_drive_controller, on ``odometry/wheels``.

Subscribes ``joint_states`` (sensor_msgs/JointState). Every message's wheel angles are
integrated at once with the exact arc (:class:`~posekit.robot.odometry.WheelOdometry`: each
side is the mean of its wheels, effective radius and separation from the multipliers), as
the controller updates its odometry every control cycle; ``odometry/wheels``
(nav_msgs/Odometry, frames ``odom``/``base_link``, twist in base_link, the course's
covariances) is published when ``publish_rate`` (20 Hz) has elapsed since the last one,
stamped with the joint state's stamp. ``enable_odom_tf`` (false, as the course: the EKF owns
``odom -> base_link``) would also broadcast the TF.

Parameters (controllers.yaml names): ``wheel_separation`` (0.186), ``wheel_radius``
(0.0425), ``wheel_separation_multiplier`` (1.36), ``left_wheel_radius_multiplier`` /
``right_wheel_radius_multiplier`` (0.95), ``left_wheel_names`` (fl, rl joints),
``right_wheel_names`` (fr, rr), ``publish_rate`` (20.0), ``odom_frame_id`` (odom),
``base_frame_id`` (base_link), ``pose_covariance_diagonal``, ``twist_covariance_diagonal``,
``enable_odom_tf`` (false); *posekit*: ``initial_x``, ``initial_y``, ``initial_yaw`` (0: the
odom origin is the spawn pose, as on the robot).

A malformed joint state (missing joint names, lengths that do not match, non-finite or
backwards stamps) is skipped with a logged reason.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.sensor_msgs import JointState
from posekit.robot._msgutil import yaw_quaternion
from posekit.robot.nodes._util import declare_wheel_geometry, period_ns
from posekit.robot.odometry import WheelOdometry
from posekit.robot.params import DEFAULT_DRIVE, WHEEL_JOINT_NAMES, DriveParams
from posekit.runtime.node import Node
from posekit.runtime.parameters import declare_value
from posekit.tf2_ros import TransformBroadcaster
from posekit.time import stamp_from_ns, stamp_to_ns

__all__ = ["WheelOdometryNode"]


class WheelOdometryNode(Node):
    """Encoder integration and ``odometry/wheels`` (see the module docstring).

    ``odometry`` is the underlying :class:`WheelOdometry` model.
    """

    def __init__(self, node_name: str = "wheel_odometry", **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)
        d = DEFAULT_DRIVE
        params = DriveParams(
            **declare_wheel_geometry(self),
            publish_rate_hz=float(declare_value(self, "publish_rate", d.publish_rate_hz)),
            odom_frame_id=str(declare_value(self, "odom_frame_id", d.odom_frame_id)),
            base_frame_id=str(declare_value(self, "base_frame_id", d.base_frame_id)),
            pose_covariance_diagonal=tuple(
                declare_value(self, "pose_covariance_diagonal", list(d.pose_covariance_diagonal))
            ),
            twist_covariance_diagonal=tuple(
                declare_value(self, "twist_covariance_diagonal", list(d.twist_covariance_diagonal))
            ),
        )
        fl, fr, rl, rr = WHEEL_JOINT_NAMES
        self._left_names = [str(n) for n in declare_value(self, "left_wheel_names", [fl, rl])]
        self._right_names = [str(n) for n in declare_value(self, "right_wheel_names", [fr, rr])]
        if not self._left_names or not self._right_names:
            raise ValueError("left_wheel_names and right_wheel_names must not be empty")
        self._publish_tf = bool(declare_value(self, "enable_odom_tf", False))
        initial = (
            float(declare_value(self, "initial_x", 0.0)),
            float(declare_value(self, "initial_y", 0.0)),
            float(declare_value(self, "initial_yaw", 0.0)),
        )
        #: The odometry model (pose in odom, unwrapped yaw).
        self.odometry = WheelOdometry(params)
        self.odometry.x, self.odometry.y, self.odometry.yaw_unwrapped = initial
        self._period_ns = period_ns(params.publish_rate_hz, "publish_rate")
        self._last_pub_ns: int | None = None
        self._last_stamp_ns: int | None = None
        self._index_cache: tuple[tuple[str, ...], list[int], list[int]] | None = None
        self._pub = self.create_publisher(Odometry, "odometry/wheels", 10)
        self._tf = TransformBroadcaster(self) if self._publish_tf else None
        self.create_subscription(JointState, "joint_states", self._on_joint_states, 10)

    def _indices(self, names: list[str]) -> tuple[list[int], list[int]] | str:
        key = tuple(names)
        cache = self._index_cache
        if cache is not None and cache[0] == key:
            return cache[1], cache[2]
        where = {n: i for i, n in enumerate(names)}
        missing = [n for n in self._left_names + self._right_names if n not in where]
        if missing:
            return f"joint_states lacks wheel joints {missing} (has {names})"
        left = [where[n] for n in self._left_names]
        right = [where[n] for n in self._right_names]
        self._index_cache = (key, left, right)
        return left, right

    def _on_joint_states(self, msg: JointState) -> None:
        found = self._indices(list(msg.name))
        if isinstance(found, str):
            self.get_logger().warning(f"Ignoring joint state: {found}", throttle_duration_sec=5.0)
            return
        left_idx, right_idx = found
        position = msg.position
        if len(position) != len(msg.name):
            self.get_logger().warning(
                f"Ignoring joint state: {len(msg.name)} names but {len(position)} positions",
                throttle_duration_sec=5.0,
            )
            return
        values = position.tolist() if isinstance(position, np.ndarray) else position
        left = sum(float(values[i]) for i in left_idx) / len(left_idx)
        right = sum(float(values[i]) for i in right_idx) / len(right_idx)
        t_ns = stamp_to_ns(msg.header.stamp)
        if not (math.isfinite(left) and math.isfinite(right)):
            self.get_logger().warning("Ignoring joint state: non-finite wheel position")
            return
        if self._last_stamp_ns is not None and t_ns <= self._last_stamp_ns:
            self.get_logger().warning(
                f"Ignoring joint state: stamp {t_ns} ns is not after the previous "
                f"{self._last_stamp_ns} ns",
                throttle_duration_sec=5.0,
            )
            return
        self._last_stamp_ns = t_ns
        self.odometry.update(left, right, t_ns / 1e9)
        if self._last_pub_ns is None:
            self._last_pub_ns = t_ns  # first reading: reference angles only
            return
        if t_ns - self._last_pub_ns >= self._period_ns:
            self._last_pub_ns = t_ns
            self._publish(t_ns)

    def _publish(self, t_ns: int) -> None:
        msg = self.odometry.to_msg()
        msg.header.stamp = stamp_from_ns(t_ns)
        self._pub.publish_transfer(msg)  # a fresh message: no copy
        if self._tf is not None:
            p = self.odometry.params
            tf = TransformStamped()
            tf.header.stamp = stamp_from_ns(t_ns)
            tf.header.frame_id = p.odom_frame_id
            tf.child_frame_id = p.base_frame_id
            tf.transform.translation.x = self.odometry.x
            tf.transform.translation.y = self.odometry.y
            tf.transform.rotation = yaw_quaternion(self.odometry.yaw)
            self._tf.sendTransform(tf)
