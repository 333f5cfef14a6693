"""do_transform_* helpers against 4x4 matrices built with scipy."""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from posekit.msgs.geometry_msgs import (
    PointStamped,
    Pose,
    PoseStamped,
    TransformStamped,
    Vector3Stamped,
)
from posekit.tf2 import (
    do_transform_point,
    do_transform_pose,
    do_transform_pose_stamped,
    do_transform_transform,
    do_transform_vector3,
)

vec = st.tuples(*[st.floats(-5, 5)] * 3)
quat = st.tuples(*[st.floats(-1, 1)] * 4).filter(lambda q: sum(c * c for c in q) > 0.1)


def make_tf(t: tuple[float, ...], q: tuple[float, ...]) -> TransformStamped:
    m = TransformStamped()
    m.header.frame_id = "target"
    m.header.stamp.sec = 7
    m.child_frame_id = "source"
    tr = m.transform
    tr.translation.x, tr.translation.y, tr.translation.z = t
    tr.rotation.x, tr.rotation.y, tr.rotation.z, tr.rotation.w = q
    return m


@given(vec, quat, vec)
def test_point_and_vector(t: tuple[float, ...], q: tuple[float, ...], p: tuple[float, ...]) -> None:
    tf = make_tf(t, q)
    r = Rotation.from_quat(q)
    ps = PointStamped()
    ps.header.frame_id = "source"
    ps.point.x, ps.point.y, ps.point.z = p
    out = do_transform_point(ps, tf)
    np.testing.assert_allclose([out.point.x, out.point.y, out.point.z], r.apply(p) + t, atol=1e-9)
    assert out.header.frame_id == "target"
    assert out.header.stamp.sec == 7
    vs = Vector3Stamped()
    vs.vector.x, vs.vector.y, vs.vector.z = p
    vo = do_transform_vector3(vs, tf)
    np.testing.assert_allclose([vo.vector.x, vo.vector.y, vo.vector.z], r.apply(p), atol=1e-9)


@given(vec, quat, vec, quat)
def test_pose_and_transform(
    t: tuple[float, ...], q: tuple[float, ...], p: tuple[float, ...], o: tuple[float, ...]
) -> None:
    tf = make_tf(t, q)
    r = Rotation.from_quat(q)
    pose = Pose()
    pose.position.x, pose.position.y, pose.position.z = p
    o_unit = np.array(o) / np.linalg.norm(o)
    pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w = o_unit
    out = do_transform_pose(pose, tf)
    assert isinstance(out, Pose)
    np.testing.assert_allclose(
        [out.position.x, out.position.y, out.position.z], r.apply(p) + t, atol=1e-9
    )
    got = Rotation.from_quat(
        [out.orientation.x, out.orientation.y, out.orientation.z, out.orientation.w]
    )
    assert got.approx_equal(r * Rotation.from_quat(o_unit), atol=1e-9)
    stamped = PoseStamped(pose=pose)
    assert do_transform_pose(stamped, tf) == do_transform_pose_stamped(stamped, tf)
    inner = make_tf(p, tuple(o_unit))
    inner.child_frame_id = "leaf"
    comp = do_transform_transform(inner, tf)
    assert comp.child_frame_id == "leaf"
    assert comp.header.frame_id == "target"
    tr = comp.transform.translation
    np.testing.assert_allclose([tr.x, tr.y, tr.z], r.apply(p) + t, atol=1e-9)
