"""The lecture's node code (static/dynamic ArUco broadcasters, marker listener) running on
posekit with only the imports changed. Marker detection itself (OpenCV) is replaced by a
known pose per image: the point here is the node / tf2_ros code, which is kept verbatim.

Original imports -> posekit imports:
    import rclpy                                -> from posekit import rclpy
    from rclpy.node import Node                 -> from posekit.rclpy.node import Node
    from rclpy.duration import Duration         -> from posekit.rclpy.duration import Duration
    from rclpy.qos import qos_profile_sensor_data -> from posekit.rclpy.qos import ...
    from tf2_ros import ...                     -> from posekit.tf2_ros import ...
    from geometry_msgs.msg import TransformStamped -> from posekit.msgs.geometry_msgs import ...
    from sensor_msgs.msg import Image, CameraInfo  -> from posekit.msgs.sensor_msgs import ...
"""

from __future__ import annotations

import re

import numpy as np
import pytest
import yaml
from scipy.spatial.transform import Rotation

from posekit import rclpy
from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.sensor_msgs import CameraInfo, Image
from posekit.rclpy.duration import Duration
from posekit.rclpy.executors import SimulatedTimeExecutor
from posekit.rclpy.node import Node
from posekit.rclpy.qos import qos_profile_sensor_data
from posekit.tf2_ros import (
    Buffer,
    StaticTransformBroadcaster,
    TransformBroadcaster,
    TransformException,
    TransformListener,
)

# Ground truth used by the fake detector and by the independent expectation below.
RVEC_BY_ID = {3: np.array([[0.1], [-0.2], [0.3]]), 7: np.array([[-0.4], [0.05], [0.2]])}
TVEC_BY_ID = {3: np.array([[0.2], [0.1], [1.5]]), 7: np.array([[-0.3], [0.0], [2.0]])}
T_ODOM_CAM = (np.array([0.5, -0.2, 0.3]), Rotation.from_euler("xyz", [-np.pi / 2, 0, -np.pi / 2]))


class FakeDetector:
    """Stands in for cv2.aruco.ArucoDetector + solvePnP."""

    def detect(self, msg: Image) -> list[tuple[int, np.ndarray, np.ndarray]]:
        # tvec flat (3,): with NumPy >= 2.4 the lecture's ``float(tvec[0])`` raises on
        # OpenCV's (3, 1) arrays ("only 0-dimensional arrays can be converted").
        return [(i, RVEC_BY_ID[i], TVEC_BY_ID[i].ravel()) for i in sorted(RVEC_BY_ID)]


class CameraSim(Node):
    """Publishes images and camera info at 10 Hz and the odom -> camera static transform."""

    def __init__(self) -> None:
        super().__init__("camera_sim")
        self._image_pub = self.create_publisher(Image, "/camera/image", qos_profile_sensor_data)
        self._info_pub = self.create_publisher(CameraInfo, "/camera/info", qos_profile_sensor_data)
        self._static = StaticTransformBroadcaster(self)
        t = TransformStamped()
        t.header.frame_id = "odom"
        t.child_frame_id = "camera_optical_frame"
        t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = (
            T_ODOM_CAM[0])
        q = T_ODOM_CAM[1].as_quat()
        (t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z,
         t.transform.rotation.w) = q
        self._static.sendTransform(t)
        self.create_timer(0.1, self._tick)

    def _tick(self) -> None:
        img = Image(height=4, width=4, encoding="bgr8", step=12,
                    data=np.zeros(48, dtype=np.uint8))
        img.header.stamp = self.get_clock().now().to_msg()
        img.header.frame_id = "camera_optical_frame"
        self._image_pub.publish(img)
        info = CameraInfo()
        info.k = np.array([500.0, 0, 2, 0, 500.0, 2, 0, 0, 1])
        info.d = np.zeros(5)
        self._info_pub.publish(info)


