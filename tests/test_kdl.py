"""posekit.kdl: the PyKDL subset, checked against closed forms (PyKDL is not installable)."""

import math
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import posekit.kdl as PyKDL
from posekit.msgs.geometry_msgs import Pose, TransformStamped

ang = st.floats(-math.pi, math.pi, allow_nan=False)


def rx(a):
    return np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])


def ry(a):
    return np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])


def rz(a):
    return np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])


def mat(R):
    return np.array([[R[i, j] for j in range(3)] for i in range(3)])


def vec(v):
    return np.array([v.x(), v.y(), v.z()])


# The lecture's kdl_chain_demo helpers, verbatim apart from the import.
def transform_to_kdl(t):
    p, q = t.transform.translation, t.transform.rotation
    return PyKDL.Frame(
        PyKDL.Rotation.Quaternion(q.x, q.y, q.z, q.w),
        PyKDL.Vector(p.x, p.y, p.z),
    )


def kdl_to_pose(frame):
    pose = Pose()
    pose.position.x, pose.position.y, pose.position.z = (frame.p.x(), frame.p.y(), frame.p.z())
    qx, qy, qz, qw = frame.M.GetQuaternion()
    pose.orientation.x, pose.orientation.y = qx, qy
    pose.orientation.z, pose.orientation.w = qz, qw
    return pose


def test_lecture_kdl_chain_demo_runs_and_matches_matrix_chain():
    t_target_middle = TransformStamped()  # odom -> overhead camera optical frame
    t_target_middle.transform.translation.x = 1.0
    t_target_middle.transform.translation.z = 3.0
    t_target_middle.transform.rotation.x = 1.0  # 180 deg about x: camera looks down
    t_target_middle.transform.rotation.w = 0.0
    t_middle_source = TransformStamped()  # camera -> box, 2.5 m in front, yawed 90 deg
    t_middle_source.transform.translation.z = 2.5
    t_middle_source.transform.rotation.z = math.sin(math.pi / 4)
    t_middle_source.transform.rotation.w = math.cos(math.pi / 4)
    kdl_target_source = transform_to_kdl(t_target_middle) * transform_to_kdl(t_middle_source)
    pose = kdl_to_pose(kdl_target_source)
    # closed form: T = [Rx(pi), (1,0,3)] [Rz(pi/2), (0,0,2.5)]
    R = rx(math.pi) @ rz(math.pi / 2)
    t = rx(math.pi) @ [0, 0, 2.5] + [1, 0, 3]
    np.testing.assert_allclose([pose.position.x, pose.position.y, pose.position.z], t, atol=1e-15)
    q = (pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w)
    # R = Rx(pi) Rz(pi/2): q = i (s + s k) = s i + s ik = s i - s j, s = sqrt(2)/2
    s = math.sqrt(0.5)
    expected = np.array((s, -s, 0, 0))
    assert np.allclose(q, expected, atol=1e-15) or np.allclose(q, -expected, atol=1e-15)
    np.testing.assert_allclose(mat(kdl_target_source.M), R, atol=1e-15)


@given(ang, st.floats(-1.5, 1.5), ang)
def test_rpy_closed_form_and_round_trip(r, p, y):
    R = PyKDL.Rotation.RPY(r, p, y)
    np.testing.assert_allclose(mat(R), rz(y) @ ry(p) @ rx(r), atol=1e-14)
    np.testing.assert_allclose(R.GetRPY(), (r, p, y), atol=1e-12)
    np.testing.assert_allclose(mat(PyKDL.Rotation.EulerZYX(y, p, r)), mat(R), atol=1e-14)
    np.testing.assert_allclose(R.GetEulerZYX(), (y, p, r), atol=1e-12)
    v = PyKDL.Vector(0.3, -0.2, 1.0)
    np.testing.assert_allclose(vec(R * v), mat(R) @ [0.3, -0.2, 1.0], atol=1e-14)
    np.testing.assert_allclose(mat(R.Inverse()), mat(R).T, atol=1e-14)
    np.testing.assert_allclose(mat(R * R.Inverse()), np.eye(3), atol=1e-14)


def test_getrpy_gimbal_rule_of_kdl_sets_roll_to_zero():
    R = PyKDL.Rotation.RPY(0.3, math.pi / 2, 0.5)
    roll, pitch, yaw = R.GetRPY()
    assert roll == 0.0
    assert pitch == pytest.approx(math.pi / 2)
    np.testing.assert_allclose(mat(PyKDL.Rotation.RPY(roll, pitch, yaw)), mat(R), atol=1e-12)


