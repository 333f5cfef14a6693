"""The simulated base: command timeout, stale rejection, limits, slip model."""

from __future__ import annotations

import math

import numpy as np
import pytest

from posekit.msgs.geometry_msgs import TwistStamped
from posekit.robot.drive import RosbotBase
from posekit.robot.odometry import WheelOdometry
from posekit.robot.params import DriveParams, SlipParams

IDEAL = SlipParams(enabled=False)


def _run(base: RosbotBase, seconds: float, cmd: tuple[float, float] | None, t0: float = 0.0):
    n = round(seconds / 0.01)
    for k in range(n):
        t = t0 + k * 0.01
        if cmd is not None:
            assert base.submit_velocity(*cmd, stamp=t, now=t).accepted
        base.step(t)
    return t0 + n * 0.01


def test_stale_command_rejected_with_reason() -> None:
    base = RosbotBase(slip=IDEAL)
    res = base.submit_velocity(0.3, 0.0, stamp=9.4, now=10.0)
    assert not res.accepted
    assert "stale" in res.reason
    assert "0.500" in res.reason
    assert base.last_command_stamp is None
    base.step(10.0)
    assert base.state.commanded_v == 0.0  # the rejected command did not move the robot
    ok = base.submit_velocity(0.3, 0.0, stamp=9.6, now=10.0)
    assert ok.accepted
    assert ok.reason == ""


def test_zero_stamp_means_now_and_nan_is_rejected() -> None:
    base = RosbotBase(slip=IDEAL)
    msg = TwistStamped()
    msg.twist.linear.x = 0.2
    res = base.submit(msg, now=5.0)
    assert res.accepted
    assert "zero header stamp" in res.reason
    assert base.last_command_stamp == 5.0
    bad = base.submit_velocity(float("nan"), 0.0, stamp=5.0, now=5.0)
    assert not bad.accepted
    assert "non-finite" in bad.reason


def test_stopped_stream_halts_within_timeout_plus_braking() -> None:
    """The last command is stamped t_last; the target drops to 0 once it is older than the
    0.5 s timeout and the base brakes at 1 m/s², so from 0.5 m/s it is still by +1.0 s."""
    p = DriveParams()
    base = RosbotBase(p, IDEAL)
    t = _run(base, 2.0, (0.5, 0.0))
    t_last = t - 0.01
    assert base.state.commanded_v == pytest.approx(0.5)
    speeds = []
    for k in range(200):
        now = t + k * 0.01
        base.step(now)
        speeds.append((now + 0.01, base.state.commanded_v, base.body_velocity[0]))
    arr = np.array(speeds)
    # Still moving at full speed until the timeout expires...
    before = arr[arr[:, 0] <= t_last + p.cmd_vel_timeout]
    assert np.all(before[:, 1] == pytest.approx(0.5))
    # ...and completely stopped by timeout + v / a_max (+ one tick).
    stop_by = t_last + p.cmd_vel_timeout + 0.5 / p.max_linear_acceleration + 0.011
    after = arr[arr[:, 0] >= stop_by]
    assert np.all(after[:, 1] == 0.0)
    assert np.all(after[:, 2] == 0.0)
    x_stop = base.pose[0]
    _run(base, 1.0, None, t0=t + 2.0)
    assert base.pose[0] == x_stop


def test_no_command_no_motion() -> None:
    base = RosbotBase()
    _run(base, 1.0, None)
    assert base.pose == (0.0, 0.0, 0.0)


def test_velocity_and_acceleration_limits() -> None:
    p = DriveParams(wheel_velocity_limit=None)
    base = RosbotBase(p, IDEAL)
    _run(base, 0.1, (5.0, 10.0))
    # 10 steps of 0.01 s at 1 m/s² and 4 rad/s².
    assert base.state.commanded_v == pytest.approx(0.1)
    assert base.state.commanded_omega == pytest.approx(0.4)
    _run(base, 3.0, (5.0, 10.0), t0=0.1)
    assert base.state.commanded_v == pytest.approx(1.0)
    assert base.state.commanded_omega == pytest.approx(3.14)


def test_wheel_joint_limit_saturates() -> None:
    base = RosbotBase(DriveParams(), IDEAL)
    _run(base, 2.0, (1.0, 0.0))
    # 1 m/s needs 1/0.040375 = 24.77 rad/s > the URDF limit of 24 rad/s.
    assert base.state.wheel_velocities == pytest.approx((24.0,) * 4)


