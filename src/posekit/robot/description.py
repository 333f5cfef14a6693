"""The ROSbot's frames as robot_state_publisher publishes them from the course's URDF.

Fixed joints go to ``/tf_static`` (:func:`static_transforms`); the four continuous wheel
joints go to ``/tf`` from ``/joint_states`` (:func:`wheel_transforms`). Offsets (m) and rpy
(rad, fixed axes x-y-z) are those of docs/specs/rosbot_and_worlds.md (Husarion rosbot_description,
basic configuration with the OAK-D-PRO camera, depthai frame chain)::

    base_link -> body_link -> imu_link
                           -> camera_mount_link -> oak_link -> oak_rgb_camera_frame
                                  -> oak_rgb_camera_optical_frame
                              oak_link -> oak_left/right_camera_frame -> *_optical_frame
                           -> cover_link -> slamtec_rplidar_link -> laser
                           -> fl/fr/rl/rr_wheel_link (continuous, about +y)

The lidar (component LDR02, a Slamtec RPLIDAR S2) follows Husarion's
husarion_components_description ``slamtec_rplidar`` macro: its body
``slamtec_rplidar_link`` sits on ``cover_link`` at (0.02, 0, 0) (the ROSbot's component
configuration) and the scan frame ``laser`` 0.0285 m above it, turned by pi about z (the
S2's zero angle points at its cable side, which faces the robot's rear), so a LaserScan's
angle 0 points backwards from the robot.

Each TransformStamped is T_parent_child: it maps child coordinates into the parent frame.

:func:`robot_description_urdf` writes the same tree as a URDF (what robot_state_publisher
publishes on ``/robot_description``): one ``<link>`` per frame above, the fixed joints of
:data:`FIXED_JOINTS` and the four continuous wheel joints (axis +y, limits 1.5 N·m and
24 rad/s), with primitive geometry where Husarion's description gives dimensions
(:data:`LINK_GEOMETRY`). The range sensors (VL53L0X) and their frames of Husarion's
description are not simulated and not in the URDF.
"""

from __future__ import annotations

import math
from typing import Any

from posekit.geometry import Transform
from posekit.geometry.scalar import quat_from_rpy
from posekit.msgs.geometry_msgs import Quaternion, TransformStamped, Vector3
from posekit.robot.params import DEFAULT_DRIVE, WHEEL_JOINT_NAMES
from posekit.time import stamp_from_seconds

__all__ = [
    "FIXED_JOINTS",
    "LINK_GEOMETRY",
    "WHEEL_JOINTS",
    "FixedJoint",
    "T_base_frame",
    "robot_description_urdf",
    "static_transforms",
    "wheel_transforms",
]

_HALF_PI = math.pi / 2

#: (parent, child, xyz (m), rpy (rad)) of one fixed joint.
FixedJoint = tuple[str, str, tuple[float, float, float], tuple[float, float, float]]

#: The fixed joints of the course's ROSbot (docs/specs/rosbot_and_worlds.md, "Geometry",
#: "Camera" and "LiDAR").
FIXED_JOINTS: tuple[FixedJoint, ...] = (
    ("base_link", "body_link", (0.0, 0.0, DEFAULT_DRIVE.wheel_radius), (0.0, 0.0, 0.0)),
    ("body_link", "imu_link", (0.003, -0.0495, 0.04332), (0.0, 0.0, 0.0)),
    ("body_link", "camera_mount_link", (-0.0141, 0.0, 0.125), (0.0, 0.0, 0.0)),
    ("body_link", "cover_link", (0.0, 0.0, 0.0603), (0.0, 0.0, 0.0)),
    ("cover_link", "slamtec_rplidar_link", (0.02, 0.0, 0.0), (0.0, 0.0, 0.0)),
    ("slamtec_rplidar_link", "laser", (0.0, 0.0, 0.0285), (0.0, 0.0, math.pi)),
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


#: URDF visual and collision geometry per link: (kind, dimensions (m), xyz (m), rpy (rad)).
#: ``box`` takes (x, y, z) sizes, ``cylinder`` (radius, length) along its z axis. Body: the
#: collision box of Husarion's ``body.urdf.xacro`` (its visual is a mesh); wheels: radius
#: 0.0425, width 0.036, axis turned onto y; lidar: the ``slamtec_rplidar`` S2 collision box;
#: camera: the OAK-D Pro's outer size (97 x 29.5 x 22.3 mm, Luxonis' product data).
LINK_GEOMETRY: dict[
    str, tuple[str, tuple[float, ...], tuple[float, float, float], tuple[float, float, float]]
] = {
    "body_link": ("box", (0.197, 0.150, 0.080), (0.0, 0.0, 0.02), (0.0, 0.0, 0.0)),
    **{
        link: ("cylinder", (DEFAULT_DRIVE.wheel_radius, 0.036), (0.0, 0.0, 0.0),
               (_HALF_PI, 0.0, 0.0))
        for _, link, _ in WHEEL_JOINTS
    },
    "slamtec_rplidar_link": (
        "box", (0.077, 0.076856, 0.038857), (0.0, 0.0, 0.038857 / 2), (0.0, 0.0, 0.0)
    ),
    "oak_link": ("box", (0.0223, 0.097, 0.0295), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)),
}


