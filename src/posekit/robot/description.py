"""The ROSbot's frames as robot_state_publisher publishes them from the course's URDF.

Fixed joints go to ``/tf_static`` (:func:`static_transforms`); the four continuous wheel
joints go to ``/tf`` from ``/joint_states`` (:func:`wheel_transforms`). Offsets (m) and rpy
(rad, fixed axes x-y-z) are those of docs/specs/rosbot_and_worlds.md (Husarion rosbot_description,
basic configuration with the OAK-D-PRO camera, depthai frame chain)::

    base_link -> body_link -> imu_link
                           -> camera_mount_link -> oak_link -> oak_rgb_camera_frame
                                  -> oak_rgb_camera_optical_frame
                              oak_link -> oak_left/right_camera_frame -> *_optical_frame
                           -> cover_link
                           -> fl/fr/rl/rr_wheel_link (continuous, about +y)

Each TransformStamped is T_parent_child: it maps child coordinates into the parent frame.
"""

from __future__ import annotations

import math

from posekit.geometry.scalar import quat_from_rpy
from posekit.msgs.geometry_msgs import Quaternion, TransformStamped, Vector3
from posekit.robot._msgutil import stamp_from_seconds
from posekit.robot.params import DEFAULT_DRIVE, WHEEL_JOINT_NAMES

__all__ = [
    "FIXED_JOINTS",
    "WHEEL_JOINTS",
    "FixedJoint",
    "static_transforms",
    "wheel_transforms",
]

_HALF_PI = math.pi / 2

#: (parent, child, xyz (m), rpy (rad)) of one fixed joint.
FixedJoint = tuple[str, str, tuple[float, float, float], tuple[float, float, float]]

#: The fixed joints of the course's ROSbot (docs/specs/rosbot_and_worlds.md, "Geometry"
#: and "Camera").
FIXED_JOINTS: tuple[FixedJoint, ...] = (
    ("base_link", "body_link", (0.0, 0.0, DEFAULT_DRIVE.wheel_radius), (0.0, 0.0, 0.0)),
    ("body_link", "imu_link", (0.003, -0.0495, 0.04332), (0.0, 0.0, 0.0)),
    ("body_link", "camera_mount_link", (-0.0141, 0.0, 0.125), (0.0, 0.0, 0.0)),
    ("body_link", "cover_link", (0.0, 0.0, 0.0603), (0.0, 0.0, 0.0)),
    ("camera_mount_link", "oak_link", (-0.01, 0.0, 0.02), (0.0, 0.0, 0.0)),
    ("oak_link", "oak_rgb_camera_frame", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)),
    (
        "oak_rgb_camera_frame",
        "oak_rgb_camera_optical_frame",
        (0.0, 0.0, 0.0),
        (-_HALF_PI, 0.0, -_HALF_PI),
    ),
    ("oak_link", "oak_left_camera_frame", (0.0, 0.0375, 0.0), (0.0, 0.0, 0.0)),
    (
        "oak_left_camera_frame",
        "oak_left_camera_optical_frame",
        (0.0, 0.0, 0.0),
        (-_HALF_PI, 0.0, -_HALF_PI),
    ),
    ("oak_link", "oak_right_camera_frame", (0.0, -0.0375, 0.0), (0.0, 0.0, 0.0)),
    (
        "oak_right_camera_frame",
        "oak_right_camera_optical_frame",
        (0.0, 0.0, 0.0),
        (-_HALF_PI, 0.0, -_HALF_PI),
    ),
)

#: (joint, child link, xyz in body_link) of the wheels, in WHEEL_JOINT_NAMES order.
WHEEL_JOINTS: tuple[tuple[str, str, tuple[float, float, float]], ...] = (
    (WHEEL_JOINT_NAMES[0], "fl_wheel_link", (0.053, 0.096, 0.0)),
    (WHEEL_JOINT_NAMES[1], "fr_wheel_link", (0.053, -0.096, 0.0)),
    (WHEEL_JOINT_NAMES[2], "rl_wheel_link", (-0.053, 0.096, 0.0)),
    (WHEEL_JOINT_NAMES[3], "rr_wheel_link", (-0.053, -0.096, 0.0)),
)


def _transform(
    parent: str,
    child: str,
    xyz: tuple[float, float, float],
    quat_xyzw: tuple[float, ...],
    t: float,
) -> TransformStamped:
    tf = TransformStamped()
    tf.header.stamp = stamp_from_seconds(t)
    tf.header.frame_id = parent
    tf.child_frame_id = child
    tf.transform.translation = Vector3(x=xyz[0], y=xyz[1], z=xyz[2])
    qx, qy, qz, qw = quat_xyzw
    tf.transform.rotation = Quaternion(x=qx, y=qy, z=qz, w=qw)
    return tf


def static_transforms(t: float = 0.0) -> list[TransformStamped]:
    """The fixed-joint transforms for ``/tf_static``, stamped ``t`` (s)."""
    return [
        _transform(parent, child, xyz, quat_from_rpy(*rpy), t)
        for parent, child, xyz, rpy in FIXED_JOINTS
    ]


def wheel_transforms(
    positions: tuple[float, float, float, float], t: float
) -> list[TransformStamped]:
    """``body_link -> *_wheel_link`` for joint angles (rad, fl fr rl rr) at ``t`` (s)."""
    out = []
    for (_, link, xyz), angle in zip(WHEEL_JOINTS, positions, strict=True):
        q_about_y = (0.0, math.sin(0.5 * angle), 0.0, math.cos(0.5 * angle))
        out.append(_transform("body_link", link, xyz, q_about_y, t))
    return out
