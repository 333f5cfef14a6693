"""The lecture's ``static_aruco_detector.py`` (Coordinate Frames > Static Transforms) on posekit.

The node code is the lecture's, steps 1-8; only the imports differ from the ROS 2 original
(each changed line says what it replaces). It detects the first ArUco marker in the overhead
camera's image, solves PnP for its pose in the camera optical frame (the image's
``header.frame_id``) and publishes it ONCE on ``/tf_static`` as ``static_aruco_box``.

Run it against the simulator (see docs/tutorial.md):

    posekit launch examples/static_aruco_detector.launch.py --until-sim-time 2

Expected output (numbers from seed 0)::

    [INFO] [...] [static_aruco_detector]: Published static TF overhead_camera_optical_frame -> static_aruco_box: t=(-0.000, -0.000, 1.519)
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
from posekit.tf2_ros import StaticTransformBroadcaster  # was: from tf2_ros import ...


class StaticArucoDetector(Node):
    def __init__(self):
        super().__init__("static_aruco_detector")
        self._camera_image_topic = self.declare_parameter(
            "camera_image_topic", "/overhead_camera/image_raw").value
        self._camera_info_topic = self.declare_parameter(
            "camera_info_topic", "/overhead_camera/camera_info").value
        self._marker_size = self.declare_parameter("marker_size", 0.2).value
        dictionary_id = self.declare_parameter("dictionary_id", "DICT_5X5_250").value
        self._child_frame_id = self.declare_parameter(
            "child_frame_id", "static_aruco_box").value

        self._bridge = CvBridge()
        self._detector = cv2.aruco.ArucoDetector(
            cv2.aruco.getPredefinedDictionary(getattr(cv2.aruco, dictionary_id)),
            cv2.aruco.DetectorParameters(),
        )
        self._camera_matrix = None
        self._dist_coeffs = None
        self._tf_published = False

        # Step 1: image pixels, intrinsics and a latched static TF publisher.
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

        # Step 3: the marker in its own frame (TL, TR, BR, BL in the z = 0 plane).
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
        if self._tf_published or self._camera_matrix is None:
            return
        cv_image = self._bridge.imgmsg_to_cv2(msg, desired_encoding="bgr8")

        # Step 4: detect the marker.
        corners, ids, _ = self._detector.detectMarkers(cv_image)
        if ids is None or len(ids) == 0:
            return
        image_points = corners[0].reshape(-1, 2).astype(np.float32)

        # Step 5: solve PnP (pose of the marker in the camera optical frame).
        success, rvec, tvec = cv2.solvePnP(
            self._marker_object_points, image_points, self._camera_matrix,
            self._dist_coeffs, flags=cv2.SOLVEPNP_IPPE_SQUARE,
        )
        if not success:
            return
        tvec = tvec.flatten()
        self._publish_static_tf(msg.header, rvec, tvec)

    def _publish_static_tf(self, image_header, rvec, tvec):
        # Step 6: rvec to a quaternion.
        qx, qy, qz, qw = Rotation.from_rotvec(rvec.flatten()).as_quat()

        # Step 7: publish once as a static TF.
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
        self.get_logger().info(
            f"Published static TF {t.header.frame_id} -> {t.child_frame_id}: "
            f"t=({tvec[0]:.3f}, {tvec[1]:.3f}, {tvec[2]:.3f})"
        )

        # Step 8: one-shot behaviour.
        self._tf_published = True
        self.destroy_subscription(self._image_sub)


def main(args=None):
    rclpy.init(args=args)
    node = StaticArucoDetector()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
