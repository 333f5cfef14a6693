"""What the static and dynamic ArUco detector nodes share: the course's parameters, caching
``CameraInfo`` once (then dropping that subscription), and decoding images with every bad
input logged and skipped rather than raised.

Course parameters: ``camera_image_topic``, ``camera_info_topic``, ``marker_size`` (m),
``dictionary_id`` (``DICT_5X5_250``), ``parent_frame_id`` (empty: the image's
``header.frame_id``, which is the camera's optical frame for the simulated cameras as for
real drivers; set it only for a source that stamps images with another frame). posekit additions:
``refine_subpixel`` (false, as the course), ``marker_sizes`` (``"id:size,..."`` per-id
sizes in metres overriding ``marker_size``).
"""

from __future__ import annotations

from typing import Any

from posekit.msgs.sensor_msgs import CameraInfo, Image
from posekit.runtime.node import Node
from posekit.runtime.parameters import declare_value
from posekit.runtime.qos import qos_profile_sensor_data
from posekit.time import stamp_to_ns
from posekit.vision.detector import ArucoMarkerDetector, MarkerDetection
from posekit.vision.nodes._common import (
    ImageRejectedError,
    U8Array,
    camera_matrix_from_info,
    decode_for_detection,
    parse_marker_sizes,
)

__all__ = ["ArucoDetectorNodeBase"]


class ArucoDetectorNodeBase(Node):
    """Base of :class:`StaticArucoDetector` and :class:`DynamicDetector`.

    Attributes: ``detector`` (the :class:`ArucoMarkerDetector`, None until CameraInfo),
    ``images_received``, ``images_rejected`` (``[(stamp_ns, reason)]``).
    """

    def __init__(self, node_name: str, *, image_topic: str, info_topic: str,
                 marker_size: float, **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)
        self._camera_image_topic = str(declare_value(self, "camera_image_topic", image_topic))
        self._camera_info_topic = str(declare_value(self, "camera_info_topic", info_topic))
        self._marker_size = float(declare_value(self, "marker_size", marker_size))
        self._dictionary_id = str(declare_value(self, "dictionary_id", "DICT_5X5_250"))
        self._parent_frame_id = str(declare_value(self, "parent_frame_id", ""))
        self._refine_subpixel = bool(declare_value(self, "refine_subpixel", False))
        self._marker_sizes = parse_marker_sizes(str(declare_value(self, "marker_sizes", "")))
        if not self._marker_size > 0.0:
            raise ValueError(f"marker_size must be > 0 m, got {self._marker_size}")
        # Fail at start-up on a bad dictionary name, not at the first CameraInfo.
        ArucoMarkerDetector(
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            marker_size=self._marker_size, dictionary=self._dictionary_id,
        )
        self.detector: ArucoMarkerDetector | None = None
        self.images_received = 0
        self.images_rejected: list[tuple[int, str]] = []
        self._image_sub: Any = self.create_subscription(
            Image, self._camera_image_topic, self._image_callback, qos_profile_sensor_data
        )
        self._info_sub: Any = self.create_subscription(
            CameraInfo, self._camera_info_topic, self._camera_info_callback,
            qos_profile_sensor_data,
        )

    # ------------------------------------------------------------------ camera info
    def _camera_info_callback(self, msg: CameraInfo) -> None:
        try:
            K, d = camera_matrix_from_info(msg)
        except ValueError as exc:
            self.get_logger().error(f"Ignoring CameraInfo: {exc}", throttle_duration_sec=2.0)
            return  # keep the subscription: a valid one may follow
        self.detector = ArucoMarkerDetector(
            K, d, marker_size=self._marker_size, marker_sizes=self._marker_sizes,
            dictionary=self._dictionary_id, refine_subpixel=self._refine_subpixel,
        )
        self.get_logger().info(
            f"Camera intrinsics received: fx={K[0, 0]:.3f} fy={K[1, 1]:.3f} "
            f"cx={K[0, 2]:.3f} cy={K[1, 2]:.3f}, distortion={d.tolist()}"
        )
        # Intrinsics never change: read them once.
        if self._info_sub is not None:
            self.destroy_subscription(self._info_sub)
            self._info_sub = None

    # ------------------------------------------------------------------ images
    def _reject(self, msg: Image, reason: str) -> None:
        stamp = msg.header.stamp
        self.images_rejected.append((stamp_to_ns(stamp),
                                     reason))
        self.get_logger().error(f"Skipping image: {reason}", throttle_duration_sec=2.0)

    def _decode(self, msg: Image) -> U8Array | None:
        """Pixels for detection, or None (logged) when the image cannot be used."""
        self.images_received += 1
        if self.detector is None:
            self.get_logger().warn("Image received before camera_info; skipping.",
                                   throttle_duration_sec=2.0)
            return None
        try:
            return decode_for_detection(msg)
        except ImageRejectedError as exc:
            self._reject(msg, str(exc))
            return None

    def _detect(self, msg: Image, pixels: U8Array) -> list[MarkerDetection]:
        assert self.detector is not None
        try:
            return self.detector.detect(pixels)
        except ValueError as exc:  # InvalidImageError: shape/dtype the decoder let through
            self._reject(msg, str(exc))
            return []

    def _parent_frame(self, msg: Image) -> str:
        return self._parent_frame_id or str(msg.header.frame_id)

    def _image_callback(self, msg: Image) -> None:
        raise NotImplementedError
