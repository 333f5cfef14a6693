"""IMU model: Gazebo-style bias and white noise, seeded, message fields."""

from __future__ import annotations

import numpy as np
import pytest

from posekit.robot.imu import ImuModel
from posekit.robot.kinematics import yaw_from_quaternion_xyzw
from posekit.robot.params import ImuParams


def test_noise_and_bias_statistics() -> None:
    imu = ImuModel(seed=5)
    samples = np.array(
        [imu.sample(0.04 * k, 0.3, 0.2, 0.0, 0.0).angular_velocity_z for k in range(20000)]
    )
    bias = imu.gyro_bias[2]
    assert abs(bias) == pytest.approx(2.0e-3)  # bias_mean with a random sign
    assert np.mean(samples) - 0.2 == pytest.approx(bias, abs=4 * 5.24e-3 / np.sqrt(20000))
    assert np.std(samples) == pytest.approx(5.24e-3, rel=0.05)


def test_bias_sign_varies_with_seed() -> None:
    signs = {np.sign(ImuModel(seed=s).gyro_bias[2]) for s in range(20)}
    assert signs == {-1.0, 1.0}


def test_seeded_and_specific_force() -> None:
    a = [ImuModel(seed=1).sample(0.0, 0.0, 0.0, 0.5, 0.1) for _ in range(1)]
    b = [ImuModel(seed=1).sample(0.0, 0.0, 0.0, 0.5, 0.1) for _ in range(1)]
    assert a == b
    acc = a[0].linear_acceleration
    assert acc[2] == pytest.approx(9.80665, abs=0.02)  # +g at rest, z up
    assert acc[0] == pytest.approx(0.5, abs=0.02)


def test_message() -> None:
    imu = ImuModel(ImuParams(orientation_noise_std=0.0), seed=2)
    msg = imu.to_msg(imu.sample(1.5, 2.0, 0.1, 0.0, 0.0))
    assert msg.header.frame_id == "imu_link"
    q = msg.orientation
    assert yaw_from_quaternion_xyzw(q.x, q.y, q.z, q.w) == pytest.approx(2.0)
    assert msg.orientation_covariance[8] == pytest.approx(1.9e-3)
    assert msg.angular_velocity_covariance[8] == pytest.approx(2.0e-3)
    assert msg.linear_acceleration_covariance[0] == pytest.approx(6.4e-2)
    assert msg.linear_acceleration_covariance[4] == pytest.approx(2.2e-2)
