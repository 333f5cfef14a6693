"""Duck-typed conversions between posekit geometry and ROS-shaped message objects.

Inputs are read by attribute name only, so ``posekit.msgs``, rclpy and rosbags messages (or
any object with the same fields) all work: quaternions need ``.x .y .z .w`` (ROS order),
vectors/points ``.x .y .z``; transforms ``.translation``/``.rotation``, poses
``.position``/``.orientation``; stamped wrappers ``.transform``/``.pose`` are unwrapped.

Outputs: pass the message class to build (``msg_type=``), or leave it out to get
``posekit.msgs.geometry_msgs`` classes. That import (of the layer below) happens inside the
function, so that ``import posekit.geometry`` stays as light as numpy alone.
"""

from __future__ import annotations

import math
from typing import Any

from posekit.geometry._parse import check_finite
from posekit.geometry._quat import quat_from_rpy_xyzw, quat_normalize_xyzw
from posekit.geometry.rotation import Rotation
from posekit.geometry.se2 import Pose2D
from posekit.geometry.transform import Transform

__all__ = [
    "pose2d_from_transform",
    "pose2d_to_transform",
    "rotation_from_msg",
    "rotation_to_msg",
    "transform_from_msg",
    "transform_to_msg",
    "transform_to_pose_msg",
    "vector_from_msg",
    "vector_to_msg",
]


def rotation_from_msg(q: Any) -> Rotation:
    """Rotation from anything with ``.x .y .z .w`` (normalised; NaN/zero raise)."""
    return Rotation._single(quat_normalize_xyzw(float(q.x), float(q.y), float(q.z), float(q.w)))


def vector_from_msg(v: Any) -> tuple[float, float, float]:
    """``(x, y, z)`` floats from a Vector3/Point-like object."""
    out = (float(v.x), float(v.y), float(v.z))
    check_finite(out, "vector")
    return out


def transform_from_msg(msg: Any) -> Transform:
    """Transform from a Transform/Pose-like message (or their Stamped wrappers).

    A ``geometry_msgs/Transform`` in a ``TransformStamped`` is ``T_parent_child``; a Pose is
    the transform from the body frame into the pose's frame.
    """
    if hasattr(msg, "transform"):
        msg = msg.transform
    elif hasattr(msg, "pose") and not hasattr(msg, "position"):
        msg = msg.pose
        if hasattr(msg, "pose"):  # PoseWithCovariance
            msg = msg.pose
    if hasattr(msg, "translation") and hasattr(msg, "rotation"):
        t, q = msg.translation, msg.rotation
    elif hasattr(msg, "position") and hasattr(msg, "orientation"):
        t, q = msg.position, msg.orientation
    else:
        raise TypeError(
            f"{type(msg).__name__} has neither (translation, rotation) nor "
            "(position, orientation) fields"
        )
    return Transform._single(rotation_from_msg(q), vector_from_msg(t))


def _single_quat(r: Rotation) -> tuple[float, float, float, float]:
    if not r.single:
        raise TypeError("messages hold a single rotation; index the batch first")
    return r.as_quat_tuple()


def rotation_to_msg(r: Rotation, msg_type: type[Any] | None = None) -> Any:
    """A Quaternion message (``x, y, z, w``) of a single rotation."""
    if msg_type is None:
        from posekit.msgs.geometry_msgs import Quaternion

        msg_type = Quaternion
    x, y, z, w = _single_quat(r)
    msg = msg_type()
    msg.x, msg.y, msg.z, msg.w = x, y, z, w
    return msg


def vector_to_msg(v: Any, msg_type: type[Any] | None = None) -> Any:
    """A Vector3 (default) or ``msg_type`` (e.g. Point) from 3 numbers."""
    if msg_type is None:
        from posekit.msgs.geometry_msgs import Vector3

        msg_type = Vector3
    msg = msg_type()
    msg.x, msg.y, msg.z = float(v[0]), float(v[1]), float(v[2])
    return msg


def transform_to_msg(T: Transform, msg_type: type[Any] | None = None) -> Any:
    """A ``geometry_msgs/Transform`` (or ``msg_type`` with translation/rotation fields)."""
    if msg_type is None:
        from posekit.msgs.geometry_msgs import Transform as TransformMsg

        msg_type = TransformMsg
    msg = msg_type()
    t = T.translation_tuple()
    msg.translation.x, msg.translation.y, msg.translation.z = t
    x, y, z, w = _single_quat(T.rotation)
    msg.rotation.x, msg.rotation.y, msg.rotation.z, msg.rotation.w = x, y, z, w
    return msg


def transform_to_pose_msg(T: Transform, msg_type: type[Any] | None = None) -> Any:
    """A ``geometry_msgs/Pose`` (or ``msg_type`` with position/orientation fields)."""
    if msg_type is None:
        from posekit.msgs.geometry_msgs import Pose

        msg_type = Pose
    msg = msg_type()
    t = T.translation_tuple()
    msg.position.x, msg.position.y, msg.position.z = t
    x, y, z, w = _single_quat(T.rotation)
    msg.orientation.x, msg.orientation.y, msg.orientation.z, msg.orientation.w = x, y, z, w
    return msg


def pose2d_to_transform(p: Pose2D, z: float = 0.0) -> Transform:
    """The SE(3) transform of a planar pose (yaw about +z, at height ``z``)."""
    return Transform._single(
        Rotation._single(quat_from_rpy_xyzw(0.0, 0.0, p.theta)), (p.x, p.y, float(z))
    )


def pose2d_from_transform(T: Transform) -> Pose2D:
    """Project an SE(3) transform onto the plane: keep x, y and the heading of the x axis.

    The heading is ``atan2(R[1, 0], R[0, 0])``, the yaw of the body x axis projected onto
    the ground plane (equal to ROS yaw when roll = pitch = 0).
    """
    x, y, _ = T.translation_tuple()
    qx, qy, qz, qw = _single_quat(T.rotation)
    r00 = 1.0 - 2.0 * (qy * qy + qz * qz)
    r10 = 2.0 * (qx * qy + qw * qz)
    return Pose2D(x, y, math.atan2(r10, r00))
