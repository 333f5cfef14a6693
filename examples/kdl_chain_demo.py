"""The lecture's ``kdl_chain_demo.py`` (Coordinate Frames > KDL Frames) on posekit.

The node code is the lecture's, steps 1-3; only the imports differ from the ROS 2 original
(each changed line says what it replaces; ``posekit.kdl`` is a PyKDL subset). Every second it
looks up ``odom -> overhead_camera_optical_frame`` and ``overhead_camera_optical_frame ->
static_aruco_box`` separately, chains them with KDL and logs the composed pose, which must
equal tf2's direct lookup (``posekit tf echo odom static_aruco_box``).

Run it against the simulator with the static detector (docs/tutorial.md):

    posekit launch examples/kdl_chain_demo.launch.py --until-sim-time 3

Expected output (the marker on top of the box is at (2, 2, 0.5))::

    [INFO] [...] [kdl_chain_demo]: static_aruco_box in odom: pos=(2.000, 2.000, 0.481) ...
"""

import posekit.kdl as PyKDL  # was: import PyKDL
from posekit import rclpy  # was: import rclpy
from posekit.msgs.geometry_msgs import Pose, TransformStamped  # was: from geometry_msgs.msg ...
from posekit.rclpy.duration import Duration  # was: from rclpy.duration import Duration
from posekit.rclpy.node import Node  # was: from rclpy.node import Node
from posekit.tf2_ros import (  # was: from tf2_ros import ...
    Buffer,
    TransformException,
    TransformListener,
)


# Step 1: ROS <-> KDL conversions.
def transform_to_kdl(t: TransformStamped) -> PyKDL.Frame:
    p, q = t.transform.translation, t.transform.rotation
    return PyKDL.Frame(
        PyKDL.Rotation.Quaternion(q.x, q.y, q.z, q.w),
        PyKDL.Vector(p.x, p.y, p.z),
    )


def kdl_to_pose(frame: PyKDL.Frame) -> Pose:
    pose = Pose()
    pose.position.x, pose.position.y, pose.position.z = (
        frame.p.x(), frame.p.y(), frame.p.z()
    )
    qx, qy, qz, qw = frame.M.GetQuaternion()
    pose.orientation.x, pose.orientation.y = qx, qy
    pose.orientation.z, pose.orientation.w = qz, qw
    return pose


class KdlChainDemo(Node):
    def __init__(self):
        super().__init__("kdl_chain_demo")
        self._target = self.declare_parameter("target_frame", "odom").value
        self._middle = self.declare_parameter(
            "intermediate_frame", "overhead_camera_optical_frame").value
        self._source = self.declare_parameter("source_frame", "static_aruco_box").value
        self._tf_buffer = Buffer()
        self._tf_listener = TransformListener(self._tf_buffer, self)
        self._timer = self.create_timer(1.0, self._timer_callback)

    def _timer_callback(self):
        # Step 2: look up each hop separately.
        try:
            t_target_middle = self._tf_buffer.lookup_transform(
                self._target, self._middle, rclpy.time.Time(),
                timeout=Duration(seconds=0.1),
            )  # odom -> overhead_camera_optical_frame
            t_middle_source = self._tf_buffer.lookup_transform(
                self._middle, self._source, rclpy.time.Time(),
                timeout=Duration(seconds=0.1),
            )  # overhead_camera_optical_frame -> static_aruco_box
        except TransformException as e:
            self.get_logger().warn(f"TF lookup failed: {e}")
            return

        # Step 3: compose with KDL, then convert back.
        kdl_target_middle = transform_to_kdl(t_target_middle)
        kdl_middle_source = transform_to_kdl(t_middle_source)
        kdl_target_source = kdl_target_middle * kdl_middle_source  # chain!
        pose_in_target = kdl_to_pose(kdl_target_source)

        p, o = pose_in_target.position, pose_in_target.orientation
        self.get_logger().info(
            f"{self._source} in {self._target}: pos=({p.x:.3f}, {p.y:.3f}, {p.z:.3f}) "
            f"quat=({o.x:.3f}, {o.y:.3f}, {o.z:.3f}, {o.w:.3f})"
        )


def main(args=None):
    rclpy.init(args=args)
    node = KdlChainDemo()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
