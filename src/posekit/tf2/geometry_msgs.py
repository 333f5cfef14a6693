"""tf2_geometry_msgs: apply a ``TransformStamped`` (T_target_source) to stamped geometry.

Each ``do_transform_*(obj, transform)`` returns a new message expressed in
``transform.header.frame_id`` with ``header = transform.header`` (as tf2_geometry_msgs does).
Points and poses get rotation and translation; vectors (directions) get the rotation only.
"""

from __future__ import annotations

from typing import Any

from posekit.msgs.builtin_interfaces import Time as TimeMsg
from posekit.msgs.geometry_msgs import (
    Point,
    PointStamped,
    Pose,
    PoseStamped,
    Quaternion,
    Transform,
    TransformStamped,
    Vector3,
    Vector3Stamped,
)
from posekit.msgs.std_msgs import Header
from posekit.tf2._linear_math import Quat, Vec3, quat_mul, quat_rotate

__all__ = [
    "do_transform_point",
    "do_transform_pose",
    "do_transform_pose_stamped",
    "do_transform_transform",
    "do_transform_vector3",
]


def _rt(transform: Any) -> tuple[Quat, Vec3]:
    tr = transform.transform
    r, t = tr.rotation, tr.translation
    q = (float(r.x), float(r.y), float(r.z), float(r.w))
    n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]) ** 0.5
    return (q[0] / n, q[1] / n, q[2] / n, q[3] / n), (float(t.x), float(t.y), float(t.z))


def _header(transform: Any) -> Header:
    h = transform.header
    return Header(stamp=TimeMsg(sec=h.stamp.sec, nanosec=h.stamp.nanosec), frame_id=h.frame_id)


def _apply_point(q: Quat, t: Vec3, p: Any) -> Vec3:
    x, y, z = quat_rotate(q, (float(p.x), float(p.y), float(p.z)))
    return x + t[0], y + t[1], z + t[2]


def do_transform_point(point: Any, transform: Any) -> PointStamped:
    """PointStamped in the transform's target frame: p' = R p + t."""
    q, t = _rt(transform)
    x, y, z = _apply_point(q, t, point.point)
    return PointStamped(header=_header(transform), point=Point(x=x, y=y, z=z))


def do_transform_vector3(vector3: Any, transform: Any) -> Vector3Stamped:
    """Vector3Stamped rotated into the target frame (no translation): v' = R v."""
    q, _ = _rt(transform)
    v = vector3.vector
    x, y, z = quat_rotate(q, (float(v.x), float(v.y), float(v.z)))
    return Vector3Stamped(header=_header(transform), vector=Vector3(x=x, y=y, z=z))


def _pose(q: Quat, t: Vec3, pose: Any) -> Pose:
    x, y, z = _apply_point(q, t, pose.position)
    o = pose.orientation
    qx, qy, qz, qw = quat_mul(q, (float(o.x), float(o.y), float(o.z), float(o.w)))
    return Pose(position=Point(x=x, y=y, z=z), orientation=Quaternion(x=qx, y=qy, z=qz, w=qw))


def do_transform_pose(pose: Any, transform: Any) -> Any:
    """A Pose or a PoseStamped in the target frame; returns the same kind it was given.

    Pose is ROS 2 tf2_geometry_msgs' signature, PoseStamped the ROS 1 style. Position R p + t,
    orientation q_T * q_pose.
    """
    if hasattr(pose, "header"):
        return do_transform_pose_stamped(pose, transform)
    q, t = _rt(transform)
    return _pose(q, t, pose)


def do_transform_pose_stamped(pose: Any, transform: Any) -> PoseStamped:
    """PoseStamped in the transform's target frame."""
    q, t = _rt(transform)
    return PoseStamped(header=_header(transform), pose=_pose(q, t, pose.pose))


def do_transform_transform(transform_in: Any, transform: Any) -> TransformStamped:
    """Compose: T_target_child = T_target_source * T_source_child (child id kept)."""
    q, t = _rt(transform)
    tr = transform_in.transform
    x, y, z = _apply_point(q, t, tr.translation)
    o = tr.rotation
    qx, qy, qz, qw = quat_mul(q, (float(o.x), float(o.y), float(o.z), float(o.w)))
    return TransformStamped(
        header=_header(transform),
        child_frame_id=transform_in.child_frame_id,
        transform=Transform(
            translation=Vector3(x=x, y=y, z=z), rotation=Quaternion(x=qx, y=qy, z=qz, w=qw)
        ),
    )
