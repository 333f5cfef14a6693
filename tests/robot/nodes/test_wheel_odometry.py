"""wheel_odometry node: closed-form arcs from hand-made joint states, rate, frames, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.sensor_msgs import JointState
from posekit.robot.kinematics import yaw_from_quaternion_xyzw
from posekit.robot.nodes import WheelOdometryNode
from posekit.robot.params import WHEEL_JOINT_NAMES
from posekit.runtime.node import Node
from posekit.time import stamp_from_ns

SIM = {"use_sim_time": True}
R_EFF = 0.0425 * 0.95
L_EFF = 0.186 * 1.36


class _Feeder(Node):
    """Publishes joint states at 100 Hz with wheel angles ``angles(t) -> (left, right)``."""

    def __init__(self, ctx, angles, names=WHEEL_JOINT_NAMES) -> None:
        super().__init__("feeder", context=ctx, parameter_overrides=SIM)
        self.pub = self.create_publisher(JointState, "joint_states", 10)
        self.angles, self.names = angles, list(names)
        self.out: list[Odometry] = []
        self.create_subscription(Odometry, "odometry/wheels", self.out.append, 100)
        self.create_timer(0.01, self._tick)

    def _tick(self) -> None:
        t_ns = self.get_clock().now_ns()
        left, right = self.angles(t_ns / 1e9)
        msg = JointState()
        msg.header.stamp = stamp_from_ns(t_ns)
        msg.name = self.names
        # Front and rear of a side differ by a constant; odometry uses their mean.
        msg.position = np.array([left + 0.1, right - 0.2, left - 0.1, right + 0.2])
        msg.velocity = np.zeros(4)
        self.pub.publish(msg)


def test_constant_wheel_speeds_give_the_closed_form_circle(ctx, executor) -> None:
    wl, wr = 8.0, 12.0  # rad/s
    node = WheelOdometryNode(context=ctx, parameter_overrides=SIM)
    feeder = _Feeder(ctx, lambda t: (wl * t, wr * t))
    executor.add_node(node)
    executor.add_node(feeder)
    executor.run_until(3.0)
    v = R_EFF * (wl + wr) / 2
    w = R_EFF * (wr - wl) / L_EFF
    stamps = [m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec for m in feeder.out]
    # First joint state (t = 0.01 s) is the reference; then one message per 50 ms.
    assert stamps == pytest.approx([0.01 + 0.05 * k for k in range(1, 60)], abs=1e-9)
    for m, t in zip(feeder.out, stamps, strict=True):
        tau = t - 0.01
        x_ref = v / w * math.sin(w * tau)
        y_ref = v / w * (1 - math.cos(w * tau))
        p = m.pose.pose
        assert (p.position.x, p.position.y) == pytest.approx((x_ref, y_ref), abs=1e-9)
        q = p.orientation
        yaw = yaw_from_quaternion_xyzw(q.x, q.y, q.z, q.w)
        assert math.remainder(yaw - w * tau, 2 * math.pi) == pytest.approx(0.0, abs=1e-9)
        assert m.twist.twist.linear.x == pytest.approx(v)
        assert m.twist.twist.angular.z == pytest.approx(w)
    assert m.header.frame_id == "odom"
    assert m.child_frame_id == "base_link"
    assert m.twist.covariance[35] == pytest.approx(2.8e-3)
    assert m.pose.covariance[35] == pytest.approx(0.01)


def test_malformed_joint_states_are_skipped_with_a_reason(ctx, executor, logs) -> None:
    node = WheelOdometryNode(context=ctx, parameter_overrides=SIM)
    feeder = _Feeder(ctx, lambda t: (t, t), names=["a", "b", "c", "d"])
    executor.add_node(node)
    executor.add_node(feeder)
    executor.run_until(0.5)
    assert feeder.out == []
    reasons = [r.message for r in logs if r.name == "wheel_odometry"]
    assert reasons
    assert "lacks wheel joints" in reasons[0]
    assert "fl_wheel_joint" in reasons[0]
    assert len(reasons) == 1  # throttled to one per 5 s


def test_parameters_are_the_controllers_yaml_names(ctx) -> None:
    node = WheelOdometryNode(
        context=ctx, parameter_overrides={**SIM, "wheel_separation_multiplier": 1.0}
    )
    assert node.odometry.params.effective_wheel_separation == pytest.approx(0.186)
    assert node.get_parameter("publish_rate").value == 20.0
    assert node.get_parameter("enable_odom_tf").value is False
    assert node.get_parameter("left_wheel_names").value == ["fl_wheel_joint", "rl_wheel_joint"]