def _fmt(values: tuple[float, ...]) -> str:
    return " ".join(repr(float(v)) for v in values)


def _origin(parent: Any, xyz: tuple[float, ...], rpy: tuple[float, ...]) -> None:
    from xml.etree import ElementTree as ET

    ET.SubElement(parent, "origin", xyz=_fmt(xyz), rpy=_fmt(rpy))


def robot_description_urdf(name: str = "rosbot") -> str:
    """The ROSbot's URDF (XML text) with exactly the links and joints posekit's TF tree has.

    Fixed joints are named ``<parent>_to_<child>_joint`` with ``_link`` dropped
    (``base_to_body_joint``, ``body_to_imu_joint``, ``cover_to_slamtec_rplidar_joint``, as
    in Husarion's description); the wheel joints keep the controller's names.
    """
    from xml.etree import ElementTree as ET

    robot = ET.Element("robot", name=name)
    links = ["base_link"] + [child for _, child, _, _ in FIXED_JOINTS]
    links += [link for _, link, _ in WHEEL_JOINTS]
    for link in links:
        el = ET.SubElement(robot, "link", name=link)
        if link in LINK_GEOMETRY:
            kind, dims, xyz, rpy = LINK_GEOMETRY[link]
            for tag in ("visual", "collision"):
                part = ET.SubElement(el, tag)
                _origin(part, xyz, rpy)
                geometry = ET.SubElement(part, "geometry")
                if kind == "box":
                    ET.SubElement(geometry, "box", size=_fmt(dims))
                else:
                    ET.SubElement(
                        geometry, "cylinder", radius=repr(dims[0]), length=repr(dims[1])
                    )
    for parent, child, xyz, rpy in FIXED_JOINTS:
        joint = ET.SubElement(robot, "joint", name=_joint_name(parent, child), type="fixed")
        ET.SubElement(joint, "parent", link=parent)
        ET.SubElement(joint, "child", link=child)
        _origin(joint, xyz, rpy)
    for joint_name, link, xyz in WHEEL_JOINTS:
        joint = ET.SubElement(robot, "joint", name=joint_name, type="continuous")
        ET.SubElement(joint, "parent", link="body_link")
        ET.SubElement(joint, "child", link=link)
        _origin(joint, xyz, (0.0, 0.0, 0.0))
        ET.SubElement(joint, "axis", xyz="0 1 0")
        ET.SubElement(joint, "limit", effort="1.5", velocity="24.0")
    ET.indent(robot)
    return '<?xml version="1.0"?>\n' + ET.tostring(robot, encoding="unicode") + "\n"


def _joint_name(parent: str, child: str) -> str:
    def short(link: str) -> str:
        return link.removesuffix("_link")

    return f"{short(parent)}_to_{short(child)}_joint"


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


def T_base_frame(frame: str) -> Transform:
    """The fixed pose of ``frame`` in ``base_link`` (composed along :data:`FIXED_JOINTS`).

    Raises:
        KeyError: ``frame`` is not a fixed frame of the robot.
    """
    by_child = {child: (parent, xyz, rpy) for parent, child, xyz, rpy in FIXED_JOINTS}
    T = Transform.identity()
    while frame != "base_link":
        if frame not in by_child:
            raise KeyError(f"{frame!r} is not a fixed frame of the ROSbot")
        parent, xyz, rpy = by_child[frame]
        T = Transform.from_xyz_rpy(xyz, rpy) * T
        frame = parent
    return T


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