# ----------------------------------------------------------------------------------------
# Lecture: dynamic_detector_demo.py (steps 1, 2, 5, 6, 7 verbatim; detection faked)
class DynamicDetector(Node):
    def __init__(self) -> None:
        super().__init__("dynamic_detector")
        self._camera_image_topic = "/camera/image"
        self._camera_info_topic = "/camera/info"
        self._camera_matrix = None
        self._detector = FakeDetector()
        # Image pixels + intrinsics
        self._image_sub = self.create_subscription(
            Image, self._camera_image_topic, self._image_callback, qos_profile_sensor_data,
        )
        self._info_sub = self.create_subscription(
            CameraInfo, self._camera_info_topic, self._camera_info_callback,
            qos_profile_sensor_data,
        )
        # Annotated debug image (marker outlines + pose axes)
        self._debug_image_pub = self.create_publisher(
            Image, "aruco_detection_image", 10
        )
        # Dynamic TF broadcaster (publishes on /tf, not /tf_static)
        self._tf_broadcaster = TransformBroadcaster(self)

    def _camera_info_callback(self, msg: CameraInfo):
        self._camera_matrix = np.array(msg.k, dtype=np.float64).reshape(3, 3)
        self._dist_coeffs = np.array(msg.d, dtype=np.float64)
        self.destroy_subscription(self._info_sub)

    def _image_callback(self, msg: Image):
        if self._camera_matrix is None:
            return
        for marker_id, rvec, tvec in self._detector.detect(msg):
            self._broadcast_marker_tf(msg.header, int(marker_id), rvec, tvec)
        debug_msg = Image(height=msg.height, width=msg.width, encoding="bgr8", step=msg.step,
                          data=msg.data)
        debug_msg.header = msg.header
        self._debug_image_pub.publish(debug_msg)

    def _broadcast_marker_tf(self, image_header, marker_id, rvec, tvec):
        qx, qy, qz, qw = Rotation.from_rotvec(rvec.flatten()).as_quat()
        t = TransformStamped()
        t.header.stamp = image_header.stamp  # image time, not now()
        t.header.frame_id = image_header.frame_id  # camera optical frame
        t.child_frame_id = f"aruco_marker_{marker_id}"
        t.transform.translation.x = float(tvec[0])
        t.transform.translation.y = float(tvec[1])
        t.transform.translation.z = float(tvec[2])
        t.transform.rotation.x = float(qx)
        t.transform.rotation.y = float(qy)
        t.transform.rotation.z = float(qz)
        t.transform.rotation.w = float(qw)
        self._tf_broadcaster.sendTransform(t)


# Lecture: static_aruco_detector.py (steps 1, 2, 6, 7, 8 verbatim; detection faked)
class StaticArucoDetector(Node):
    def __init__(self) -> None:
        super().__init__("static_aruco_detector")
        self._camera_image_topic = "/camera/image"
        self._camera_info_topic = "/camera/info"
        self._child_frame_id = "static_aruco_box"
        self._camera_matrix = None
        self._tf_published = False
        # Image pixels
        self._image_sub = self.create_subscription(
            Image, self._camera_image_topic, self._image_callback, qos_profile_sensor_data,
        )
        # Intrinsics
        self._info_sub = self.create_subscription(
            CameraInfo, self._camera_info_topic, self._camera_info_callback,
            qos_profile_sensor_data,
        )
        # Broadcaster
        self._static_tf_broadcaster = StaticTransformBroadcaster(self)

    def _camera_info_callback(self, msg: CameraInfo):
        self._camera_matrix = np.array(msg.k, dtype=np.float64).reshape(3, 3)
        self._dist_coeffs = np.array(msg.d, dtype=np.float64)
        self.destroy_subscription(self._info_sub)

    def _image_callback(self, msg: Image):
        if self._camera_matrix is None or self._tf_published:
            return
        image_header = msg.header
        _, rvec, tvec = FakeDetector().detect(msg)[0]
        qx, qy, qz, qw = Rotation.from_rotvec(rvec.flatten()).as_quat()
        t = TransformStamped()
        t.header.stamp = self.get_clock().now().to_msg()
        t.header.frame_id = image_header.frame_id  # camera optical frame
        t.child_frame_id = self._child_frame_id  # "static_aruco_box"
        t.transform.translation.x = float(tvec[0])
        t.transform.translation.y = float(tvec[1])
        t.transform.translation.z = float(tvec[2])
        t.transform.rotation.x = float(qx)
        t.transform.rotation.y = float(qy)
        t.transform.rotation.z = float(qz)
        t.transform.rotation.w = float(qw)
        self._static_tf_broadcaster.sendTransform(t)
        self._tf_published = True
        self.destroy_subscription(self._image_sub)


