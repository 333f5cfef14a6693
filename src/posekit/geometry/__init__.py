"""posekit.geometry: rotations, rigid transforms and planar poses (numpy only).

Its only posekit import is :mod:`posekit.msgs` (the layer below), done inside the conversion
functions that build messages, so ``import posekit.geometry`` loads numpy alone. Public API:

* :class:`Rotation` - SO(3), scipy-like (one or a batch), plus ROS ``from_rpy``/``as_rpy``
  and the lecture's world/body composition helpers.
* :class:`Transform` - SE(3) ``T_a_b`` with ``T_a_c = T_a_b * T_b_c``.
* :class:`Slerp` - scipy's interpolation through key rotations at key times.
* :class:`Pose2D` - SE(2) with exact ``exp``/``log`` for arc odometry.
* :mod:`posekit.geometry.scalar` - the same maths as functions on plain float tuples.
* :func:`wrap_angle` - posekit's one angle-wrapping convention ([-π, π], in-range values
  untouched).
* duck-typed ROS message conversions, named errors and :class:`GimbalLockWarning`.

Conventions (quaternion order ``(x, y, z, w)`` unless ``scalar_first=True``, active
rotations, lowercase extrinsic / uppercase intrinsic Euler) are in ``docs/conventions.md``.
"""

from __future__ import annotations

from posekit.geometry import scalar
from posekit.geometry._quat import EULER_SEQUENCES, wrap_angle
from posekit.geometry.conversions import (
    pose2d_from_transform,
    pose2d_to_transform,
    rotation_from_msg,
    rotation_to_msg,
    transform_from_msg,
    transform_to_msg,
    transform_to_pose_msg,
    vector_from_msg,
    vector_to_msg,
)
from posekit.geometry.errors import (
    GeometryError,
    GimbalLockWarning,
    InvalidQuaternionError,
    NonFiniteError,
    NonOrthonormalMatrixError,
    ShapeError,
    UnknownSequenceError,
    ZeroAxisError,
)
from posekit.geometry.rotation import Rotation, compose_body, compose_world
from posekit.geometry.se2 import Pose2D
from posekit.geometry.slerp import Slerp
from posekit.geometry.transform import Transform

__all__ = [
    "EULER_SEQUENCES",
    "GeometryError",
    "GimbalLockWarning",
    "InvalidQuaternionError",
    "NonFiniteError",
    "NonOrthonormalMatrixError",
    "Pose2D",
    "Rotation",
    "ShapeError",
    "Slerp",
    "Transform",
    "UnknownSequenceError",
    "ZeroAxisError",
    "compose_body",
    "compose_world",
    "pose2d_from_transform",
    "pose2d_to_transform",
    "rotation_from_msg",
    "rotation_to_msg",
    "scalar",
    "transform_from_msg",
    "transform_to_msg",
    "transform_to_pose_msg",
    "vector_from_msg",
    "vector_to_msg",
    "wrap_angle",
]
