"""The ROSbot's IMU (Gazebo IMU sensor through ros2_control's imu_broadcaster), 25 Hz.

Gazebo's Gaussian noise model per axis: ``reading = truth + bias + N(0, noise_std)`` where
``bias`` is drawn once per run from N(bias_mean, bias_std) and given a random sign. The
orientation is the simulated attitude relative to the spawn frame (no noise unless
``orientation_noise_std`` > 0). The accelerometer reports specific force in imu_link
(``+g`` on z at rest); the lever arm from base_link to imu_link (< 6 cm) is ignored, and
imu_link's axes are parallel to base_link's (identity rotation in the URDF).
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass

from posekit.msgs.geometry_msgs import Vector3
from posekit.msgs.sensor_msgs import Imu
from posekit.msgs.std_msgs import Header
from posekit.robot._msgutil import covariance_from_diagonal, yaw_quaternion
from posekit.robot.params import DEFAULT_IMU, ImuParams
from posekit.time import stamp_from_seconds

__all__ = ["ImuModel", "ImuReading"]


@dataclass(frozen=True, slots=True)
class ImuReading:
    """One IMU sample: ``yaw`` (rad, wrapped), ``angular_velocity_z`` (rad/s), specific
    force ``linear_acceleration`` (x, y, z) in imu_link (m/s²), at time ``t`` (s)."""

    t: float
    yaw: float
    angular_velocity_z: float
    linear_acceleration: tuple[float, float, float]


def _gz_bias(rng: random.Random, mean: float, std: float) -> float:
    bias = rng.gauss(mean, std) if std > 0.0 else mean
    return -bias if rng.random() < 0.5 else bias


class ImuModel:
    """Seeded IMU model (see module doc). ``sample`` takes the true body state."""

    def __init__(self, params: ImuParams = DEFAULT_IMU, *, seed: int | None = 0) -> None:
        self.params = params
        self._rng = random.Random(seed)
        p = params
        self.gyro_bias = (
            _gz_bias(self._rng, p.angular_velocity_bias_mean, p.angular_velocity_bias_std),
            _gz_bias(self._rng, p.angular_velocity_bias_mean, p.angular_velocity_bias_std),
            _gz_bias(self._rng, p.angular_velocity_bias_mean, p.angular_velocity_bias_std),
        )
        self.accel_bias = (
            _gz_bias(self._rng, p.linear_acceleration_bias_mean, p.linear_acceleration_bias_std),
            _gz_bias(self._rng, p.linear_acceleration_bias_mean, p.linear_acceleration_bias_std),
            _gz_bias(self._rng, p.linear_acceleration_bias_mean, p.linear_acceleration_bias_std),
        )
        self._orientation_cov = covariance_from_diagonal(p.orientation_covariance_diagonal)
        self._gyro_cov = covariance_from_diagonal(p.angular_velocity_covariance_diagonal)
        self._accel_cov = covariance_from_diagonal(p.linear_acceleration_covariance_diagonal)

    @property
    def period(self) -> float:
        """Seconds between samples (0.04 s)."""
        return 1.0 / self.params.rate_hz

    def sample(self, t: float, yaw: float, omega: float, ax: float, ay: float) -> ImuReading:
        """A reading at ``t`` (s) for true yaw (rad), yaw rate (rad/s) and body accelerations
        ``ax`` (dv/dt) and ``ay`` (centripetal), m/s²."""
        p = self.params
        g = self._rng.gauss
        yaw_meas = yaw + (g(0.0, p.orientation_noise_std) if p.orientation_noise_std > 0 else 0.0)
        wz = omega + self.gyro_bias[2] + g(0.0, p.angular_velocity_noise_std)
        sa = p.linear_acceleration_noise_std
        acc = (
            ax + self.accel_bias[0] + g(0.0, sa),
            ay + self.accel_bias[1] + g(0.0, sa),
            p.gravity + self.accel_bias[2] + g(0.0, sa),
        )
        wrapped = (yaw_meas + math.pi) % (2.0 * math.pi) - math.pi
        return ImuReading(t=t, yaw=wrapped, angular_velocity_z=wz, linear_acceleration=acc)

    def to_msg(self, reading: ImuReading) -> Imu:
        """sensor_msgs/Imu for ``/imu/data`` (frame ``imu_link``, course covariances).

        Angular velocity x and y are reported as 0 (planar motion: their truth is 0 and only
        z is used downstream)."""
        ax, ay, az = reading.linear_acceleration
        # Every field given (no default sub-message or covariance built and replaced), and
        # positionally in the message's ROS field order: header, orientation (+ covariance),
        # angular_velocity (+ covariance), linear_acceleration (+ covariance).
        return Imu(
            Header(stamp_from_seconds(reading.t), self.params.frame_id),
            yaw_quaternion(reading.yaw),
            self._orientation_cov.copy(),
            Vector3(0.0, 0.0, reading.angular_velocity_z),
            self._gyro_cov.copy(),
            Vector3(ax, ay, az),
            self._accel_cov.copy(),
        )
