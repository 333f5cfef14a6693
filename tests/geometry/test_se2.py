"""Pose2D (SE(2)): exact exp/log against closed-form arcs, group laws, SE(3) agreement."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from posekit.geometry import (
    NonFiniteError,
    NonOrthonormalMatrixError,
    Pose2D,
    pose2d_from_transform,
    pose2d_to_transform,
)
from posekit.geometry.se2 import integrate_arc

coord = st.floats(-5, 5, allow_nan=False)
heading = st.floats(-math.pi, math.pi, allow_nan=False)
poses = st.builds(Pose2D, coord, coord, heading)


@pytest.mark.parametrize(("v", "omega", "t"), [(1.0, 0.5, 2.0), (0.3, -2.0, 1.2), (2.0, 1e-9, 3.0)])
def test_exp_follows_the_circle_of_radius_v_over_omega(v, omega, t):
    p = Pose2D.exp(v * t, 0.0, omega * t)
    if abs(omega) > 1e-6:
        R = v / omega
        expected = (R * math.sin(omega * t), R * (1 - math.cos(omega * t)))
    else:  # straight line to first order
        expected = (v * t, 0.5 * v * omega * t * t)
    assert p.x == pytest.approx(expected[0], abs=1e-12)
    assert p.y == pytest.approx(expected[1], abs=1e-12)
    assert p.theta == pytest.approx(omega * t, abs=1e-15)


def test_exp_with_lateral_velocity_and_straight_line():
    # a holonomic (mecanum) base: vy only -> straight sideways
    assert Pose2D.exp(0.0, 2.0, 0.0).approx_equal(Pose2D(0, 2, 0))
    # half circle of radius 1 turning left ends at (0, 2) facing backwards
    p = Pose2D.exp(math.pi, 0.0, math.pi)
    assert p.approx_equal(Pose2D(0.0, 2.0, math.pi), atol=1e-15)


@given(coord, coord, st.floats(-3.1, 3.1))
def test_log_inverts_exp(dx, dy, dth):
    np.testing.assert_allclose(Pose2D.exp(dx, dy, dth).log(), (dx, dy, dth), atol=1e-12)


@given(poses)
def test_exp_inverts_log(p):
    assert Pose2D.exp(*p.log()).approx_equal(p, atol=1e-12)


@given(coord, st.floats(-1, 1), st.integers(1, 50))
def test_exact_arc_steps_compose_to_one_big_step(v, omega, n):
    # the exponential of a constant twist is a one-parameter subgroup: exp(a)^n = exp(n a)
    dt = 0.1
    step = Pose2D.exp(v * dt, 0.0, omega * dt)
    pose = Pose2D()
    for _ in range(n):
        pose = pose * step
    assert pose.approx_equal(Pose2D.exp(v * dt * n, 0.0, omega * dt * n), atol=1e-10)


@given(poses, poses, poses)
def test_group_laws_and_matrices(a, b, c):
    np.testing.assert_allclose((a * b).as_matrix(), a.as_matrix() @ b.as_matrix(), atol=1e-12)
    assert ((a * b) * c).approx_equal(a * (b * c), atol=1e-11)
    assert (a * a.inv()).approx_equal(Pose2D(), atol=1e-12)
    np.testing.assert_allclose(a.inv().as_matrix(), np.linalg.inv(a.as_matrix()), atol=1e-11)
    pt = np.array([0.7, -1.3])
    np.testing.assert_allclose(a.apply(pt), (a.as_matrix() @ np.r_[pt, 1])[:2], atol=1e-12)
    np.testing.assert_allclose(a.apply(np.array([pt, pt])), [a.apply(pt)] * 2, atol=1e-15)
    assert Pose2D.from_matrix(a.as_matrix()).approx_equal(a, atol=1e-12)
    # SE(2) composition agrees with SE(3) composition of the lifted poses
    lifted = pose2d_to_transform(a) * pose2d_to_transform(b)
    assert pose2d_from_transform(lifted).approx_equal(a * b, atol=1e-12)


def test_interpolate_is_geodesic():
    a, b = Pose2D(0, 0, 0), Pose2D.exp(math.pi, 0, math.pi)
    mid = a.interpolate(b, 0.5)
    assert mid.approx_equal(Pose2D.exp(math.pi / 2, 0, math.pi / 2), atol=1e-12)
    assert a.interpolate(b, 0.0).approx_equal(a)
    assert a.interpolate(b, 1.0).approx_equal(b)


def test_value_semantics_and_errors():
    p = Pose2D(1, 2, 3 * math.pi)
    assert p.theta == pytest.approx(math.pi)
    with pytest.raises(AttributeError):
        p.x = 3.0  # type: ignore[misc]
    assert Pose2D(1, 2, 0.5) == Pose2D(1, 2, 0.5)
    assert hash(Pose2D()) == hash(Pose2D())
    assert p.as_tuple() == (p.x, p.y, p.theta)
    with pytest.raises(NonFiniteError):
        Pose2D(math.nan, 0, 0)
    with pytest.raises(NonFiniteError):
        Pose2D.exp(1.0, 0.0, math.inf)
    with pytest.raises(NonOrthonormalMatrixError):
        Pose2D.from_matrix(np.diag([2.0, 1.0, 1.0]))


@given(coord, coord, st.floats(-20, 20), coord, coord, st.floats(-3.1, 3.1))
def test_integrate_arc_is_pose_times_exp_against_matrix_exponential(x, y, th, dx, dy, dth):
    from scipy.linalg import expm

    out = integrate_arc(x, y, th, dx, dy, dth)
    assert out[2] == th + dth  # the heading is accumulated, not wrapped
    start = Pose2D(x, y, th).as_matrix()
    twist = np.array([[0.0, -dth, dx], [dth, 0.0, dy], [0.0, 0.0, 0.0]])
    end = start @ expm(twist)  # independent oracle: the matrix exponential of se(2)
    np.testing.assert_allclose(out[:2], end[:2, 2], atol=1e-9)
    assert Pose2D(*out).approx_equal(Pose2D(x, y, th) * Pose2D.exp(dx, dy, dth), atol=1e-12)


@pytest.mark.parametrize("dth", [0.0, 1e-9, -3e-7, 2e-6])
def test_integrate_arc_near_zero_turn_is_continuous(dth):
    x, y, _ = integrate_arc(0.0, 0.0, 0.0, 1.0, 0.5, dth)
    # sin(d)/d and (1 - cos d)/d by their series to 4th order (error < d^6 / 5040)
    a = 1.0 - dth**2 / 6.0 + dth**4 / 120.0
    b = dth / 2.0 - dth**3 / 24.0
    assert x == pytest.approx(a * 1.0 - b * 0.5, abs=1e-15)
    assert y == pytest.approx(b * 1.0 + a * 0.5, abs=1e-15)
