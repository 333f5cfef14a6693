"""Wheel odometry: exact-arc integration of encoder increments, message conventions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from posekit.robot.odometry import WheelOdometry
from posekit.robot.params import DriveParams


@pytest.mark.parametrize(("v", "w"), [(0.3, 0.6), (-0.2, 1.5), (0.5, -0.25), (0.4, 0.0)])
def test_circle_from_encoder_increments(v: float, w: float) -> None:
    """Wheel angles of a constant (v, omega) give the circle of radius v/omega exactly."""
    p = DriveParams()
    r, L = p.wheel_radius * 0.95, 0.186 * 1.36  # the course's effective values
    odom = WheelOdometry(p)
    for k in range(201):  # 10 s at 20 Hz
        t = k * 0.05
        left = (v - w * L / 2) * t / r
        right = (v + w * L / 2) * t / r
        odom.update(left, right, t)
    T = 10.0
    if w == 0.0:
        ex, ey = v * T, 0.0
    else:
        ex, ey = v / w * math.sin(w * T), v / w * (1 - math.cos(w * T))
    assert (odom.x, odom.y) == pytest.approx((ex, ey), abs=1e-9)
    assert odom.yaw_unwrapped == pytest.approx(w * T, abs=1e-9)
    assert (odom.v, odom.omega) == pytest.approx((v, w), abs=1e-9)


def test_joint_positions_average_front_and_rear() -> None:
    odom = WheelOdometry()
    odom.update_from_joint_positions((0.0, 0.0, 0.0, 0.0), 0.0)
    odom.update_from_joint_positions((1.0, 1.0, 3.0, 3.0), 1.0)
    assert odom.x == pytest.approx(2.0 * 0.0425 * 0.95)
    assert odom.yaw == 0.0


def test_message_fields() -> None:
    odom = WheelOdometry()
    odom.update(0.0, 0.0, 0.0)
    odom.update(1.0, 2.0, 0.05)
    msg = odom.to_msg()
    assert msg.header.frame_id == "odom"
    assert msg.child_frame_id == "base_link"
    assert (msg.header.stamp.sec, msg.header.stamp.nanosec) == (0, 50_000_000)
    assert np.allclose(np.diag(msg.pose.covariance.reshape(6, 6)), [1e-3] * 5 + [1e-2])
    assert np.allclose(
        np.diag(msg.twist.covariance.reshape(6, 6)), [3.3e-5, 3.3e-5, 0, 0, 0, 2.8e-3]
    )
    # Twist in base_link: forward speed and yaw rate, no lateral component.
    assert msg.twist.twist.linear.y == 0.0
    assert msg.twist.twist.linear.x == pytest.approx(1.5 * 0.040375 / 0.05)
    assert msg.twist.twist.angular.z == pytest.approx(0.040375 / 0.25296 / 0.05)
