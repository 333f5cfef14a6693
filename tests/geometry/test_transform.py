"""Transform (SE(3)): matrices, the index-cancelling chain rule, inverse, tf2 interpolation,
batches, and differential checks against scipy's RigidTransform."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial.transform import RigidTransform as SciTf
from scipy.spatial.transform import Rotation as SciRot

from posekit.geometry import (
    NonFiniteError,
    NonOrthonormalMatrixError,
    Rotation,
    ShapeError,
    Transform,
)

coord = st.floats(-10, 10, allow_nan=False)


@st.composite
def transforms(draw):
    q = np.array([draw(st.floats(-1, 1)) for _ in range(4)])
    if np.linalg.norm(q) < 0.1:
        q = np.array([0.0, 0.3, 0.0, 0.9])
    t = [draw(coord) for _ in range(3)]
    return Transform(Rotation.from_quat(q), t)


def homogeneous(R, t):
    m = np.eye(4)
    m[:3, :3] = R
    m[:3, 3] = t
    return m


@given(transforms(), transforms(), transforms())
def test_chain_inverse_and_matrices(T_a_b, T_b_c, T_c_d):
    # T_a_c = T_a_b * T_b_c is the 4x4 matrix product
    np.testing.assert_allclose(
        (T_a_b * T_b_c).as_matrix(), T_a_b.as_matrix() @ T_b_c.as_matrix(), atol=1e-12
    )
    assert ((T_a_b * T_b_c) * T_c_d).approx_equal(T_a_b * (T_b_c * T_c_d), atol=1e-11)
    inv_ref = np.linalg.inv(T_a_b.as_matrix())
    np.testing.assert_allclose(T_a_b.inv().as_matrix(), inv_ref, atol=1e-11)
    assert (T_a_b * T_a_b.inv()).approx_equal(Transform.identity(), atol=1e-12)
    assert (Transform.identity() * T_a_b).approx_equal(T_a_b, atol=1e-15)
    p_c = np.array([0.5, -2.0, 3.0])
    p_a = T_a_b.apply(T_b_c.apply(p_c))
    np.testing.assert_allclose((T_a_b * T_b_c).apply(p_c), p_a, atol=1e-11)
    np.testing.assert_allclose(T_a_b.as_matrix() @ np.r_[p_c, 1.0], np.r_[T_a_b.apply(p_c), 1],
                               atol=1e-11)  # a component near 0 has no relative tolerance
    np.testing.assert_allclose(T_a_b.apply(T_a_b.apply(p_c), inverse=True), p_c, atol=1e-11)
    assert Transform.from_matrix(T_a_b.as_matrix()).approx_equal(T_a_b, atol=1e-12)


def test_lecture_chain_odom_to_marker():
    # odom -T1-> base_link -T2-> camera_optical -T3-> marker: T_odom_marker = T1 T2 T3
    T_odom_base = Transform(Rotation.from_rpy(0, 0, math.pi / 2), [1.0, 2.0, 0.0])
    T_base_cam = Transform(Rotation.from_rpy(-math.pi / 2, 0, -math.pi / 2), [0.1, 0.0, 0.3])
    T_cam_marker = Transform(Rotation.identity(), [0.0, 0.0, 2.0])  # 2 m along optical z
    T_odom_marker = T_odom_base * T_base_cam * T_cam_marker
    expected = T_odom_base.as_matrix() @ T_base_cam.as_matrix() @ T_cam_marker.as_matrix()
    np.testing.assert_allclose(T_odom_marker.as_matrix(), expected, atol=1e-15)
    # optical z = base forward x; base x = odom y after the 90 deg yaw: marker 2.1 m along +y
    np.testing.assert_allclose(T_odom_marker.translation, [1.0, 4.1, 0.3], atol=1e-15)


def test_tf2_interpolation_reference_numbers():
    # docs/specs/tf2.md section 10: map->odom @1 identity, @2 t(2,0,0) yaw 90 deg; lookup @1.5
    T1 = Transform.identity()
    T2 = Transform(Rotation.from_rpy(0, 0, math.pi / 2), [2.0, 0.0, 0.0])
    mid = T1.interpolate(T2, 0.5)
    np.testing.assert_allclose(mid.translation, [1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(
        mid.rotation.as_quat(), [0, 0, 0.38268343236508984, 0.9238795325112867], atol=1e-15
    )
    assert T1.interpolate(T2, 0.0).approx_equal(T1, atol=0)
    assert T1.interpolate(T2, 1.0).approx_equal(T2, atol=1e-15)
    many = T1.interpolate(T2, np.linspace(0, 1, 5))
    assert len(many) == 5
    np.testing.assert_allclose(many.translation[:, 0], [0, 0.5, 1, 1.5, 2], atol=1e-15)


def test_batch_equals_loop_of_singles_and_scipy():
    rng = np.random.default_rng(2)
    n = 10_000
    A = Transform.random(n, rng)
    Bt = Transform.random(n, rng)
    p = rng.normal(size=(n, 3))
    ref_a = SciTf.from_components(A.translation, SciRot.from_quat(A.rotation.as_quat()))
    ref_b = SciTf.from_components(Bt.translation, SciRot.from_quat(Bt.rotation.as_quat()))
    np.testing.assert_allclose((A * Bt).as_matrix(), (ref_a * ref_b).as_matrix(), atol=1e-12)
    np.testing.assert_allclose(A.inv().as_matrix(), ref_a.inv().as_matrix(), atol=1e-12)
    np.testing.assert_allclose(A.apply(p), ref_a.apply(p), atol=1e-12)
    np.testing.assert_allclose(A.apply(p, inverse=True), ref_a.apply(p, inverse=True), atol=1e-12)
    singles_a, singles_b = list(A[:200]), list(Bt[:200])
    loop = np.array([(a * b).as_matrix() for a, b in zip(singles_a, singles_b, strict=True)])
    np.testing.assert_allclose((A[:200] * Bt[:200]).as_matrix(), loop, atol=1e-14)
    loop = np.array([a.inv().as_matrix() for a in singles_a])
    np.testing.assert_allclose(A[:200].inv().as_matrix(), loop, atol=1e-14)
    loop = np.array(
        [a.interpolate(b, 0.3).as_matrix() for a, b in zip(singles_a, singles_b, strict=True)]
    )
    np.testing.assert_allclose(A[:200].interpolate(Bt[:200], 0.3).as_matrix(), loop, atol=1e-14)
    assert Transform.from_matrix(A.as_matrix()).approx_equal(A, atol=1e-12).all()


def test_protocol_and_constructors():
    T = Transform(Rotation.from_rpy(0.1, 0.2, 0.3), (1, 2, 3))
    assert T.single
    with pytest.raises(TypeError):
        len(T)
    assert T.translation_tuple() == (1.0, 2.0, 3.0)
    assert "Transform(translation=[1.0, 2.0, 3.0]" in repr(T)
    batch = Transform(Rotation.from_rpy(0.1, 0.2, 0.3), np.zeros((4, 3)))
    assert len(batch) == 4
    assert batch[0].single
    assert len(batch[1:]) == 3
    assert len(list(batch)) == 4
    assert Transform.from_translation([1, 0, 0]).rotation.approx_equal(Rotation.identity())
    assert len(Transform.from_rotation(Rotation.random(3, rng=0))) == 3
    assert len(Transform.identity(3)) == 3
    d, ang = T.distance(Transform.identity())
    assert d == pytest.approx(math.sqrt(14))
    assert ang == pytest.approx(T.rotation.magnitude())


def test_errors():
    with pytest.raises(ShapeError):
        Transform.from_matrix(np.eye(3))
    bad = np.eye(4)
    bad[3, 0] = 1.0
    with pytest.raises(NonOrthonormalMatrixError):
        Transform.from_matrix(bad)
    with pytest.raises(NonOrthonormalMatrixError):
        Transform.from_matrix(np.diag([2.0, 1, 1, 1]))
    with pytest.raises(NonFiniteError):
        Transform(Rotation.identity(), [0, math.nan, 0])
    with pytest.raises(ShapeError):
        Transform(Rotation.random(3, rng=0), np.zeros((4, 3)))
    with pytest.raises(ShapeError):
        Transform(None, [1, 2])
    with pytest.raises(TypeError):
        Transform("not a rotation")  # type: ignore[arg-type]


def test_from_xyz_rpy_is_urdf_origin() -> None:
    """Oracle: scipy's extrinsic 'xyz' Euler angles (URDF/SDF fixed-axis rpy)."""
    rng = np.random.default_rng(7)
    for _ in range(20):
        xyz, rpy = rng.uniform(-3, 3, 3), rng.uniform(-3, 3, 3)
        m = Transform.from_xyz_rpy(xyz, rpy).as_matrix()
        np.testing.assert_allclose(m[:3, :3], SciRot.from_euler("xyz", rpy).as_matrix(),
                                   atol=1e-12)
        np.testing.assert_array_equal(m[:3, 3], xyz)
        np.testing.assert_array_equal(m[3], (0.0, 0.0, 0.0, 1.0))
