"""The lecture's nodes, run from ``examples/`` as they are, on known marker poses.

``examples/dynamic_detector_demo.py``, ``static_aruco_detector.py`` and
``aruco_marker_listener.py`` are loaded from their files (the same loader ``posekit launch``
uses) and run in one simulated-time executor, with the camera topics set the ROS way
(``--ros-args -p``). Only the ArUco detector object is replaced: it reports each marker's
corners as the exact pinhole projection of a marker at a known pose, so the examples' own
``solvePnP``, quaternion conversion, broadcasting, discovery and lookup run on data whose
answer is known. (tests/examples/test_examples.py runs the same nodes on rendered images.)

Oracle: closed-form composition with scipy's Rotation, independent of posekit:
``p_odom = R_odom_cam @ t_cam_marker + t_odom_cam`` and ``R_odom_marker = R_odom_cam *
R(rvec)``; the corners come from OpenCV's ``projectPoints``.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from posekit import rclpy
from posekit.launch.description import resolve_factory
from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.sensor_msgs import CameraInfo, Image
from posekit.rclpy.executors import SimulatedTimeExecutor
from posekit.rclpy.node import Node
from posekit.rclpy.qos import qos_profile_sensor_data
from posekit.tf2_ros import Buffer, StaticTransformBroadcaster, TransformListener

cv2 = pytest.importorskip("cv2")

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
WIDTH, HEIGHT = 320, 240
K = np.array([[500.0, 0.0, 160.0], [0.0, 500.0, 120.0], [0.0, 0.0, 1.0]])
MARKER_SIZE = 0.2  # the examples' default marker_size parameter
# Ground truth: each marker's pose in the camera optical frame (rvec, tvec as solvePnP's).
RVEC_BY_ID = {3: np.array([0.1, -0.2, 0.3]), 7: np.array([-0.4, 0.05, 0.2])}
TVEC_BY_ID = {3: np.array([0.2, 0.1, 1.5]), 7: np.array([-0.3, 0.0, 2.0])}
T_ODOM_CAM = (np.array([0.5, -0.2, 0.3]), Rotation.from_euler("xyz", [-np.pi / 2, 0, -np.pi / 2]))


def example(file: str, cls: str) -> Any:
    """The node class of an example file, loaded as ``posekit launch`` loads it."""
    return resolve_factory(f"{EXAMPLES / file}:{cls}")


class KnownPoseDetector:
    """Stands in for ``cv2.aruco.ArucoDetector``: ``detectMarkers`` returns, for every
    marker of the ground truth, its four corners (TL, TR, BR, BL in the marker's z = 0
    plane, OpenCV's ArUco order) projected through ``K``, in OpenCV's return shapes."""

    def detectMarkers(self, image: np.ndarray) -> tuple[Any, Any, Any]:
        half = MARKER_SIZE / 2
        square = np.array([[-half, half, 0], [half, half, 0], [half, -half, 0],
                           [-half, -half, 0]])
        corners = []
        for marker_id in sorted(RVEC_BY_ID):
            pixels, _ = cv2.projectPoints(square, RVEC_BY_ID[marker_id], TVEC_BY_ID[marker_id],
                                          K, np.zeros(5))
            corners.append(pixels.reshape(1, 4, 2).astype(np.float32))
        ids = np.array([[i] for i in sorted(RVEC_BY_ID)], dtype=np.int32)
        return tuple(corners), ids, ()


class CameraSim(Node):
    """Publishes black images and the camera info at 10 Hz and odom -> camera (static)."""

    def __init__(self) -> None:
        super().__init__("camera_sim")
        self._image_pub = self.create_publisher(Image, "/camera/image", qos_profile_sensor_data)
        self._info_pub = self.create_publisher(CameraInfo, "/camera/info", qos_profile_sensor_data)
        self._static = StaticTransformBroadcaster(self)
        t = TransformStamped()
        t.header.frame_id = "odom"
        t.child_frame_id = "camera_optical_frame"
        tr, q = t.transform.translation, t.transform.rotation
        tr.x, tr.y, tr.z = T_ODOM_CAM[0]
        q.x, q.y, q.z, q.w = T_ODOM_CAM[1].as_quat()
        self._static.sendTransform(t)
        self.create_timer(0.1, self._tick)

    def _tick(self) -> None:
        img = Image(height=HEIGHT, width=WIDTH, encoding="bgr8", step=3 * WIDTH,
                    data=np.zeros(3 * WIDTH * HEIGHT, dtype=np.uint8))
        img.header.stamp = self.get_clock().now().to_msg()
        img.header.frame_id = "camera_optical_frame"
        self._image_pub.publish(img)
        info = CameraInfo(width=WIDTH, height=HEIGHT)
        info.k = K.ravel()
        info.d = np.zeros(5)
        self._info_pub.publish(info)


def expected_marker_in_odom(marker_id: int) -> np.ndarray:
    t_odom_cam, R_odom_cam = T_ODOM_CAM
    return R_odom_cam.apply(TVEC_BY_ID[marker_id]) + t_odom_cam


def test_lecture_nodes_from_examples_find_known_markers(logs) -> None:
    rclpy.init(args=["prog", "--ros-args", "-p", "camera_image_topic:=/camera/image",
                     "-p", "camera_info_topic:=/camera/info"])
    try:
        dynamic = example("dynamic_detector_demo.py", "DynamicDetectorDemo")()
        static = example("static_aruco_detector.py", "StaticArucoDetector")()
        listener = example("aruco_marker_listener.py", "ArucoMarkerListener")()
        dynamic._detector = static._detector = KnownPoseDetector()
        executor = SimulatedTimeExecutor()
        for node in (CameraSim(), dynamic, static, listener):
            executor.add_node(node)
        executor.run_until(3.0)

        assert "Detected markers: [3, 7]" in [r.message for r in logs
                                                if r.name == "dynamic_detector_demo"]
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
        assert static._tf_published
        assert static._image_sub not in list(static.subscriptions)
        assert dynamic._info_sub not in list(dynamic.subscriptions)  # dropped after one info

        # The static detector's transform (the first marker, 3) is latched for a node that
        # starts late; solvePnP on exact float32 corners recovers the pose to ~1e-6.
        late_buffer = Buffer()
        late = rclpy.create_node("late_listener")
        TransformListener(late_buffer, late)
        executor.add_node(late)
        executor.run_until(3.1)
        box = late_buffer.lookup_transform("odom", "static_aruco_box", rclpy.time.Time())
        p, q = box.transform.translation, box.transform.rotation
        assert [p.x, p.y, p.z] == pytest.approx(list(expected_marker_in_odom(3)), abs=1e-5)
        R_expected = T_ODOM_CAM[1] * Rotation.from_rotvec(RVEC_BY_ID[3])
        angle = (Rotation.from_quat([q.x, q.y, q.z, q.w]) * R_expected.inv()).magnitude()
        assert angle < 1e-5
        assert not [r for r in logs if r.severity.name == "ERROR"]
    finally:
        rclpy.shutdown()
