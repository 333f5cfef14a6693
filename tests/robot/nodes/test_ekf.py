"""ekf_node: waits for data, fuses odometry/wheels and imu/data at 20 Hz, publishes
odometry/filtered and the TF odom -> base_link (checked in closed form)."""

from __future__ import annotations

import math

import pytest

from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.sensor_msgs import Imu
from posekit.robot._msgutil import covariance_from_diagonal, yaw_quaternion
from posekit.robot.kinematics import yaw_from_quaternion_xyzw
from posekit.robot.nodes import EkfNode
from posekit.runtime.node import Node
from posekit.tf2_ros import Buffer, TransformListener
from posekit.time import Time, stamp_from_ns

SIM = {"use_sim_time": True}


class _Sensors(Node):
    """Ideal sensors of a robot driving a circle (v, w) from t0, IMU yaw offset by ``yaw0``."""

    def __init__(self, ctx, v: float, w: float, t0: float = 1.0, yaw0: float = 0.7) -> None:
        super().__init__("sensors", context=ctx, parameter_overrides=SIM)
        self.v, self.w, self.t0, self.yaw0 = v, w, t0, yaw0
        self.odom_pub = self.create_publisher(Odometry, "odometry/wheels", 10)
        self.imu_pub = self.create_publisher(Imu, "imu/data", 10)
        self.filtered: list[Odometry] = []
        self.create_subscription(Odometry, "odometry/filtered", self.filtered.append, 100)
        self.create_timer(0.05, self._odom)
        self.create_timer(0.04, self._imu)

    def _now(self) -> tuple[int, float]:
        ns = self.get_clock().now_ns()
        return ns, ns / 1e9

    def _odom(self) -> None:
        ns, t = self._now()
        if t < self.t0:
            return
        msg = Odometry()
        msg.header.stamp = stamp_from_ns(ns)
        msg.twist.twist.linear.x = self.v
        msg.twist.twist.angular.z = self.w
        msg.twist.covariance = covariance_from_diagonal((3.3e-5, 3.3e-5, 0, 0, 0, 2.8e-3))
        self.odom_pub.publish(msg)

    def _imu(self) -> None:
        ns, t = self._now()
        if t < self.t0:
            return
        msg = Imu()
        msg.header.stamp = stamp_from_ns(ns)
        msg.orientation = yaw_quaternion(self.yaw0 + self.w * (t - self.t0))
        msg.orientation_covariance = covariance_from_diagonal((1.9e-3,) * 3)
        msg.angular_velocity.z = self.w
        msg.angular_velocity_covariance = covariance_from_diagonal((0, 0, 2e-3))
        self.imu_pub.publish(msg)


def test_filtered_odometry_follows_the_circle_and_tf_matches(ctx, executor) -> None:
    v, w = 0.4, 0.5
    ekf = EkfNode(context=ctx, parameter_overrides=SIM)
    sensors = _Sensors(ctx, v, w)
    buffer = Buffer()
    TransformListener(buffer, sensors)
    executor.add_node(ekf)
    executor.add_node(sensors)
    executor.run_until(0.9)
    assert sensors.filtered == []  # nothing before the first measurement
    executor.run_until(7.0)
    stamps = [m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec for m in sensors.filtered]
    assert stamps == pytest.approx([1.05 + 0.05 * k for k in range(len(stamps))], abs=1e-9)
    last = sensors.filtered[-1]
    tau = 7.0 - 1.0
    # The IMU yaw is relative (its first reading is the filter's zero), so the filter sees the
    # circle x = v/w sin(w t), y = v/w (1 - cos(w t)) starting at the first measurement.
    # The first wheel twist arrives with the zero velocity state, so the filter lags by about
    # one 50 ms sample: tolerance a few centimetres.
    p = last.pose.pose
    assert p.position.x == pytest.approx(v / w * math.sin(w * tau), abs=0.03)
    assert p.position.y == pytest.approx(v / w * (1 - math.cos(w * tau)), abs=0.03)
    q = p.orientation
    yaw = yaw_from_quaternion_xyzw(q.x, q.y, q.z, q.w)
    assert math.remainder(yaw - w * tau, 2 * math.pi) == pytest.approx(0.0, abs=1e-3)
    assert last.twist.twist.linear.x == pytest.approx(v, abs=1e-3)
    assert last.header.frame_id == "odom"
    assert last.child_frame_id == "base_link"
    # TF odom -> base_link carries exactly the published pose.
    t = buffer.lookup_transform("odom", "base_link", Time())
    assert (t.transform.translation.x, t.transform.translation.y) == (p.position.x, p.position.y)
    assert t.header.stamp == last.header.stamp


