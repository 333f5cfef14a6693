"""The lecture's ``dynamic_detector_demo.py`` (Coordinate Frames > Dynamic Transforms) on posekit.

The node code is the lecture's, steps 1-8; only the imports differ from the ROS 2 original
(each changed line says what it replaces). Every camera image: detect every ArUco marker,
solve PnP per marker, broadcast ``<image frame> -> aruco_marker_<id>`` on ``/tf`` stamped
with the image's stamp, and publish the annotated ``aruco_detection_image``.

Run it against the simulator (see docs/tutorial.md):

    posekit launch examples/dynamic_detector_demo.launch.py --until-sim-time 3

Expected output::

    [INFO] [...] [dynamic_detector_demo]: Detected markers: [2, 4, 5]
"""

import cv2
import numpy as np

from posekit import rclpy  # was: import rclpy
from posekit.cv_bridge import CvBridge  # was: from cv_bridge import CvBridge
from posekit.geometry import Rotation  # was: from scipy.spatial.transform import Rotation
from posekit.msgs.geometry_msgs import TransformStamped  # was: from geometry_msgs.msg import ...
from posekit.msgs.sensor_msgs import CameraInfo, Image  # was: from sensor_msgs.msg import ...
from posekit.rclpy.node import Node  # was: from rclpy.node import Node
from posekit.rclpy.qos import qos_profile_sensor_data  # was: from rclpy.qos import ...
from posekit.tf2_ros import TransformBroadcaster  # was: from tf2_ros import TransformBroadcaster


class DynamicDetectorDemo(Node):
    def __init__(self):
        super().__init__("dynamic_detector_demo")
        self._camera_image_topic = self.declare_parameter(
            "camera_image_topic", "/oak/rgb/color").value
        self._camera_info_topic = self.declare_parameter(
            "camera_info_topic", "/oak/stereo/camera_info").value
        self._marker_size = self.declare_parameter("marker_size", 0.2).value
        dictionary_id = self.declare_parameter("dictionary_id", "DICT_5X5_250").value

        self._bridge = CvBridge()
        self._detector = cv2.aruco.ArucoDetector(
            cv2.aruco.getPredefinedDictionary(getattr(cv2.aruco, dictionary_id)),
            cv2.aruco.DetectorParameters(),
        )
        self._camera_matrix = None
        self._dist_coeffs = None

        # Step 1: image pixels + intrinsics, a debug image and a dynamic TF broadcaster.
        # Image pixels + intrinsics
        self._image_sub = self.create_subscription(
            Image, self._camera_image_topic, self._image_callback, qos_profile_sensor_data)
        self._info_sub = self.create_subscription(
            CameraInfo, self._camera_info_topic, self._camera_info_callback,
            qos_profile_sensor_data)
        # Annotated debug image (marker outlines + pose axes)
        self._debug_image_pub = self.create_publisher(
            Image, "aruco_detection_image", 10
        )
        # Dynamic TF broadcaster (publishes on /tf, not /tf_static)
        self._tf_broadcaster = TransformBroadcaster(self)

        # Step 3: a marker in its own frame (TL, TR, BR, BL in the z = 0 plane).
        half = self._marker_size / 2.0
        self._marker_object_points = np.array(
            [[-half, half, 0.0], [half, half, 0.0], [half, -half, 0.0], [-half, -half, 0.0]],
            dtype=np.float32,
        )

    # Step 2: cache the intrinsics once.
    def _camera_info_callback(self, msg: CameraInfo):
        self._camera_matrix = np.array(msg.k, dtype=np.float64).reshape(3, 3)
        self._dist_coeffs = np.array(msg.d, dtype=np.float64)
        self.destroy_subscription(self._info_sub)

    def _image_callback(self, msg: Image):
        if self._camera_matrix is None:
            return
        cv_image = self._bridge.imgmsg_to_cv2(msg, desired_encoding="bgr8")

        # Step 4: detect all markers in the current frame.
        corners, ids, _ = self._detector.detectMarkers(cv_image)
        if ids is None or len(ids) == 0:
            return  # nothing to do for this frame

        # Step 5: solve PnP for each detected marker.
        for i, marker_id in enumerate(ids.flatten()):
            image_points = corners[i].reshape(-1, 2).astype(np.float32)
            success, rvec, tvec = cv2.solvePnP(
                self._marker_object_points, image_points, self._camera_matrix,
                self._dist_coeffs, flags=cv2.SOLVEPNP_IPPE_SQUARE,
            )
            if not success:
                continue
            self._broadcast_marker_tf(msg.header, int(marker_id), rvec, tvec.flatten())
            # Step 8 (part): a 3D axis triad on each marker.
            cv2.drawFrameAxes(
                cv_image, self._camera_matrix, self._dist_coeffs, rvec, tvec,
                self._marker_size * 0.5,
            )
        self.get_logger().info(
            f"Detected markers: {sorted(int(i) for i in ids.flatten())}",
            throttle_duration_sec=1.0,
        )

        # Step 8: publish an annotated debug image.
        cv2.aruco.drawDetectedMarkers(cv_image, corners, ids)
        debug_msg = self._bridge.cv2_to_imgmsg(cv_image, encoding="bgr8")
        debug_msg.header = msg.header
        self._debug_image_pub.publish(debug_msg)

    def _broadcast_marker_tf(self, image_header, marker_id, rvec, tvec):
        # Step 6: rvec to a quaternion.
        qx, qy, qz, qw = Rotation.from_rotvec(rvec.flatten()).as_quat()

        # Step 7: one TF per marker, every frame.
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


def main(args=None):
    rclpy.init(args=args)
    node = DynamicDetectorDemo()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
