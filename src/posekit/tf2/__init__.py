"""posekit.tf2: a transform buffer with ROS 2 tf2's exact semantics, plus vectorised lookups.

``from posekit.tf2 import Buffer, TransformException`` replaces ``from tf2_ros import ...``.
Times are integer nanoseconds inside; lookups accept :class:`posekit.time.Time`, a
``builtin_interfaces/Time`` or int ns (0 = latest common time). Quaternions are (x, y, z, w).

``quat_from_rpy``, ``rpy_from_quat`` and ``matrix_from_quat`` are tf2's own
``Quaternion::setRPY``, ``Matrix3x3::getRPY`` and ``Matrix3x3::setRotation`` arithmetic
(what tf2's tools print and publish, to the last bit); :mod:`posekit.geometry.scalar` has
the same conversions for general use.
"""

from __future__ import annotations

from posekit.tf2._linear_math import matrix_from_quat, quat_from_rpy, rpy_from_quat
from posekit.tf2.buffer import Buffer, TransformRegistration
from posekit.tf2.buffer_core import MAX_GRAPH_DEPTH, BufferCore, time_to_ns
from posekit.tf2.exceptions import (
    BackwardExtrapolationException,
    ConnectivityException,
    ExtrapolationException,
    ForwardExtrapolationException,
    InvalidArgumentException,
    LookupException,
    NoDataForExtrapolationException,
    TimeoutException,
    TransformException,
    TypeException,
)
from posekit.tf2.future import Future
from posekit.tf2.geometry_msgs import (
    do_transform_point,
    do_transform_pose,
    do_transform_pose_stamped,
    do_transform_transform,
    do_transform_vector3,
)
from posekit.tf2.time_cache import DEFAULT_CACHE_TIME_NS

__all__ = [
    "DEFAULT_CACHE_TIME_NS",
    "MAX_GRAPH_DEPTH",
    "BackwardExtrapolationException",
    "Buffer",
    "BufferCore",
    "ConnectivityException",
    "ExtrapolationException",
    "ForwardExtrapolationException",
    "Future",
    "InvalidArgumentException",
    "LookupException",
    "NoDataForExtrapolationException",
    "TimeoutException",
    "TransformException",
    "TransformRegistration",
    "TypeException",
    "do_transform_point",
    "do_transform_pose",
    "do_transform_pose_stamped",
    "do_transform_transform",
    "do_transform_vector3",
    "matrix_from_quat",
    "quat_from_rpy",
    "rpy_from_quat",
    "time_to_ns",
]
