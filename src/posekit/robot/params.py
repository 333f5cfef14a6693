"""The course's ROSbot parameters (Husarion rosbot_ros as vendored in ENPM605 spring 2026).

Every default below is read from ``docs/specs/rosbot_and_worlds.md``
(controllers.yaml, the URDF, the IMU sensor, robot_localization's config). Units are SI:
metres, seconds, radians. Frames follow REP-103/105 (x forward, y left, z up).

The slip and noise parameters marked *posekit* are not in any course file: they describe
how posekit's simulator replaces Gazebo's contact physics (see :mod:`posekit.robot.drive`
and ``docs/robot.md``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = [
    "DEFAULT_DRIVE",
    "DEFAULT_EKF",
    "DEFAULT_ENCODERS",
    "DEFAULT_IMU",
    "DEFAULT_SLIP",
    "WHEEL_JOINT_NAMES",
    "DriveParams",
    "EkfParams",
    "EncoderParams",
    "ImuParams",
    "SlipParams",
]

#: Wheel joints in the order /joint_states reports them (front-left, front-right, rear-...).
WHEEL_JOINT_NAMES: tuple[str, str, str, str] = (
    "fl_wheel_joint",
    "fr_wheel_joint",
    "rl_wheel_joint",
    "rr_wheel_joint",
)


@dataclass(frozen=True, slots=True)
class DriveParams:
    """diff_drive_controller parameters (controllers.yaml) plus the URDF wheel geometry.

    The controller uses the *effective* values ``wheel_separation * wheel_separation_multiplier``
    and ``wheel_radius * *_wheel_radius_multiplier`` both to turn a command into wheel speeds
    and to compute odometry from wheel angles. The simulated wheels themselves have the URDF
    radius ``wheel_radius`` and sit ``track_width`` apart; the difference is what the slip
    model of :class:`SlipParams` explains.
    """

    wheel_separation: float = 0.186
    wheel_separation_multiplier: float = 1.36
    wheel_radius: float = 0.0425
    left_wheel_radius_multiplier: float = 0.95
    right_wheel_radius_multiplier: float = 0.95
    #: URDF lateral distance between left and right wheel centres (wheel_separation_y), m.
    track_width: float = 0.192
    #: URDF longitudinal distance between front and rear axles (wheel_separation_x), m.
    wheelbase: float = 0.106
    max_linear_velocity: float = 1.0
    max_linear_acceleration: float = 1.0
    max_angular_velocity: float = 3.14
    max_angular_acceleration: float = 4.0
    #: URDF joint velocity limit of each wheel, rad/s (None: no limit).
    wheel_velocity_limit: float | None = 24.0
    #: controller_manager update rate, Hz.
    control_rate_hz: float = 100.0
    #: Odometry publish rate, Hz.
    publish_rate_hz: float = 20.0
    #: A command older than this (by stamp or by arrival) stops the robot, s.
    cmd_vel_timeout: float = 0.5
    odom_frame_id: str = "odom"
    base_frame_id: str = "base_link"
    pose_covariance_diagonal: tuple[float, ...] = (0.001, 0.001, 0.001, 0.001, 0.001, 0.01)
    twist_covariance_diagonal: tuple[float, ...] = (3.3e-5, 3.3e-5, 0.0, 0.0, 0.0, 2.8e-3)

    @property
    def effective_wheel_separation(self) -> float:
        """``wheel_separation * wheel_separation_multiplier`` (0.25296 m by default)."""
        return self.wheel_separation * self.wheel_separation_multiplier

    @property
    def effective_left_wheel_radius(self) -> float:
        """``wheel_radius * left_wheel_radius_multiplier`` (0.040375 m by default)."""
        return self.wheel_radius * self.left_wheel_radius_multiplier

    @property
    def effective_right_wheel_radius(self) -> float:
        """``wheel_radius * right_wheel_radius_multiplier`` (0.040375 m by default)."""
        return self.wheel_radius * self.right_wheel_radius_multiplier

    @property
    def control_period(self) -> float:
        """Seconds between controller updates (0.01 s)."""
        return 1.0 / self.control_rate_hz


@dataclass(frozen=True, slots=True)
class SlipParams:
    """posekit's skid-steer slip model (replaces Gazebo's tyre contacts).

    A skid-steered base turns only by dragging its wheels sideways, so its yaw rate is a
    fraction ``eta`` of what the wheel speed difference would give a two-wheeled robot with
    the same track, and it moves forward a little less than the wheel surface speed (a
    longitudinal slip ``s``)::

        v_true     = (1 - s)   * (u_R + u_L) / 2
        omega_true = eta       * (u_R - u_L) / track_width

    with ``u`` the wheel surface speeds (URDF radius times wheel angular velocity).
    ``eta`` and ``s`` are drawn once per run around their nominal values (``*_run_std``,
    relative) and then wander with a first-order Gauss-Markov (Ornstein-Uhlenbeck) process
    (``*_walk_std`` stationary std, relative, ``correlation_time`` in s).

    The nominal values are chosen so that the course's calibration multipliers (1.36 and
    0.95) are exactly right *on average*: ``eta0 = r_eff * B / (r * L_eff)`` and
    ``s0 = 1 - r_eff / r`` (see :meth:`nominal_yaw_efficiency`). Wheel odometry is then
    unbiased in expectation and drifts only through the seeded variation, as in the lecture.
    """

    #: Nominal yaw efficiency; None derives it from the drive parameters (about 0.721).
    yaw_efficiency: float | None = None
    #: Nominal longitudinal slip; None derives it from the drive parameters (0.05).
    longitudinal_slip: float | None = None
    yaw_efficiency_run_std: float = 0.03
    yaw_efficiency_walk_std: float = 0.05
    longitudinal_slip_run_std: float = 0.01
    longitudinal_slip_walk_std: float = 0.01
    correlation_time: float = 2.0
    #: Set False for an ideal (no slip, calibrated) base: useful for closed-form tests.
    enabled: bool = True

    def nominal_yaw_efficiency(self, drive: DriveParams) -> float:
        """The ``eta`` that makes the controller's effective track exact on average."""
        if self.yaw_efficiency is not None:
            return self.yaw_efficiency
        r_eff = 0.5 * (drive.effective_left_wheel_radius + drive.effective_right_wheel_radius)
        return r_eff * drive.track_width / (drive.wheel_radius * drive.effective_wheel_separation)

    def nominal_longitudinal_slip(self, drive: DriveParams) -> float:
        """The ``s`` that makes the controller's effective wheel radius exact on average."""
        if self.longitudinal_slip is not None:
            return self.longitudinal_slip
        r_eff = 0.5 * (drive.effective_left_wheel_radius + drive.effective_right_wheel_radius)
        return 1.0 - r_eff / drive.wheel_radius


