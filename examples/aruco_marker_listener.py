"""The lecture's ``aruco_marker_listener.py`` (Coordinate Frames > Listening for Marker Frames).

The node code is the lecture's, steps 1-3; only the imports differ from the ROS 2 original
(each changed line says what it replaces). Every second it discovers the ``aruco_marker_*``
frames in the TF buffer and logs each one's position in ``odom``.

Run it against the simulator, in one process with the detector (docs/tutorial.md):

    posekit launch examples/dynamic_detector_listener.launch.py --until-sim-time 3

or from a second terminal, against a running simulation (every launch is visible on Zenoh):

    posekit launch dynamic_detector --realtime                # terminal 1
    POSEKIT_TRANSPORT=zenoh python examples/aruco_marker_listener.py   # terminal 2

Expected output (marker 4 sits at (2.0, 0.0, 0.25) in odom)::

    [INFO] [...] [aruco_marker_listener]: aruco_marker_2: x=2.01, y=-0.50, z=0.250 (3 decimals)
    [INFO] [...] [aruco_marker_listener]: aruco_marker_4: x=2.01, y=0.00, z=0.250
    [INFO] [...] [aruco_marker_listener]: aruco_marker_5: x=2.01, y=0.50, z=0.250
"""

import yaml

from posekit import rclpy  # was: import rclpy
from posekit.rclpy.duration import Duration  # was: from rclpy.duration import Duration
from posekit.rclpy.node import Node  # was: from rclpy.node import Node
from posekit.tf2_ros import (  # was: from tf2_ros import ...
    Buffer,
    TransformException,
    TransformListener,
)


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
                    frame,  # "aruco_marker_<id>"
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


def main(args=None):
    rclpy.init(args=args)
    node = ArucoMarkerListener()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
