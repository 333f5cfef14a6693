"""posekit.geometry.scalar (tuple function API) against scipy, transforms3d and closed forms."""

import math

import numpy as np
import pytest
import transforms3d.euler as t3e
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation as SciRot

from posekit.geometry import EULER_SEQUENCES, GimbalLockWarning, InvalidQuaternionError, ShapeError
from posekit.geometry import scalar as ps

angle = st.floats(-math.pi, math.pi, allow_nan=False)


@st.composite
def quats(draw):
    q = np.array([draw(st.floats(-1, 1, allow_nan=False)) for _ in range(4)])
    if np.linalg.norm(q) < 0.1:
        q = np.array([0.3, 0.1, -0.2, 0.9])
    return tuple((q / np.linalg.norm(q)).tolist())


@given(st.sampled_from(EULER_SEQUENCES), angle, st.floats(-1.5, 1.5), angle)
def test_quat_from_euler_matches_scipy_and_round_trips(seq, a, b, c):
    q = ps.quat_from_euler(seq, a, b, c)
    ref = SciRot.from_euler(seq, [a, b, c]).as_quat(canonical=True)
    np.testing.assert_allclose(q, ref, atol=1e-12)
    back = ps.euler_from_quat(seq, q, warn=False)
    # inside the 1e-7 rad lock band the third angle is dropped: error bounded by the band
    proper = seq[0].lower() == seq[2].lower()
    dist = min(abs(back[1]), abs(math.pi - back[1])) if proper else math.pi / 2 - abs(back[1])
    tol = 1e-12 if dist > 1e-6 else 3e-7
    assert SciRot.from_euler(seq, back).approx_equal(SciRot.from_quat(ref), atol=tol)
    wxyz = ps.quat_from_euler(seq, math.degrees(a), math.degrees(b), math.degrees(c),
                              degrees=True, scalar_first=True)
    np.testing.assert_allclose(wxyz, (q[3], q[0], q[1], q[2]), atol=1e-12)


@given(angle, st.floats(-1.5, 1.5), angle)
def test_rpy_matches_transforms3d_sxyz(r, p, y):
    q = ps.quat_from_rpy(r, p, y)
    w, x, yy, z = t3e.euler2quat(r, p, y, "sxyz")
    sign = 1.0 if w * q[3] >= 0 else -1.0
    np.testing.assert_allclose(q, np.array((x, yy, z, w)) * sign, atol=1e-14)
    np.testing.assert_allclose(ps.rpy_from_quat(q), (r, p, y), atol=1e-12)


@given(quats(), quats(), st.tuples(angle, angle, angle))
def test_multiply_rotate_matrix_match_scipy(q1, q2, v):
    r1, r2 = SciRot.from_quat(q1), SciRot.from_quat(q2)
    prod = ps.quat_multiply(q1, q2)
    assert SciRot.from_quat(prod).approx_equal(r1 * r2, atol=1e-13)
    np.testing.assert_allclose(ps.rotate_vector(q1, v), r1.apply(v), atol=1e-13)
    np.testing.assert_allclose(ps.quat_to_matrix(q1), r1.as_matrix(), atol=1e-14)
    wxyz = (q1[3], q1[0], q1[1], q1[2])
    np.testing.assert_allclose(ps.quat_to_matrix(wxyz, scalar_first=True), r1.as_matrix(),
                               atol=1e-14)


def test_policy_and_errors():
    assert ps.quat_multiply((0, 0, 0, 2.0), (0, 0, 0, 1)) == (0, 0, 0, 1)
    with pytest.raises(InvalidQuaternionError):
        ps.rpy_from_quat((0, 0, 0, 0))
    with pytest.raises(ShapeError):
        ps.rotate_vector((0, 0, 0, 1), (1, 2))
    with pytest.raises(ShapeError):
        ps.quat_to_matrix((0, 0, 1))
    with pytest.warns(GimbalLockWarning):
        ang = ps.euler_from_quat("xyz", ps.quat_from_rpy(0.2, math.pi / 2, 0.3))
    assert ang[2] == 0.0