def test_parameters_and_refusals(ctx) -> None:
    node = EkfNode(context=ctx, parameter_overrides=SIM)
    assert node.get_parameter("frequency").value == 20.0
    assert node.get_parameter("odom0").value == "odometry/wheels"
    assert node.get_parameter("imu0").value == "imu/data"
    assert node.get_parameter("publish_tf").value is True
    with pytest.raises(ValueError, match="two_d_mode"):
        EkfNode("e2", context=ctx, parameter_overrides={**SIM, "two_d_mode": False})
    with pytest.raises(ValueError, match="initial_state"):
        EkfNode("e3", context=ctx, parameter_overrides={**SIM, "initial_state": [0.0] * 3})


def test_set_pose_resets_the_filter_as_robot_localization_does(ctx, executor) -> None:
    """A PoseWithCovarianceStamped on set_pose (what the scenarios remap to /initialpose):
    the filter continues from that pose (the circle's closed form from the new pose and
    heading), with the message's pose covariance; a pose in another frame is refused."""
    from posekit.msgs.geometry_msgs import PoseWithCovarianceStamped

    v, w = 0.4, 0.5
    ekf = EkfNode(context=ctx, parameter_overrides=SIM)
    sensors = _Sensors(ctx, v, w)
    pub = sensors.create_publisher(PoseWithCovarianceStamped, "set_pose", 10)
    executor.add_node(ekf)
    executor.add_node(sensors)
    executor.run_until(3.0)
    x0, y0, yaw0, t_set = 2.0, -1.0, 1.0, 3.0

    def pose_msg(frame: str) -> PoseWithCovarianceStamped:
        msg = PoseWithCovarianceStamped()
        msg.header.frame_id = frame
        msg.header.stamp = stamp_from_ns(int(t_set * 1e9))
        msg.pose.pose.position.x, msg.pose.pose.position.y = x0, y0
        msg.pose.pose.orientation = yaw_quaternion(yaw0)
        msg.pose.covariance[0] = msg.pose.covariance[7] = 0.25
        msg.pose.covariance[35] = (math.pi / 12) ** 2
        return msg

    before = ekf.filter.pose
    pub.publish(pose_msg("map"))  # refused: not the world frame
    executor.run_until(3.04)
    assert math.dist(ekf.filter.pose[:2], (x0, y0)) > 0.5
    assert before != (x0, y0, yaw0)
    pub.publish(pose_msg("odom"))
    executor.run_until(3.06)
    cov = ekf.filter.covariance
    # The message's variances, grown by the process noise over the few ms since its stamp.
    assert cov[0, 0] == pytest.approx(0.25, abs=0.01)
    assert cov[2, 2] == pytest.approx((math.pi / 12) ** 2, abs=0.01)
    executor.run_until(6.0)
    tau = 6.0 - t_set
    p = sensors.filtered[-1].pose.pose
    # The IMU yaw restarts from yaw0 with its next reading; the first twist after the reset
    # meets zero velocities (a lag of about one 50 ms sample): a few centimetres.
    assert p.position.x == pytest.approx(x0 + v / w * (math.sin(yaw0 + w * tau)
                                                       - math.sin(yaw0)), abs=0.04)
    assert p.position.y == pytest.approx(y0 - v / w * (math.cos(yaw0 + w * tau)
                                                       - math.cos(yaw0)), abs=0.04)
    q = p.orientation
    yaw = yaw_from_quaternion_xyzw(q.x, q.y, q.z, q.w)
    # The first IMU reading after the reset (0.04-0.08 s after the stamp, the robot turning
    # at w = 0.5 rad/s) is the new zero of the relative yaw: up to 0.04 rad behind.
    assert -0.045 < math.remainder(yaw - (yaw0 + w * tau), 2 * math.pi) <= 0.0
