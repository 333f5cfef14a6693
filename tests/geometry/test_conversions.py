"""Duck-typed ROS message conversions, and the bottom-layer import rule."""

import math
import subprocess
import sys
from types import SimpleNamespace

import numpy as np
import pytest

from posekit.geometry import (
    InvalidQuaternionError,
    Rotation,
    Transform,
    rotation_from_msg,
    rotation_to_msg,
    transform_from_msg,
    transform_to_msg,
    transform_to_pose_msg,
    vector_from_msg,
    vector_to_msg,
)
from posekit.msgs import geometry_msgs


def test_geometry_does_not_import_msgs_or_numpy_eagerly():
    code = (
        "import sys, posekit.geometry; "
        "print('posekit.msgs' in sys.modules, type(sys.modules['numpy']).__name__)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    msgs_loaded, numpy_kind = out.stdout.split()
    assert msgs_loaded == "False"
    assert numpy_kind == "_LazyModule"  # deferred until the first array operation


def test_transform_stamped_round_trip():
    msg = geometry_msgs.TransformStamped()
    msg.transform.translation.x, msg.transform.translation.y = 1.0, -2.0
    msg.transform.rotation.z, msg.transform.rotation.w = math.sin(0.25), math.cos(0.25)
    T = transform_from_msg(msg)
    np.testing.assert_allclose(T.translation, [1, -2, 0])
    assert T.rotation.approx_equal(Rotation.from_rpy(0, 0, 0.5), atol=1e-15)
    out = transform_to_msg(T)
    assert isinstance(out, geometry_msgs.Transform)
    assert out.rotation.z == pytest.approx(math.sin(0.25))
    assert out.translation.y == -2.0
    pose = transform_to_pose_msg(T)
    assert isinstance(pose, geometry_msgs.Pose)
    assert pose.position.x == 1.0
    assert pose.orientation.w == pytest.approx(math.cos(0.25))
    assert transform_from_msg(pose).approx_equal(T, atol=1e-15)


def test_duck_typed_and_stamped_inputs():
    q = SimpleNamespace(x=0.0, y=0.0, z=0.0, w=2.0)  # non-unit: normalised
    assert rotation_from_msg(q).as_quat().tolist() == [0, 0, 0, 1]
    pose_stamped = geometry_msgs.PoseStamped()
    pose_stamped.pose.position.z = 3.0
    assert transform_from_msg(pose_stamped).translation.tolist() == [0, 0, 3]
    pwc = SimpleNamespace(pose=SimpleNamespace(pose=geometry_msgs.Pose()))
    assert transform_from_msg(pwc).approx_equal(Transform.identity())
    assert vector_from_msg(geometry_msgs.Point(x=1, y=2, z=3)) == (1.0, 2.0, 3.0)
    pt = vector_to_msg([4, 5, 6], geometry_msgs.Point)
    assert isinstance(pt, geometry_msgs.Point)
    assert (pt.x, pt.y, pt.z) == (4, 5, 6)
    v = vector_to_msg(np.array([1.0, 2.0, 3.0]))
    assert isinstance(v, geometry_msgs.Vector3)
    qm = rotation_to_msg(Rotation.from_rpy(0.1, 0, 0), msg_type=geometry_msgs.Quaternion)
    assert qm.x == pytest.approx(math.sin(0.05))


def test_bad_messages():
    with pytest.raises(InvalidQuaternionError):
        rotation_from_msg(SimpleNamespace(x=0, y=0, z=0, w=0))
    with pytest.raises(TypeError):
        transform_from_msg(SimpleNamespace(a=1))
    with pytest.raises(TypeError):
        rotation_to_msg(Rotation.random(2, rng=0))
