"""Deterministic fixed-step closed loop of the ROSbot models, without the runtime.

One tick is the drive controller period (10 ms). At tick time ``t`` the loop runs, in
this order, whatever is due:

1. IMU sample (25 Hz) of the true state -> EKF queue;
2. encoders + wheel odometry (20 Hz) -> EKF queue (its twist, with the course covariances);
3. EKF step (20 Hz): fuse the queue, predict to ``t``; the three poses are recorded here;
4. the command source (P controller at 20 Hz on the filtered pose, random mover at 2 Hz,
   or a user function), whose TwistStamped is stamped ``t`` and offered to the base;
5. the base advances from ``t`` to ``t + 10 ms``.

All randomness (slip, IMU, random mover) comes from ``seed``; the same arguments give the
same arrays bit for bit. The node layer runs the same models on sim time.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from posekit.robot.drive import CommandResult, RosbotBase
from posekit.robot.ekf import Ekf2D
from posekit.robot.encoders import WheelEncoders
from posekit.robot.imu import ImuModel
from posekit.robot.odometry import WheelOdometry
from posekit.robot.p_controller import PController, PControllerParams
from posekit.robot.params import (
    DEFAULT_DRIVE,
    DEFAULT_EKF,
    DEFAULT_ENCODERS,
    DEFAULT_IMU,
    DEFAULT_SLIP,
    DriveParams,
    EkfParams,
    EncoderParams,
    ImuParams,
    SlipParams,
)
from posekit.robot.random_mover import RandomMover, RandomMoverParams

__all__ = ["CommandSource", "SimResult", "run_headless", "sub_seeds"]

#: A user command source: ``f(t) -> (v, omega)`` or None to send nothing at that tick.
CommandSource = Callable[[float], "tuple[float, float] | None"]

_FloatArray = npt.NDArray[np.float64]


def sub_seeds(seed: int) -> tuple[int, int, int]:
    """Independent seeds for (slip, IMU, random mover) derived from one run seed."""
    a, b, c = np.random.SeedSequence(seed).generate_state(3)
    return int(a), int(b), int(c)


@dataclass
class SimResult:
    """Time series recorded at the EKF rate (20 Hz).

    ``t`` (N,) in s; ``truth``, ``wheels``, ``filtered`` (N, 3) as (x, y, yaw) in odom with
    yaw wrapped to [-pi, pi); ``commands`` (N, 2) the last command offered (v, omega).
    ``goal_reached_time`` is the sim time of the P controller's "Goal reached" (else None);
    ``rejected`` lists (time, reason) of commands the base refused; ``log`` holds the lines
    the demo nodes would log.
    """

    t: _FloatArray
    truth: _FloatArray
    wheels: _FloatArray
    filtered: _FloatArray
    commands: _FloatArray
    goal_reached_time: float | None = None
    rejected: list[tuple[float, str]] = field(default_factory=list)
    log: list[str] = field(default_factory=list)

    def final_errors(self) -> dict[str, tuple[float, float]]:
        """``{"wheels": (position_err_m, |yaw_err|_rad), "filtered": (...)}`` at the end."""
        out: dict[str, tuple[float, float]] = {}
        gt = self.truth[-1]
        for name, est in (("wheels", self.wheels[-1]), ("filtered", self.filtered[-1])):
            pos = float(math.hypot(est[0] - gt[0], est[1] - gt[1]))
            dyaw = float(abs((est[2] - gt[2] + math.pi) % (2 * math.pi) - math.pi))
            out[name] = (pos, dyaw)
        return out


def _ticks(period: float, dt: float, what: str) -> int:
    n = round(period / dt)
    if n < 1 or abs(n * dt - period) > 1e-9:
        raise ValueError(f"{what} period {period} s is not a multiple of the {dt} s control tick")
    return n


_Command = tuple[float, float]


def _commander(
    scenario: str, *, goal: tuple[float, float, float],
    controller_params: PControllerParams | None, mover_params: RandomMoverParams | None,
    command_source: CommandSource | None, mover_seed: int, dt: float, result: SimResult,
) -> tuple[int, Callable[[float, tuple[float, float, float]], _Command | None]]:
    """The scenario's command source: control ticks between commands, and
    ``command(t, ekf_pose)`` giving ``(v, omega)`` or None (nothing sent this tick).

    The P controller's "Goal reached" is recorded in ``result`` (time and log line).
    """
    if scenario == "p_controller":
        controller = PController(controller_params or PControllerParams())
        controller.set_goal(*goal)

        def p_command(t: float, pose: tuple[float, float, float]) -> _Command | None:
            fx, fy, fyaw = pose
            out = controller.compute(fx, fy, fyaw)
            if out.just_reached:
                result.goal_reached_time = t
                result.log.append(
                    f"Goal reached: x={fx:.2f}, y={fy:.2f}, yaw={fyaw:.2f} (t={t:.2f} s)"
                )
            return (out.v, out.omega) if out.publish else None

        return _ticks(controller.period, dt, "p_controller"), p_command
    if scenario == "random_mover":
        mover = RandomMover(mover_params or RandomMoverParams(seed=mover_seed))
        return _ticks(mover.period, dt, "random_mover"), lambda t, pose: mover.next_command()
    if scenario == "custom":
        if command_source is None:
            raise ValueError("scenario 'custom' needs a command_source")
        source = command_source
        return 1, lambda t, pose: source(t)
    if scenario == "idle":
        return 1, lambda t, pose: None
    raise ValueError(
        f"unknown scenario {scenario!r}; use p_controller, random_mover, idle or custom"
    )


def run_headless(
    *,
    scenario: str = "p_controller",
    duration: float = 60.0,
    seed: int = 0,
    goal: tuple[float, float, float] = (5.0, 5.0, math.pi / 2),
    stop_on_goal: bool = False,
    controller_params: PControllerParams | None = None,
    mover_params: RandomMoverParams | None = None,
    command_source: CommandSource | None = None,
    drive: DriveParams = DEFAULT_DRIVE,
    slip: SlipParams = DEFAULT_SLIP,
    imu: ImuParams = DEFAULT_IMU,
    encoders: EncoderParams = DEFAULT_ENCODERS,
    ekf: EkfParams = DEFAULT_EKF,
    start: tuple[float, float, float] = (0.0, 0.0, 0.0),
) -> SimResult:
    """Run the closed loop for ``duration`` simulated seconds.

    Args:
        scenario: ``"p_controller"`` (drive to ``goal``), ``"random_mover"``, ``"idle"``
            (no commands) or ``"custom"`` (``command_source`` at the control rate).
        duration: simulated seconds.
        seed: run seed (slip, IMU noise, random mover; see :func:`sub_seeds`).
        goal: P-controller goal ``(x, y, yaw)`` in odom (the launch default (5, 5, pi/2)).
        stop_on_goal: end the run at the P controller's "Goal reached".
        start: spawn pose ``(x, y, yaw)`` in odom; wheel odometry and the EKF are
            initialised to it (as if odom were set up with that pose), which lets tests
            start the controller from other headings.
    """
    dt = drive.control_period
    slip_seed, imu_seed, mover_seed = sub_seeds(seed)
    base = RosbotBase(drive, slip, seed=slip_seed, x=start[0], y=start[1], yaw=start[2])
    enc = WheelEncoders(encoders)
    odom = WheelOdometry(drive)
    odom.x, odom.y, odom.yaw_unwrapped = start
    imu_model = ImuModel(imu, seed=imu_seed)
    filt = Ekf2D(ekf, t0=0.0, initial_pose=start)

    n_odom = _ticks(1.0 / drive.publish_rate_hz, dt, "odometry")
    n_ekf = _ticks(1.0 / ekf.frequency_hz, dt, "EKF")
    n_imu = _ticks(1.0 / imu.rate_hz, dt, "IMU")
    twist_var = (
        drive.twist_covariance_diagonal[0],
        drive.twist_covariance_diagonal[1],
        drive.twist_covariance_diagonal[5],
    )
    imu_var = (imu.orientation_covariance_diagonal[2], imu.angular_velocity_covariance_diagonal[2])
    n_steps = round(duration / dt)
    n_rec = n_steps // n_ekf + 1
    t_rec = np.zeros(n_rec)
    truth = np.zeros((n_rec, 3))
    wheels = np.zeros((n_rec, 3))
    filtered = np.zeros((n_rec, 3))
    commands = np.zeros((n_rec, 2))
    rec = 0
    result = SimResult(t_rec, truth, wheels, filtered, commands)
    n_cmd, next_command = _commander(
        scenario, goal=goal, controller_params=controller_params, mover_params=mover_params,
        command_source=command_source, mover_seed=mover_seed, dt=dt, result=result)
    last_cmd = (0.0, 0.0)
    two_pi = 2.0 * math.pi

    for k in range(n_steps + 1):
        t = k * dt
        if k % n_imu == 0:
            v_true, w_true, ax = base.body_velocity
            yaw_true = base.pose[2]
            reading = imu_model.sample(t, yaw_true, w_true, ax, v_true * w_true)
            filt.add_imu(t, reading.yaw, reading.angular_velocity_z, imu_var)
        if k % n_odom == 0:
            left, right = base.wheel_angles
            odom.update(enc.read_angle(left), enc.read_angle(right), t)
            if k > 0:
                filt.add_wheel_twist(t, odom.v, 0.0, odom.omega, twist_var)
        if k % n_ekf == 0:
            filt.step(t)
            x, y, yaw = base.pose
            t_rec[rec] = t
            truth[rec] = (x, y, (yaw + math.pi) % two_pi - math.pi)
            wheels[rec] = (odom.x, odom.y, odom.yaw)
            filtered[rec] = filt.pose
            commands[rec] = last_cmd
            rec += 1
        if k % n_cmd == 0 and k < n_steps:
            cmd = next_command(t, filt.pose)
            if cmd is not None:
                res: CommandResult = base.submit_velocity(cmd[0], cmd[1], stamp=t, now=t)
                if res.accepted:
                    last_cmd = cmd
                else:
                    result.rejected.append((t, res.reason))
            if stop_on_goal and result.goal_reached_time is not None:
                break
        if k < n_steps:
            base.step(t, dt)

    result.t = t_rec[:rec]
    result.truth = truth[:rec]
    result.wheels = wheels[:rec]
    result.filtered = filtered[:rec]
    result.commands = commands[:rec]
    return result
