"""``overhead_camera``: the fixed camera of ``aruco_box_camera_world`` (gz-sensors + bridge).

Publishes ``/overhead_camera/image_raw`` (rgb8 640x480, 30 Hz, frame_id
``overhead_camera_optical_frame``: the optical frame, as real camera drivers stamp images)
and ``/overhead_camera/camera_info`` (HFOV 1.047 rad, d = 0): topics, size, FOV and rate
come from the world's camera entry. With ``publish_static_frames`` (true) it also latches the
camera's static frames on ``/tf_static`` as ``static_aruco_detector.launch.py`` does:
``odom -> overhead_camera`` (2, 2, 2, rpy 0 1.5708 0) and ``overhead_camera ->
overhead_camera_optical_frame`` (rpy -1.5708 0 -1.5708) - every static transform of the
world whose child frame starts with the camera's frame id.

The image is rendered from exactly those frames, ``T_odom_optical = T_odom_camera @
T_camera_optical`` (the optical rotation from the world's static transform when it has one,
else the exact ``Rz(-pi/2) Rx(-pi/2)``), so a detector's ``static_aruco_box`` composes back
to the true marker pose.

Parameters: ``world`` (aruco_box_camera_world), ``camera_name`` (overhead_camera),
``publish_static_frames`` (true), and the common ``noise_sigma``, ``seed``, ``supersample``,
``lazy`` (see :class:`SimulatedCamera`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from posekit.geometry import Transform
from posekit.runtime.parameters import declare_value
from posekit.tf2_ros import StaticTransformBroadcaster
from posekit.time import stamp_from_ns
from posekit.vision.camera import T_CAMERA_FRAME_OPTICAL, PinholeCamera
from posekit.vision.nodes._camera import F64Array, SimulatedCamera
from posekit.vision.nodes._common import transform_msg

__all__ = ["OverheadCameraNode"]


class OverheadCameraNode(SimulatedCamera):
    """A fixed camera of the world (see the module docstring)."""

    def __init__(self, node_name: str = "overhead_camera", **kwargs: Any) -> None:
        super().__init__(node_name, "aruco_box_camera_world", **kwargs)
        name = str(declare_value(self, "camera_name", "overhead_camera"))
        publish_statics = bool(declare_value(self, "publish_static_frames", True))
        specs = {c.name: c for c in self.world.cameras}
        if name not in specs:
            raise ValueError(
                f"world '{self.world.name}' has no camera {name!r}; cameras: {sorted(specs)}"
            )
        spec = specs[name]
        frame = spec.frame_id or spec.name
        self._statics = [s for s in self.world.static_transforms if s.child.startswith(frame)]
        T_camera_optical = np.array(T_CAMERA_FRAME_OPTICAL)
        header_frame = frame  # a world without an optical frame: the body frame
        for s in self._statics:
            if s.parent == frame and s.child.endswith("optical_frame"):
                T_camera_optical = Transform.from_xyz_rpy(s.xyz, s.rpy).as_matrix()
                header_frame = s.child
        #: Pose of the optical frame in the world (odom), metres.
        self.T_world_optical: F64Array = spec.T_world_camera @ T_camera_optical
        near, far = spec.clip
        camera = PinholeCamera.from_hfov(spec.width, spec.height, spec.horizontal_fov,
                                         near=near, far=far)
        if publish_statics and self._statics:
            self._static_broadcaster = StaticTransformBroadcaster(self)
            stamp = stamp_from_ns(self.get_clock().now_ns())
            self._static_broadcaster.sendTransform(
                [transform_msg(s.parent, s.child, stamp, s.xyz, s.quaternion_xyzw)
                 for s in self._statics]
            )
        self._start(camera, "/" + spec.image_topic.lstrip("/"),
                    "/" + spec.info_topic.lstrip("/"), header_frame, spec.rate_hz)

    def T_world_optical_at(self, t_ns: int) -> F64Array:
        """The (fixed) optical-frame pose in the world."""
        return self.T_world_optical