def test_quaternion_constructor_and_getter():
    s = math.sqrt(0.5)
    R = PyKDL.Rotation.Quaternion(s, 0, 0, s)  # 90 deg about x (lecture exercise)
    np.testing.assert_allclose(mat(R), rx(math.pi / 2), atol=1e-15)
    np.testing.assert_allclose(R.GetQuaternion(), (s, 0, 0, s), atol=1e-15)
    R2 = PyKDL.Rotation.Quaternion(0, 0, 0, 3.0)  # non-unit: normalised
    np.testing.assert_allclose(mat(R2), np.eye(3))
    M = PyKDL.Rotation(*rz(0.4).ravel())
    np.testing.assert_allclose(mat(M), rz(0.4), atol=1e-15)
    assert PyKDL.Rotation.RotZ(0.4) == M
    np.testing.assert_allclose(vec(M.UnitX()), rz(0.4)[:, 0], atol=1e-15)
    np.testing.assert_allclose(vec(PyKDL.Rotation.RotY(0.2).UnitZ()), ry(0.2)[:, 2], atol=1e-15)
    np.testing.assert_allclose(vec(PyKDL.Rotation.RotX(0.2).UnitY()), rx(0.2)[:, 1], atol=1e-15)
    axis = PyKDL.Vector(0, 0, 2)
    assert PyKDL.Rotation.Rot(axis, 0.4) == M
    np.testing.assert_allclose(vec(M.GetRot()), [0, 0, 0.4], atol=1e-15)
    np.testing.assert_allclose(
        mat(PyKDL.Rotation.EulerZYZ(0.1, 0.2, 0.3)), rz(0.1) @ ry(0.2) @ rz(0.3), atol=1e-15
    )


def test_frame_algebra():
    F_a_b = PyKDL.Frame(PyKDL.Rotation.RotZ(math.pi / 2), PyKDL.Vector(1, 0, 0))
    F_b_c = PyKDL.Frame(PyKDL.Vector(0, 2, 0))
    F_a_c = F_a_b * F_b_c
    # c's origin: 2 m along b's y, which is a's -x, plus b's origin (1, 0, 0)
    np.testing.assert_allclose(vec(F_a_c.p), [-1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(vec(F_a_b * PyKDL.Vector(1, 0, 0)), [1, 1, 0], atol=1e-15)
    ident = F_a_b * F_a_b.Inverse()
    assert ident == PyKDL.Frame.Identity()
    np.testing.assert_allclose(vec(F_a_b.Inverse().p), [0, 1, 0], atol=1e-15)
    assert PyKDL.Frame(PyKDL.Rotation.RotX(1.0)).p == PyKDL.Vector.Zero()
    with pytest.raises(TypeError):
        PyKDL.Frame(1.0)


def test_vector_interface():
    v = PyKDL.Vector(1, 2, 3)
    assert (v.x(), v.y(), v.z()) == (1, 2, 3)
    assert (v[0], v[1], v[2], v[-1]) == (1, 2, 3, 3)
    v[1] = 5.0
    v.z(7.0)
    assert list(v) == [1, 5, 7]
    assert v * PyKDL.Vector(0, 0, 1) == PyKDL.Vector(5, -1, 0)  # cross product, as PyKDL
    assert PyKDL.dot(v, PyKDL.Vector(1, 1, 1)) == 13
    assert 2 * v == v * 2 == PyKDL.Vector(2, 10, 14)
    assert (v - v).Norm() == 0
    assert (v + v) / 2 == v
    assert PyKDL.Vector(3, 4, 0).Norm() == 5
    w = PyKDL.Vector(0, 3, 4)
    assert w.Normalize() == 5
    assert w == PyKDL.Vector(0, 0.6, 0.8)
    with pytest.raises(IndexError):
        v[3]


def test_duck_typed_inputs_work_too():
    t = SimpleNamespace(
        transform=SimpleNamespace(
            translation=SimpleNamespace(x=1, y=2, z=3),
            rotation=SimpleNamespace(x=0, y=0, z=0, w=1),
        )
    )
    assert transform_to_kdl(t).p == PyKDL.Vector(1, 2, 3)
