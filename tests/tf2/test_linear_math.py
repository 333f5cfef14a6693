"""tf2 LinearMath kernels against scipy and closed forms (docs/specs/tf2.md section 12)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from posekit.tf2._linear_math import (
    canonical_quat,
    matrix_from_quat,
    matrix_get_rpy,
    quat_from_matrix,
    quat_from_rpy,
    quat_inverse,
    quat_mul,
    quat_rotate,
    slerp,
)

angles = st.floats(-math.pi, math.pi, allow_nan=False)
quats = st.tuples(*[st.floats(-1, 1, allow_nan=False)] * 4).filter(
    lambda q: sum(c * c for c in q) > 1e-3
)


@given(angles, angles, angles)
def test_set_rpy_matches_scipy_extrinsic_xyz(roll: float, pitch: float, yaw: float) -> None:
    expected = Rotation.from_euler("xyz", [roll, pitch, yaw]).as_quat()
    got = np.array(quat_from_rpy(roll, pitch, yaw))
    # same rotation, and setRPY's sign is the half-angle product formula's, not canonical
    assert min(np.abs(got - expected).max(), np.abs(got + expected).max()) < 1e-14


@given(quats)
def test_matrix_from_quat_normalises_like_scipy(q: tuple[float, float, float, float]) -> None:
    m = np.array(matrix_from_quat(q)).reshape(3, 3)
    np.testing.assert_allclose(m, Rotation.from_quat(q).as_matrix(), atol=1e-12)


@given(quats)
def test_canonical_quat_unit_and_sign_rule(q: tuple[float, float, float, float]) -> None:
    c = np.array(canonical_quat(q))
    n = np.array(q) / np.linalg.norm(q)
    assert abs(np.linalg.norm(c) - 1.0) < 1e-12
    assert min(np.abs(c - n).max(), np.abs(c + n).max()) < 1e-12
    m = Rotation.from_quat(q).as_matrix()
    if np.trace(m) > 1e-9:
        assert c[3] > 0
    elif np.trace(m) < -1e-9:
        i = int(np.argmax(np.diag(m)))
        assert c[i] > 0


def test_get_rotation_spec_example_sign_flip() -> None:
    # docs/specs/tf2.md 5.8: stored (0,0,-0.7071,-0.7071) comes back as (0,0,0.7071,0.7071)
    h = math.sqrt(0.5)
    assert canonical_quat((0.0, 0.0, -h, -h)) == pytest.approx((0.0, 0.0, h, h), abs=1e-15)
    # 180 deg about z: trace = -1, largest diagonal is m22 -> z positive
    assert canonical_quat((0.0, 0.0, -1.0, 0.0)) == pytest.approx((0.0, 0.0, 1.0, 0.0))


def test_zero_quaternion_becomes_nan() -> None:
    assert all(math.isnan(c) for c in canonical_quat((0.0, 0.0, 0.0, 0.0)))


def test_quat_from_matrix_tie_break_picks_index_rule() -> None:
    # diag (-1, -1, 1) with equal first two: m00 < m11 false -> compare m00 < m22 -> i = 2
    m = (-1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0)
    assert quat_from_matrix(m) == pytest.approx((0.0, 0.0, 1.0, 0.0))


@given(quats, quats)
def test_quat_mul_is_hamilton(a: tuple[float, ...], b: tuple[float, ...]) -> None:
    got = Rotation.from_quat(quat_mul(a, b))  # type: ignore[arg-type]
    exp = Rotation.from_quat(a) * Rotation.from_quat(b)
    assert got.approx_equal(exp, atol=1e-9)


@given(quats, st.tuples(*[st.floats(-10, 10)] * 3))
def test_quat_rotate_scales_by_norm_squared(q: tuple[float, ...], v: tuple[float, ...]) -> None:
    n2 = sum(c * c for c in q)
    exp = Rotation.from_quat(q).apply(v) * n2
    np.testing.assert_allclose(quat_rotate(q, v), exp, atol=1e-9)  # type: ignore[arg-type]


def test_inverse_is_conjugate_not_reciprocal() -> None:
    assert quat_inverse((1.0, 2.0, 3.0, 4.0)) == (-1.0, -2.0, -3.0, 4.0)


@pytest.mark.parametrize("t", [0.0, 0.25, 0.5, 0.75, 1.0])
def test_slerp_about_fixed_axis_interpolates_angle(t: float) -> None:
    a, b = 0.3, 1.7
    q1 = (0.0, 0.0, math.sin(a / 2), math.cos(a / 2))
    q2 = (0.0, 0.0, math.sin(b / 2), math.cos(b / 2))
    ang = a + t * (b - a)
    assert slerp(q1, q2, t) == pytest.approx((0, 0, math.sin(ang / 2), math.cos(ang / 2)))


def test_slerp_takes_shortest_path_with_negated_input() -> None:
    q1 = (0.0, 0.0, 0.0, 1.0)
    h = math.sqrt(0.5)
    q2 = (0.0, 0.0, -h, -h)  # = +90 deg about z, written with the other sign
    got = slerp(q1, q2, 0.5)
    assert got == pytest.approx((0.0, 0.0, math.sin(math.pi / 8), math.cos(math.pi / 8)))


def test_slerp_zero_angle_returns_first_unchanged() -> None:
    q = (0.0, 0.0, 0.0, 1.0)
    assert slerp(q, (0.0, 0.0, 0.0, 1.0), 0.3) is q


@given(angles, st.floats(-1.5, 1.5), angles)
def test_get_rpy_inverts_set_rpy(roll: float, pitch: float, yaw: float) -> None:
    m = matrix_from_quat(quat_from_rpy(roll, pitch, yaw))
    r, p, y = matrix_get_rpy(m)
    back = Rotation.from_euler("xyz", [r, p, y])
    assert back.approx_equal(Rotation.from_euler("xyz", [roll, pitch, yaw]), atol=1e-9)


def test_get_rpy_gimbal_lock_branch() -> None:
    m = np.array(Rotation.from_euler("xyz", [0.4, math.pi / 2, 0.0]).as_matrix())
    m[2, 0] = -1.0  # exact singular value takes the locked branch
    r, p, y = matrix_get_rpy(tuple(m.ravel()))  # type: ignore[arg-type]
    assert (p, y) == (math.pi / 2, 0.0)
    assert r == pytest.approx(math.atan2(m[2, 1], m[2, 2]))


@given(quats)
def test_core_unrolled_canonical_equals_linear_math(q: tuple[float, float, float, float]) -> None:
    from posekit.tf2.path import canonical as _canonical

    assert _canonical(q) == canonical_quat(q)  # bit-identical, every getRotation branch