# Lecture: aruco_marker_listener.py (steps 1-3 verbatim)
class ArucoMarkerListener(Node):
    def __init__(self):
        super().__init__("aruco_marker_listener")
        self._target_frame = "odom"
        self._marker_prefix = "aruco_marker_"
        self._tf_buffer = Buffer()
        self._tf_listener = TransformListener(self._tf_buffer, self)
        self._timer = self.create_timer(1.0, self._timer_callback)

    def _discover_marker_frames(self):
        frames = yaml.safe_load(self._tf_buffer.all_frames_as_yaml()) or {}
        return sorted(
            name for name in frames if name.startswith(self._marker_prefix)
        )

    def _timer_callback(self):
        for frame in self._discover_marker_frames():
            try:
                t = self._tf_buffer.lookup_transform(
                    self._target_frame,  # "odom"
                    frame,  # "aruco_marker_"
                    rclpy.time.Time(),  # latest available
                    timeout=Duration(seconds=0.1),
                )
            except TransformException as e:
                self.get_logger().warn(
                    f"{frame} -> {self._target_frame}: {e}")
                continue
            p = t.transform.translation
            self.get_logger().info(
                f"{frame}: x={p.x:.3f}, y={p.y:.3f}, z={p.z:.3f}")


# ----------------------------------------------------------------------------------------
def expected_marker_in_odom(marker_id: int) -> np.ndarray:
    """Independent composition: p_odom = R_odom_cam @ t_cam_marker + t_odom_cam."""
    t_odom_cam, R_odom_cam = T_ODOM_CAM
    return R_odom_cam.apply(TVEC_BY_ID[marker_id].ravel()) + t_odom_cam


def test_lecture_nodes_run_unchanged(logs) -> None:
    rclpy.init()
    try:
        nodes = [CameraSim(), DynamicDetector(), StaticArucoDetector(), ArucoMarkerListener()]
        executor = SimulatedTimeExecutor()
        for node in nodes:
            executor.add_node(node)
        executor.run_until(3.0)
        listener_lines = [r.message for r in logs if r.name == "aruco_marker_listener"]
        assert len(listener_lines) == 6  # t = 1, 2, 3 s; two markers each
        pattern = re.compile(r"(aruco_marker_\d+): x=(\S+), y=(\S+), z=(\S+)")
        for line in listener_lines:
            m = pattern.fullmatch(line)
            assert m, line
            marker_id = int(m.group(1).rsplit("_", 1)[1])
            got = np.array([float(m.group(2)[:-1]), float(m.group(3)[:-1]), float(m.group(4))])
            assert got == pytest.approx(expected_marker_in_odom(marker_id), abs=1e-3)
        assert [line.split(":")[0] for line in listener_lines[:2]] == [
            "aruco_marker_3", "aruco_marker_7"]
        static = nodes[2]
        assert static._tf_published
        assert static._image_sub not in list(static.subscriptions)
        assert nodes[1]._info_sub not in list(nodes[1].subscriptions)  # dropped after first info
        # The static detector's transform is latched for a node that starts late.
        late_buffer = Buffer()
        late = rclpy.create_node("late_listener")
        TransformListener(late_buffer, late)
        executor.add_node(late)
        executor.run_until(3.1)
        box = late_buffer.lookup_transform("odom", "static_aruco_box", rclpy.time.Time())
        p = box.transform.translation
        assert [p.x, p.y, p.z] == pytest.approx(list(expected_marker_in_odom(3)), abs=1e-12)
        assert not [r for r in logs if r.severity.name == "ERROR"]
    finally:
        rclpy.shutdown()
