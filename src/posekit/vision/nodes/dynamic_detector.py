"""``dynamic_detector``: the lecture's ``dynamic_detector_demo.py`` (Dynamic Transforms).

Every image: detect every marker (``cv2.aruco.ArucoDetector``), solve PnP per marker with
``SOLVEPNP_IPPE_SQUARE`` (object points TL, TR, BR, BL), and broadcast
``<parent> -> aruco_marker_<id>`` on ``/tf`` stamped with the **image's** stamp, where
``<parent>`` is ``parent_frame_id`` or the image's frame. Publishes the annotated debug image
``aruco_detection_image`` (bgr8: outlines and ids from ``drawDetectedMarkers``, axes of half
the marker size from ``cv2.drawFrameAxes``) with the image's header.

Parameters (course names and node defaults): ``camera_image_topic`` (/oak/rgb/color),
``camera_info_topic`` (/oak/stereo/camera_info), ``marker_size`` (0.194), ``dictionary_id``
(DICT_5X5_250), ``publish_tf`` (true), ``parent_frame_id`` ("").
posekit additions: ``refine_subpixel`` (false), ``marker_sizes`` ("id:size,..."),
``publish_alternative_tf`` (false: also broadcast the second IPPE solution as
``<alternative_frame_prefix><id>``), ``alternative_frame_prefix`` (``ippe_alt_marker_``: not
``aruco_marker_``, so the listener does not pick the alternatives up),
``ambiguity_warn_ratio`` (0 = off: warn, throttled, when a marker's IPPE ambiguity ratio
exceeds it - the two poses then explain the corners almost equally and the orientation may
flip between frames).

Deviation: the debug image is drawn only while someone subscribes to it (drawing costs about
2 ms per 1280x720 frame); the TF output does not depend on it.

Bad input (image before CameraInfo, unsupported encoding, empty or malformed image) is
logged and skipped; a frame without markers publishes no transform.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from posekit.msgs.image import numpy_to_image
from posekit.msgs.sensor_msgs import Image
from posekit.msgs.std_msgs import Header
from posekit.runtime.parameters import declare_value
from posekit.tf2_ros import TransformBroadcaster
from posekit.vision.detector import MarkerDetection, draw_detections
from posekit.vision.nodes._common import bgr_canvas, transform_msg
from posekit.vision.nodes._detector_base import ArucoDetectorNodeBase

__all__ = ["DynamicDetector"]


class DynamicDetector(ArucoDetectorNodeBase):
    """Per-frame ArUco detection to ``aruco_marker_<id>`` TF frames (see the module doc).

    Attributes (besides the base's): ``last_detections`` (list of
    :class:`~posekit.vision.detector.MarkerDetection` of the last processed image, both IPPE
    solutions and the ambiguity ratio included), ``last_stamp`` (its header stamp),
    ``detection_counts`` (``{marker_id: frames seen}``), ``frames_processed``.
    """

    def __init__(self, node_name: str = "dynamic_detector", **kwargs: Any) -> None:
        super().__init__(node_name, image_topic="/oak/rgb/color",
                         info_topic="/oak/stereo/camera_info", marker_size=0.194, **kwargs)
        self._publish_tf = bool(declare_value(self, "publish_tf", True))
        self._publish_alt = bool(declare_value(self, "publish_alternative_tf", False))
        self._alt_prefix = str(declare_value(self, "alternative_frame_prefix", "ippe_alt_marker_"))
        self._ambiguity_warn = float(declare_value(self, "ambiguity_warn_ratio", 0.0))
        self._debug_image_pub = self.create_publisher(Image, "aruco_detection_image", 10)
        self._tf_broadcaster = TransformBroadcaster(self) if self._publish_tf else None
        self.last_detections: list[MarkerDetection] = []
        self.last_stamp: Any = None
        self.detection_counts: dict[int, int] = {}
        self.frames_processed = 0
        self.get_logger().info(
            f"ArUco detector started: image={self._camera_image_topic}, "
            f"info={self._camera_info_topic}, dict={self._dictionary_id}, "
            f"marker_size={self._marker_size} m"
        )
        self.get_logger().info("Waiting for camera_info...")

    def _image_callback(self, msg: Image) -> None:
        pixels = self._decode(msg)
        if pixels is None:
            return
        detections = self._detect(msg, pixels)
        self.frames_processed += 1
        self.last_detections = detections
        self.last_stamp = msg.header.stamp
        if detections:
            self._broadcast(msg, detections)
            self.get_logger().info(
                f"Detected markers: {sorted(d.marker_id for d in detections)}",
                throttle_duration_sec=1.0,
            )
        if self._debug_image_pub.get_subscription_count():
            self._publish_debug_image(msg, pixels, detections)

    def _broadcast(self, msg: Image, detections: list[MarkerDetection]) -> None:
        parent = self._parent_frame(msg)
        stamp = msg.header.stamp  # image time, not now(): consumers interpolate to it
        transforms = []
        for det in detections:
            self.detection_counts[det.marker_id] = self.detection_counts.get(det.marker_id, 0) + 1
            transforms.append(transform_msg(parent, f"aruco_marker_{det.marker_id}", stamp,
                                            det.translation, det.quaternion_xyzw))
            if self._publish_alt and det.alternative is not None:
                alt = det.alternative
                transforms.append(transform_msg(parent, f"{self._alt_prefix}{det.marker_id}",
                                                stamp, alt.translation, alt.quaternion_xyzw))
            alt_pose = det.alternative
            if alt_pose is not None and 0.0 < self._ambiguity_warn < det.ambiguity_ratio:
                self.get_logger().warn(
                    f"marker {det.marker_id}: IPPE ambiguity {det.ambiguity_ratio:.2f} "
                    f"(errors {det.reprojection_error:.3f} vs "
                    f"{alt_pose.reprojection_error:.3f} px): its orientation may flip",
                    throttle_duration_sec=1.0,
                )
        if self._tf_broadcaster is not None and transforms:
            # One TFMessage per image (tf2_ros would send one per sendTransform call).
            self._tf_broadcaster.sendTransform(transforms)

    def _publish_debug_image(self, msg: Image, pixels: Any,
                             detections: list[MarkerDetection]) -> None:
        assert self.detector is not None
        canvas = bgr_canvas(np.asarray(pixels), str(msg.encoding))
        if detections:
            canvas = draw_detections(canvas, detections, self.detector.camera_matrix,
                                     self.detector.dist_coeffs, axis_ratio=0.5)
        header = Header(stamp=msg.header.stamp, frame_id=msg.header.frame_id)
        self._debug_image_pub.publish(numpy_to_image(canvas, "bgr8", header))
