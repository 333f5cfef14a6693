"""Diff-drive kinematics, the lecture's command table, exact arc vs the closed-form circle."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from posekit.robot.drive import RosbotBase
from posekit.robot.kinematics import (
    body_to_wheel_speeds,
    integrate_exact_arc,
    quaternion_xyzw_from_yaw,
    wheel_to_body_speeds,
    yaw_from_quaternion_xyzw,
)
from posekit.robot.params import SlipParams

finite = st.floats(-5.0, 5.0, allow_nan=False)


def test_lecture_formulas_by_hand() -> None:
    # r = 0.05 m, L = 0.2 m, wheels at 10 and 6 rad/s: v = 0.05*16/2, omega = 0.05*4/0.2.
    v, w = wheel_to_body_speeds(6.0, 10.0, wheel_separation=0.2, wheel_radius=0.05)
    assert v == pytest.approx(0.4)
    assert w == pytest.approx(1.0)
    # Inverse: v_R = (2v + wL)/(2r) = (0.8 + 0.2)/0.1 = 10, v_L = (0.8 - 0.2)/0.1 = 6.
    wl, wr = body_to_wheel_speeds(0.4, 1.0, wheel_separation=0.2, wheel_radius=0.05)
    assert (wl, wr) == pytest.approx((6.0, 10.0))


@given(finite, finite, st.floats(0.05, 1.0), st.floats(0.01, 0.2))
def test_kinematics_round_trip(v: float, w: float, sep: float, r: float) -> None:
    wl, wr = body_to_wheel_speeds(v, w, wheel_separation=sep, wheel_radius=r)
    v2, w2 = wheel_to_body_speeds(wl, wr, wheel_separation=sep, wheel_radius=r)
    assert v2 == pytest.approx(v, abs=1e-9)
    assert w2 == pytest.approx(w, abs=1e-9)


def test_sign_conventions() -> None:
    # omega > 0 is counter-clockwise: the right wheel runs faster than the left.
    wl, wr = body_to_wheel_speeds(0.0, 1.0, wheel_separation=0.2, wheel_radius=0.05)
    assert wr > 0 > wl
    wl, wr = body_to_wheel_speeds(1.0, 0.0, wheel_separation=0.2, wheel_radius=0.05)
    assert wl == wr > 0


# (linear.x sign, angular.z sign, expected signs of (x, y, yaw change) seen from the start
# pose) for the lecture's velocity-command reference table; 0 means "stays ~0".
COMMAND_TABLE = [
    (+1, 0, (+1, 0, 0), "straight forward"),
    (-1, 0, (-1, 0, 0), "straight backward"),
    (0, +1, (0, 0, +1), "rotate left (counterclockwise)"),
    (0, -1, (0, 0, -1), "rotate right (clockwise)"),
    (+1, +1, (+1, +1, +1), "curve forward to the left"),
    (+1, -1, (+1, -1, -1), "curve forward to the right"),
    (-1, +1, (-1, -1, +1), "curve backward to the right"),
    (-1, -1, (-1, +1, -1), "curve backward to the left"),
]


@pytest.mark.parametrize(("sv", "sw", "expected", "motion"), COMMAND_TABLE)
def test_velocity_command_reference_table(
    sv: int, sw: int, expected: tuple[int, int, int], motion: str
) -> None:
    base = RosbotBase(slip=SlipParams(enabled=False), seed=1)
    for k in range(100):  # 1 s at 100 Hz
        t = k * 0.01
        base.submit_velocity(0.3 * sv, 0.8 * sw, stamp=t, now=t)
        base.step(t)
    x, y, yaw = base.pose
    for value, sign, label in zip((x, y, yaw), expected, ("x", "y", "yaw"), strict=True):
        if sign == 0:
            assert abs(value) < 1e-9, (motion, label, value)
        else:
            assert value * sign > 1e-3, (motion, label, value)


@given(st.floats(-1.0, 1.0), st.floats(0.05, 3.0), st.integers(1, 200), st.floats(-3.0, 3.0))
def test_exact_arc_matches_closed_form_circle(v: float, w: float, n: int, yaw0: float) -> None:
    """Constant (v, omega) for T: the robot is on a circle of radius v/omega (any step)."""
    total = 4.0
    dt = total / n
    x, y, yaw = 1.0, -2.0, yaw0
    for _ in range(n):
        x, y, yaw = integrate_exact_arc(x, y, yaw, v * dt, w * dt)
    R = v / w
    # Closed form in the start frame, then rotated by yaw0.
    bx, by = R * math.sin(w * total), R * (1.0 - math.cos(w * total))
    ex = 1.0 + math.cos(yaw0) * bx - math.sin(yaw0) * by
    ey = -2.0 + math.sin(yaw0) * bx + math.cos(yaw0) * by
    assert x == pytest.approx(ex, abs=1e-9)
    assert y == pytest.approx(ey, abs=1e-9)
    assert yaw == pytest.approx(yaw0 + w * total, abs=1e-9)


def test_lecture_euler_formula_is_first_order_exact_arc_is_exact() -> None:
    v, w, total = 0.5, 1.0, 3.0
    R = v / w
    exact = (R * math.sin(w * total), R * (1 - math.cos(w * total)))

    def euler(n: int) -> float:
        dt = total / n
        x = y = psi = 0.0
        for _ in range(n):
            ds, dpsi = v * dt, w * dt
            x, y, psi = x + ds * math.cos(psi), y + ds * math.sin(psi), psi + dpsi
        return math.hypot(x - exact[0], y - exact[1])

    e1, e2 = euler(60), euler(120)
    assert 1.8 < e1 / e2 < 2.2  # error halves with the step: first order
    x, y, _ = integrate_exact_arc(0.0, 0.0, 0.0, v * total, w * total)  # one big step
    assert math.hypot(x - exact[0], y - exact[1]) < 1e-12


def test_exact_arc_small_angle_branch_is_continuous() -> None:
    for d in (1e-7, -3e-7, 9.9e-7):
        a = integrate_exact_arc(0.0, 0.0, 0.3, 1.0, d)
        # Reference from the closed form with extended precision via math.fsum style terms.
        bx, by = math.sin(d) / d, (1 - math.cos(d)) / d
        ref = (math.cos(0.3) * bx - math.sin(0.3) * by, math.sin(0.3) * bx + math.cos(0.3) * by)
        assert a[0] == pytest.approx(ref[0], abs=1e-9)
        assert a[1] == pytest.approx(ref[1], abs=1e-9)


def test_lateral_component() -> None:
    # Pure sideways motion without rotation moves along the body y axis.
    x, y, yaw = integrate_exact_arc(0.0, 0.0, math.pi / 2, 0.0, 0.0, lateral=1.0)
    assert (x, y, yaw) == pytest.approx((-1.0, 0.0, math.pi / 2))


def test_yaw_quaternion_against_scipy() -> None:
    yaws = np.linspace(-3.1, 3.1, 25)
    for yaw in yaws:
        q = quaternion_xyzw_from_yaw(float(yaw))
        ref = Rotation.from_euler("z", yaw).as_quat()  # scipy: x, y, z, w
        assert np.allclose(q, ref) or np.allclose(q, -ref)
        assert yaw_from_quaternion_xyzw(*q) == pytest.approx(yaw)
