"""``oak_camera``: the ROSbot's simulated OAK-D colour camera (gz-sensors + ros_gz_bridge).

Renders the world's ArUco boxes from the robot's *true* pose at each frame time and publishes

==========================  ======================  ======================================
topic                       type                    content
==========================  ======================  ======================================
``/oak/rgb/color``          sensor_msgs/Image       rgb8 1280x720, 30 Hz, frame_id
                                                    ``oak_rgb_camera_optical_frame``
``/oak/stereo/camera_info`` sensor_msgs/CameraInfo  K of a 60 deg HFOV pinhole, d = 0
                                                    (the sim bridges only the stereo info)
==========================  ======================  ======================================

Camera pose: ``T_odom_optical(t) = T_odom_base(t) @ T_base_optical`` where ``T_base_optical``
is the robot description's fixed chain ``base_link -> ... -> oak_rgb_camera_optical_frame``
(:data:`posekit.robot.description.FIXED_JOINTS`) and ``T_odom_base(t)`` is the latest
``/ground_truth/odom`` sample (20 Hz) carried forward to the frame time ``t`` along its own
twist (exact arc), so frames between ground-truth samples are rendered where the robot
really is (a 33 ms-stale pose would shift a marker 2 m away by ~1 cm per 0.3 rad/s of turn).
Before the first sample the robot is at the world's spawn pose, at rest.

Images and CameraInfo are stamped with the camera's **optical** frame, as real camera drivers
do (REP 103): a consumer that reads ``header.frame_id`` (the lecture's detectors parent each
marker on it) gets x right, y down, z forward, the frame ``solvePnP`` answers in.

Parameters: ``world`` (aruco_box_world), ``width`` (1280), ``height`` (720),
``horizontal_fov`` (1.0471975512 rad = 60 deg), ``rate`` (30.0 Hz), ``image_topic``
(/oak/rgb/color), ``camera_info_topic`` (/oak/stereo/camera_info), ``optical_frame_id``
(oak_rgb_camera_optical_frame: the description frame rendered from), ``frame_id`` (the
header frame, "" = ``optical_frame_id``), ``ground_truth_topic`` (/ground_truth/odom), and
the common ``noise_sigma``, ``seed``, ``supersample``, ``lazy`` (see :class:`SimulatedCamera`).
"""

from __future__ import annotations

import math
from typing import Any

from posekit.geometry import Rotation, Transform
from posekit.geometry.se2 import integrate_arc
from posekit.msgs.nav_msgs import Odometry
from posekit.robot.description import FIXED_JOINTS
from posekit.robot.kinematics import yaw_from_quaternion_xyzw
from posekit.runtime.parameters import declare_value
from posekit.time import stamp_to_ns
from posekit.vision.camera import PinholeCamera
from posekit.vision.nodes._camera import F64Array, SimulatedCamera
from posekit.vision.nodes._common import NS, pose_from_chain

__all__ = ["OakCameraNode"]


class OakCameraNode(SimulatedCamera):
    """The ROSbot's OAK-D colour camera (see the module docstring)."""

    def __init__(self, node_name: str = "oak_camera", **kwargs: Any) -> None:
        super().__init__(node_name, "aruco_box_world", **kwargs)
        width = int(declare_value(self, "width", 1280))
        height = int(declare_value(self, "height", 720))
        hfov = float(declare_value(self, "horizontal_fov", math.radians(60.0)))
        rate = float(declare_value(self, "rate", 30.0))
        image_topic = str(declare_value(self, "image_topic", "/oak/rgb/color"))
        info_topic = str(declare_value(self, "camera_info_topic", "/oak/stereo/camera_info"))
        optical = str(declare_value(self, "optical_frame_id", "oak_rgb_camera_optical_frame"))
        frame_id = str(declare_value(self, "frame_id", "")) or optical
        truth_topic = str(declare_value(self, "ground_truth_topic", "/ground_truth/odom"))
        #: T_base_optical from the robot description (metres).
        self.T_base_optical: F64Array = pose_from_chain(FIXED_JOINTS, "base_link", optical)
        sx, sy, syaw = self.world.spawn
        # (t_ns, x, y, yaw, v, w) of the latest ground-truth sample.
        self._truth: tuple[int, float, float, float, float, float] = (0, sx, sy, syaw, 0.0, 0.0)
        self.create_subscription(Odometry, truth_topic, self._on_truth, 10)
        camera = PinholeCamera.from_hfov(width, height, hfov, near=0.05, far=100.0)
        self._start(camera, image_topic, info_topic, frame_id, rate)

    def _on_truth(self, msg: Odometry) -> None:
        p = msg.pose.pose.position
        q = msg.pose.pose.orientation
        yaw = yaw_from_quaternion_xyzw(q.x, q.y, q.z, q.w)
        tw = msg.twist.twist
        self._truth = (stamp_to_ns(msg.header.stamp), float(p.x), float(p.y), yaw,
                       float(tw.linear.x), float(tw.angular.z))

    def T_world_base_at(self, t_ns: int) -> F64Array:
        """Planar pose (4x4) of base_link in odom at ``t_ns``, from the latest ground truth."""
        t0, x, y, yaw, v, w = self._truth
        dt = max(0, t_ns - t0) / NS
        x, y, yaw = integrate_arc(x, y, yaw, v * dt, 0.0, w * dt)
        return Transform(Rotation.from_rpy(0.0, 0.0, yaw), (x, y, 0.0)).as_matrix()

    def T_world_optical_at(self, t_ns: int) -> F64Array:
        """Optical-frame pose in odom at ``t_ns`` (``T_odom_base @ T_base_optical``)."""
        out: F64Array = self.T_world_base_at(t_ns) @ self.T_base_optical
        return out
