"""Scalar kernels (posekit.geometry._quat) against closed forms and independent algebra."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from posekit.geometry import _quat as sk
from posekit.geometry import wrap_angle
from posekit.geometry.errors import InvalidQuaternionError, UnknownSequenceError

finite = st.floats(-1.0, 1.0, allow_nan=False)
angles = st.floats(-math.pi, math.pi, allow_nan=False)


@st.composite
def unit_quats(draw):
    q = np.array([draw(finite) for _ in range(4)])
    n = np.linalg.norm(q)
    if n < 0.1:
        q = np.array([0.0, 0.0, 0.0, 1.0])
        n = 1.0
    return tuple((q / n).tolist())


def hamilton_matrix(q):
    """Left-multiplication matrix of q (x, y, z, w), built from i^2 = j^2 = k^2 = ijk = -1."""
    x, y, z, w = q
    # acting on (x, y, z, w) column vectors
    return np.array(
        [
            [w, -z, y, x],
            [z, w, -x, y],
            [-y, x, w, z],
            [-x, -y, -z, w],
        ]
    )


@given(unit_quats(), unit_quats())
def test_multiply_matches_left_multiplication_matrix(a, b):
    np.testing.assert_allclose(sk.quat_multiply_xyzw(a, b), hamilton_matrix(a) @ b, atol=1e-15)


def test_basis_units_follow_hamilton_rules():
    i, j, k, one = (1.0, 0, 0, 0), (0, 1.0, 0, 0), (0, 0, 1.0, 0), (0, 0, 0, 1.0)
    assert sk.quat_multiply_xyzw(i, j) == k
    assert sk.quat_multiply_xyzw(j, k) == i
    assert sk.quat_multiply_xyzw(k, i) == j
    minus_one = (0.0, 0.0, 0.0, -1.0)
    for u in (i, j, k):
        assert sk.quat_multiply_xyzw(u, u) == pytest.approx(minus_one)
    assert sk.quat_multiply_xyzw(sk.quat_multiply_xyzw(i, j), k) == pytest.approx(minus_one)
    assert sk.quat_multiply_xyzw(one, i) == i


@given(unit_quats(), st.tuples(finite, finite, finite))
def test_rotate_vector_is_q_p_qconj(q, v):
    # the lecture's p' = q p q^-1 with p a pure quaternion
    p = (v[0], v[1], v[2], 0.0)
    full = sk.quat_multiply_xyzw(sk.quat_multiply_xyzw(q, p), sk.quat_conjugate_xyzw(q))
    np.testing.assert_allclose(sk.quat_rotate_vector_xyzw(q, v), full[:3], atol=1e-14)
    np.testing.assert_allclose(np.array(sk.quat_to_matrix_xyzw(q)) @ v, full[:3], atol=1e-14)


@given(unit_quats())
def test_matrix_round_trip_and_orthonormal(q):
    m = np.array(sk.quat_to_matrix_xyzw(q))
    np.testing.assert_allclose(m @ m.T, np.eye(3), atol=1e-14)
    assert np.linalg.det(m) == pytest.approx(1.0, abs=1e-14)
    back = sk.matrix_to_quat_xyzw(tuple(map(tuple, m)))
    assert min(np.abs(np.subtract(back, q)).max(), np.abs(np.add(back, q)).max()) < 1e-14


def test_matrix_to_quat_sign_rule_of_tf2():
    # trace > 0 -> w > 0; 180 deg about y (trace -1, largest diagonal m11) -> y > 0
    q = sk.matrix_to_quat_xyzw(((-1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, -1.0)))
    assert q == pytest.approx((0.0, 1.0, 0.0, 0.0))


@given(angles, angles, angles)
def test_rpy_matches_tf2_half_angle_formula(r, p, y):
    # tf2 Quaternion::setRPY written out (docs/specs/tf2.md 12.2)
    cr, sr = math.cos(r / 2), math.sin(r / 2)
    cp, sp = math.cos(p / 2), math.sin(p / 2)
    cy, sy = math.cos(y / 2), math.sin(y / 2)
    expected = (
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    )
    np.testing.assert_allclose(sk.quat_from_rpy_xyzw(r, p, y), expected, atol=1e-15)
    # and equals the matrix product Rz(yaw) Ry(pitch) Rx(roll)
    def rx(a):
        return np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])

    def ry(a):
        return np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])

    def rz(a):
        return np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])

    np.testing.assert_allclose(
        sk.quat_to_matrix_xyzw(expected), rz(y) @ ry(p) @ rx(r), atol=1e-14
    )


def test_slerp_reference_numbers_from_tf2_spec():
    # docs/specs/tf2.md section 10: half way between identity and yaw 90 deg
    q90 = sk.quat_from_rpy_xyzw(0.0, 0.0, math.pi / 2)
    q = sk.quat_slerp_xyzw((0.0, 0.0, 0.0, 1.0), q90, 0.5)
    np.testing.assert_allclose(q, (0, 0, 0.38268343236508984, 0.9238795325112867), atol=1e-15)
    # identical inputs are returned unchanged (theta == 0 branch)
    assert sk.quat_slerp_xyzw(q90, q90, 0.3) == q90


@given(unit_quats(), unit_quats())
def test_slerp_endpoints_and_shortest_path(a, b):
    q0 = sk.quat_slerp_xyzw(a, b, 0.0)
    np.testing.assert_allclose(q0, a, atol=1e-12)
    q1 = sk.quat_slerp_xyzw(a, b, 1.0)
    # end point is b or -b: same rotation, reached along the shorter arc
    assert min(np.abs(np.subtract(q1, b)).max(), np.abs(np.add(q1, b)).max()) < 1e-9
    half = sk.quat_slerp_xyzw(a, b, 0.5)
    # the midpoint of the shortest arc is never farther from a than the end point
    assert abs(np.dot(half, a)) >= abs(np.dot(b, a)) - 1e-12


@pytest.mark.parametrize("q", [(0, 0, 0, 0), (math.nan, 0, 0, 1), (0, math.inf, 0, 1)])
def test_normalize_rejects_non_rotations(q):
    with pytest.raises(InvalidQuaternionError):
        sk.quat_normalize_xyzw(*q)


def test_normalize_scales_finite_quaternions():
    assert sk.quat_normalize_xyzw(0.0, 0.0, 0.0, 2.0) == (0.0, 0.0, 0.0, 1.0)
    h = 0.5**0.5
    np.testing.assert_allclose(sk.quat_normalize_xyzw(1e-200, 0, 0, 1e-200), (h, 0, 0, h))


def test_sequences_table():
    assert len(sk.EULER_SEQUENCES) == 24
    with pytest.raises(UnknownSequenceError):
        sk.euler_params("xxy")
    with pytest.raises(UnknownSequenceError):
        sk.euler_params("xYz")


@pytest.mark.parametrize("a", [0.0, 1.0, -1.0, math.pi, -math.pi, 3 * math.pi, -7.5])
def test_wrap_angle(a):
    w = sk.wrap_angle(a)
    assert -math.pi <= w <= math.pi
    assert math.cos(w) == pytest.approx(math.cos(a), abs=1e-12)
    assert math.sin(w) == pytest.approx(math.sin(a), abs=1e-12)


@given(st.floats(-100.0, 100.0))
def test_wrap_angle_convention(a: float) -> None:
    """Oracle: cos/sin of the input; in-range angles come back bit-identical."""
    w = wrap_angle(a)
    assert -math.pi <= w <= math.pi
    if -math.pi <= a <= math.pi:
        assert w == a
    else:
        assert w != -math.pi  # outside the range lands in (-pi, pi]
    assert math.cos(w) == pytest.approx(math.cos(a), abs=1e-9)
    assert math.sin(w) == pytest.approx(math.sin(a), abs=1e-9)