@dataclass(frozen=True, slots=True)
class EncoderParams:
    """Wheel encoders. Gazebo reports exact joint angles; quantisation is an optional knob.

    ``counts_per_revolution`` is the real firmware's ENCODER_CPR 48 x GEAR_RATIO 34.014.
    """

    counts_per_revolution: float = 48 * 34.014
    quantize: bool = False


@dataclass(frozen=True, slots=True)
class ImuParams:
    """Gazebo IMU on ``imu_link`` (25 Hz) and the covariances its broadcaster declares.

    Noise follows Gazebo's Gaussian model: white noise of std ``*_noise_std`` plus a constant
    bias drawn once as N(bias_mean, bias_std) with a random sign. Gazebo reports orientation
    from the simulated pose without noise; ``orientation_noise_std`` (posekit, default 0)
    can add white yaw noise.
    """

    rate_hz: float = 25.0
    frame_id: str = "imu_link"
    angular_velocity_noise_std: float = 5.24e-3
    angular_velocity_bias_mean: float = 2.0e-3
    angular_velocity_bias_std: float = 0.0
    linear_acceleration_noise_std: float = 1.86e-3
    linear_acceleration_bias_mean: float = 1.0e-3
    linear_acceleration_bias_std: float = 0.0
    orientation_noise_std: float = 0.0
    orientation_covariance_diagonal: tuple[float, float, float] = (1.9e-3, 1.9e-3, 1.9e-3)
    angular_velocity_covariance_diagonal: tuple[float, float, float] = (0.0, 0.0, 2.0e-3)
    linear_acceleration_covariance_diagonal: tuple[float, float, float] = (6.4e-2, 2.2e-2, 0.0)
    gravity: float = 9.80665


def _default_process_noise() -> tuple[float, ...]:
    # robot_localization's default process_noise_covariance, restricted to the 2D states.
    return (0.05, 0.05, 0.06, 0.025, 0.025, 0.02)


@dataclass(frozen=True, slots=True)
class EkfParams:
    """robot_localization ekf_node in the course's configuration (2D mode, 20 Hz).

    Fused: wheel odometry vx, vy, vyaw; IMU yaw (relative to the first reading) and vyaw.
    ``process_noise_diagonal`` is over (x, y, yaw, vx, vy, vyaw) per second of prediction
    (robot_localization's defaults; the course does not override them).
    """

    frequency_hz: float = 20.0
    world_frame: str = "odom"
    base_link_frame: str = "base_link"
    process_noise_diagonal: tuple[float, ...] = field(default_factory=_default_process_noise)
    initial_covariance_diagonal: tuple[float, ...] = (1e-9,) * 6
    imu_yaw_relative: bool = True
    #: Variance floor applied to measurement variances of 0 (robot_localization uses 1e-9).
    min_measurement_variance: float = 1e-9


DEFAULT_DRIVE = DriveParams()
DEFAULT_SLIP = SlipParams()
DEFAULT_ENCODERS = EncoderParams()
DEFAULT_IMU = ImuParams()
DEFAULT_EKF = EkfParams()
