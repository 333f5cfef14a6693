"""``static_aruco_detector``: the lecture's ``static_aruco_detector.py`` (Static Transforms).

Caches ``CameraInfo`` once (then drops that subscription), detects markers in the camera
image with ``cv2.aruco.ArucoDetector``, solves PnP for the first detected marker with
``SOLVEPNP_IPPE_SQUARE`` (object points TL, TR, BR, BL), and publishes ONE transform
``<parent> -> static_aruco_box`` on ``/tf_static`` (latched), stamped with the node clock's
now as the course does; then it drops the image subscription and processes nothing more.

Parameters (course names and node defaults): ``camera_image_topic``
(/overhead_camera/image_raw), ``camera_info_topic`` (/overhead_camera/camera_info),
``marker_size`` (0.1 - the course's node default; its launch file sets 0.2),
``dictionary_id`` (DICT_5X5_250), ``child_frame_id`` (static_aruco_box), ``parent_frame_id``
("" = the image's frame). posekit additions: ``refine_subpixel`` (false), ``marker_sizes``
("id:size,..."), ``marker_id`` (-1 = the first marker found, as the course; else wait for
that id).

Bad input (image before CameraInfo, unsupported encoding, empty image) is logged and
skipped; frames without markers are skipped until one shows a marker.
"""

from __future__ import annotations

from typing import Any

from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.sensor_msgs import Image
from posekit.runtime.parameters import declare_value
from posekit.tf2_ros import StaticTransformBroadcaster
from posekit.time import stamp_from_ns
from posekit.vision.detector import MarkerDetection
from posekit.vision.nodes._common import transform_msg
from posekit.vision.nodes._detector_base import ArucoDetectorNodeBase

__all__ = ["StaticArucoDetector"]


class StaticArucoDetector(ArucoDetectorNodeBase):
    """One-shot ArUco pose to a static TF frame (see the module docstring).

    Attributes (besides the base's): ``tf_published`` (bool), ``published_transform`` (the
    TransformStamped sent), ``detection`` (the :class:`MarkerDetection` it came from, both
    IPPE solutions and the ambiguity ratio included).
    """

    def __init__(self, node_name: str = "static_aruco_detector", **kwargs: Any) -> None:
        super().__init__(node_name, image_topic="/overhead_camera/image_raw",
                         info_topic="/overhead_camera/camera_info", marker_size=0.1, **kwargs)
        self._child_frame_id = str(declare_value(self, "child_frame_id", "static_aruco_box"))
        self._marker_id = int(declare_value(self, "marker_id", -1))
        self._static_tf_broadcaster = StaticTransformBroadcaster(self)
        self.tf_published = False
        self.published_transform: TransformStamped | None = None
        self.detection: MarkerDetection | None = None
        self.get_logger().info(
            f"Static ArUco detector started: image={self._camera_image_topic}, "
            f"info={self._camera_info_topic}, dict={self._dictionary_id}, "
            f"marker_size={self._marker_size} m, child_frame_id={self._child_frame_id}"
        )
        self.get_logger().info("Waiting for camera_info...")

    def _image_callback(self, msg: Image) -> None:
        if self.tf_published:
            return
        pixels = self._decode(msg)
        if pixels is None:
            return
        detections = self._detect(msg, pixels)
        if self._marker_id >= 0:
            detections = [d for d in detections if d.marker_id == self._marker_id]
        if not detections:
            self.get_logger().debug("No marker in this frame; waiting for another.",
                                    throttle_duration_sec=2.0)
            return
        det = detections[0]
        parent = self._parent_frame(msg)
        t = transform_msg(parent, self._child_frame_id, stamp_from_ns(self.get_clock().now_ns()),
                          det.translation, det.quaternion_xyzw)
        self._static_tf_broadcaster.sendTransform(t)
        self.tf_published = True
        self.published_transform = t
        self.detection = det
        p = det.translation
        self.get_logger().info(
            f"Published static TF {parent} -> {self._child_frame_id} (marker id "
            f"{det.marker_id}, t=({p[0]:.3f}, {p[1]:.3f}, {p[2]:.3f}) m, IPPE ambiguity "
            f"{det.ambiguity_ratio:.2f}); halting further detection."
        )
        # One-shot: the transform stays latched on /tf_static.
        self.destroy_subscription(self._image_sub)
        self._image_sub = None