def test_ideal_base_matches_command_and_odometry_exactly() -> None:
    """Without slip the course's multipliers are exactly right: truth = odometry.

    Odometry is updated every control step here, so each increment has a constant twist
    (at 20 Hz the acceleration phase would bend the arcs and add ~1e-5 m)."""
    base = RosbotBase(slip=IDEAL)
    odom = WheelOdometry()
    odom.update(*base.wheel_angles, 0.0)
    for k in range(500):
        t = k * 0.01
        base.submit_velocity(0.4, 0.7, stamp=t, now=t)
        base.step(t)
        odom.update(*base.wheel_angles, (k + 1) * 0.01)
    x, y, yaw = base.pose
    assert (odom.x, odom.y, odom.yaw_unwrapped) == pytest.approx((x, y, yaw), abs=1e-9)
    assert base.state.v == pytest.approx(0.4)
    assert base.state.omega == pytest.approx(0.7)


def test_nominal_slip_is_the_course_calibration() -> None:
    p, s = DriveParams(), SlipParams()
    # eta0 = r_eff * B / (r * L_eff) = 0.95 * 0.192 / (0.186 * 1.36), s0 = 1 - 0.95.
    assert s.nominal_yaw_efficiency(p) == pytest.approx(0.95 * 0.192 / (0.186 * 1.36))
    assert s.nominal_longitudinal_slip(p) == pytest.approx(0.05)


def test_slip_is_seeded_and_makes_odometry_drift() -> None:
    def spin(seed: int) -> tuple[tuple[float, float, float], float]:
        base = RosbotBase(seed=seed)
        odom = WheelOdometry()
        odom.update(*base.wheel_angles, 0.0)
        t = _run(base, 10.0, (0.0, 1.0))
        odom.update(*base.wheel_angles, t)
        return base.pose, odom.yaw_unwrapped

    (pose_a, odom_a), (pose_b, _), (pose_c, _) = spin(3), spin(3), spin(4)
    assert pose_a == pose_b
    assert pose_a != pose_c
    # Skid steering: the true rotation differs from what the wheels imply.
    assert abs(pose_a[2] - odom_a) > 1e-3
    # ...but stays near the commanded ~10 rad (slip variation of a few percent).
    assert pose_a[2] == pytest.approx(odom_a, rel=0.25)


def test_slip_statistics_over_seeds() -> None:
    """Across seeds the yaw efficiency averages to its nominal value (calibration holds)."""
    p, s = DriveParams(), SlipParams()
    etas = []
    for seed in range(200):
        base = RosbotBase(p, s, seed=seed)
        base.step(0.0)
        etas.append(base.state.yaw_efficiency)
    eta0 = s.nominal_yaw_efficiency(p)
    spread = eta0 * math.hypot(s.yaw_efficiency_run_std, s.yaw_efficiency_walk_std)
    assert np.mean(etas) == pytest.approx(eta0, abs=4 * spread / math.sqrt(200))
    assert np.std(etas) == pytest.approx(spread, rel=0.25)


def test_future_stamp_is_rejected_so_the_timeout_still_stops_the_robot() -> None:
    """A sender on the wall clock (stamps near 1.8e9 s) against a simulation on sim time:
    diff_drive_controller only checks the age, which is negative, so the robot would drive
    on; posekit rejects the command and the base brakes as after a stopped stream."""
    p = DriveParams()
    base = RosbotBase(p, IDEAL)
    t = _run(base, 2.0, (0.5, 0.0))
    t_last = t - 0.01
    wall_stamp = 1_795_000_000.25
    for k in range(200):
        now = t + k * 0.01
        res = base.submit_velocity(0.5, 0.0, stamp=wall_stamp + k * 0.01, now=now)
        assert not res.accepted
        assert res.kind == "future"
        assert "future" in res.reason
        assert "use_sim_time" in res.reason
        base.step(now)
    assert base.last_command_stamp == pytest.approx(t_last)
    # Stopped: target zero at t_last + timeout, braking at 1 m/s² from 0.5 m/s (closed form).
    assert t + 2.0 > t_last + p.cmd_vel_timeout + 0.5 / p.max_linear_acceleration
    assert base.state.commanded_v == 0.0
    assert base.body_velocity[0] == 0.0
    # A stamp equal to now is valid (an in-process sender at the same instant).
    assert base.submit_velocity(0.1, 0.0, stamp=t + 2.0, now=t + 2.0).accepted
