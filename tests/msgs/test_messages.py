"""Message classes: ROS 2 defaults, keyword construction, rclpy-style nested assignment."""

from __future__ import annotations

import numpy as np
import pytest

from posekit.msgs import builtin_interfaces, geometry_msgs, std_msgs, tf2_msgs
from posekit.msgs.geometry_msgs import (
    Point,
    PointStamped,
    Pose,
    PoseStamped,
    PoseWithCovariance,
    Quaternion,
    Transform,
    TransformStamped,
    Vector3,
    Vector3Stamped,
)
from posekit.msgs.std_msgs import Header
from posekit.msgs.tf2_msgs import TFMessage


@pytest.mark.parametrize(
    ("cls", "msgtype"),
    [
        (builtin_interfaces.Time, "builtin_interfaces/msg/Time"),
        (builtin_interfaces.Duration, "builtin_interfaces/msg/Duration"),
        (std_msgs.Header, "std_msgs/msg/Header"),
        (Vector3, "geometry_msgs/msg/Vector3"),
        (Quaternion, "geometry_msgs/msg/Quaternion"),
        (Point, "geometry_msgs/msg/Point"),
        (Pose, "geometry_msgs/msg/Pose"),
        (PoseStamped, "geometry_msgs/msg/PoseStamped"),
        (PointStamped, "geometry_msgs/msg/PointStamped"),
        (Vector3Stamped, "geometry_msgs/msg/Vector3Stamped"),
        (Transform, "geometry_msgs/msg/Transform"),
        (TransformStamped, "geometry_msgs/msg/TransformStamped"),
        (TFMessage, "tf2_msgs/msg/TFMessage"),
    ],
)
def test_no_argument_construction_and_type_name(cls: type, msgtype: str) -> None:
    msg = cls()
    assert msg.__msgtype__ == msgtype
    assert cls.__msgtype__ == msgtype


def test_ros_defaults() -> None:
    t = TransformStamped()
    assert t.header.stamp.sec == 0
    assert t.header.stamp.nanosec == 0
    assert t.header.frame_id == ""
    assert t.child_frame_id == ""
    tr = t.transform
    assert (tr.translation.x, tr.translation.y, tr.translation.z) == (0.0, 0.0, 0.0)
    q = tr.rotation
    assert (q.x, q.y, q.z, q.w) == (0.0, 0.0, 0.0, 1.0)  # identity, not the all-zero quaternion
    assert Pose().orientation == Quaternion(x=0.0, y=0.0, z=0.0, w=1.0)
    assert TFMessage().transforms == []


def test_keyword_construction() -> None:
    t = TransformStamped(
        header=Header(stamp=builtin_interfaces.Time(sec=5, nanosec=6), frame_id="odom"),
        child_frame_id="base_link",
        transform=Transform(translation=Vector3(x=1.0, y=2.0), rotation=Quaternion(z=1.0, w=0.0)),
    )
    assert t.header.frame_id == "odom"
    assert t.header.stamp.nanosec == 6
    assert t.transform.translation.y == 2.0
    assert t.transform.translation.z == 0.0
    assert t.transform.rotation.w == 0.0


def test_nested_assignment_like_rclpy() -> None:
    t = TransformStamped()
    t.header.stamp = builtin_interfaces.Time(sec=1, nanosec=2)
    t.header.frame_id = "world"
    t.child_frame_id = "map"
    t.transform.translation.x = 1.0
    t.transform.rotation.z = 0.5
    assert t.header.stamp == builtin_interfaces.Time(sec=1, nanosec=2)
    assert t.transform.translation.x == 1.0
    assert t.transform.rotation.z == 0.5
    msg = TFMessage()
    msg.transforms.append(t)
    assert msg.transforms[0].child_frame_id == "map"


def test_default_submessages_not_shared() -> None:
    a, b = TransformStamped(), TransformStamped()
    a.transform.translation.x = 3.0
    a.header.frame_id = "x"
    assert b.transform.translation.x == 0.0
    assert b.header.frame_id == ""
    m1, m2 = TFMessage(), TFMessage()
    m1.transforms.append(TransformStamped())
    assert m2.transforms == []


def test_value_equality_and_slots() -> None:
    assert PointStamped() == PointStamped()
    assert Point(x=1.0) != Point(x=2.0)
    with pytest.raises(AttributeError):
        Point().w = 1.0  # type: ignore[attr-defined]


def test_covariance_is_36_float64_zeros_and_compares_by_value() -> None:
    a = PoseWithCovariance()
    assert a.covariance.shape == (36,)
    assert a.covariance.dtype == np.float64
    assert not a.covariance.any()
    b = PoseWithCovariance()
    assert a == b
    b.covariance[0] = 1.0
    assert a != b
    assert a.covariance[0] == 0.0  # separate arrays


def test_modules_export_their_types() -> None:
    assert {"Vector3", "Quaternion", "TransformStamped"} <= set(geometry_msgs.__all__)
    assert "TFMessage" in tf2_msgs.__all__
    assert "Header" in std_msgs.__all__
