"""``kdl_chain_demo``: the lecture's ``kdl_chain_demo.py`` (KDL Frames).

Every ``period`` seconds it looks up the two hops *separately*::

    T_odom_camera = lookup_transform(target_frame, intermediate_frame, Time())
    T_camera_box  = lookup_transform(intermediate_frame, source_frame, Time())

composes them with :mod:`posekit.kdl` (``PyKDL.Frame * PyKDL.Frame``) into
``T_odom_box = T_odom_camera * T_camera_box`` and logs, in the course's number format::

    KDL-composed static_aruco_box in odom: pos=(2.000, 2.000, 0.481) quat=(-0.002, -0.001,
    1.000, 0.007)

(one line; the numbers are a run of the ``kdl_chain_demo`` scenario: the plain ArUco
corners put the marker 2 cm too far from the camera, see docs/vision.md).

``posekit tf echo odom static_aruco_box`` (tf2's own chaining) prints the same pose.

Parameters (course): ``target_frame`` (odom), ``intermediate_frame``
(overhead_camera_optical_frame), ``source_frame`` (static_aruco_box), ``period`` (1.0 s);
posekit: ``lookup_timeout`` (0.1 s).
"""

from __future__ import annotations

from typing import Any

import posekit.kdl as PyKDL  # noqa: N812 - the lecture's spelling
from posekit.msgs.geometry_msgs import Pose, TransformStamped
from posekit.runtime.parameters import declare_value
from posekit.tf2.exceptions import TransformException
from posekit.time import Time
from posekit.vision.nodes._tf_lookup import PeriodicTfLookupNode

__all__ = ["KdlChainDemo", "kdl_to_pose", "transform_to_kdl"]


def transform_to_kdl(t: TransformStamped) -> PyKDL.Frame:
    """``PyKDL.Frame`` of a TransformStamped (T_parent_child; quaternion x, y, z, w)."""
    p, q = t.transform.translation, t.transform.rotation
    return PyKDL.Frame(PyKDL.Rotation.Quaternion(q.x, q.y, q.z, q.w),
                       PyKDL.Vector(p.x, p.y, p.z))


def kdl_to_pose(frame: PyKDL.Frame) -> Pose:
    """``geometry_msgs/Pose`` of a ``PyKDL.Frame`` (position m, orientation x, y, z, w)."""
    pose = Pose()
    pose.position.x, pose.position.y, pose.position.z = frame.p.x(), frame.p.y(), frame.p.z()
    qx, qy, qz, qw = frame.M.GetQuaternion()
    pose.orientation.x, pose.orientation.y = qx, qy
    pose.orientation.z, pose.orientation.w = qz, qw
    return pose


class KdlChainDemo(PeriodicTfLookupNode):
    """Composes two TF hops with KDL and logs the result (module docstring).

    Attributes: ``last_frame`` (the composed ``PyKDL.Frame``), ``last_pose`` (as a Pose),
    ``hops`` (the two TransformStamped of the last composition), ``compositions`` (count).
    """

    def __init__(self, node_name: str = "kdl_chain_demo", **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)
        self._target = str(declare_value(self, "target_frame", "odom"))
        self._middle = str(
            declare_value(self, "intermediate_frame", "overhead_camera_optical_frame"))
        self._source = str(declare_value(self, "source_frame", "static_aruco_box"))
        self.last_frame: PyKDL.Frame | None = None
        self.last_pose: Pose | None = None
        self.hops: tuple[TransformStamped, TransformStamped] | None = None
        self.compositions = 0
        self.get_logger().info(
            f"KDL chain demo: {self._target} <- {self._middle} <- {self._source}"
        )

    def _timer_callback(self) -> None:
        try:
            t_target_middle = self._tf_buffer.lookup_transform(
                self._target, self._middle, Time(), timeout=self._timeout)
            t_middle_source = self._tf_buffer.lookup_transform(
                self._middle, self._source, Time(), timeout=self._timeout)
        except TransformException as exc:
            self.get_logger().warn(f"TF lookup failed: {exc}", throttle_duration_sec=2.0)
            return
        # Chain by hand: T_target_source = T_target_middle * T_middle_source.
        frame = transform_to_kdl(t_target_middle) * transform_to_kdl(t_middle_source)
        pose = kdl_to_pose(frame)
        self.last_frame, self.last_pose = frame, pose
        self.hops = (t_target_middle, t_middle_source)
        self.compositions += 1
        p, o = pose.position, pose.orientation
        self.get_logger().info(
            f"KDL-composed {self._source} in {self._target}: "
            f"pos=({p.x:.3f}, {p.y:.3f}, {p.z:.3f}) "
            f"quat=({o.x:.3f}, {o.y:.3f}, {o.z:.3f}, {o.w:.3f})"
        )
