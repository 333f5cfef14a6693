"""The lecture's random mover (Mobile Robot Control > Odometry, ``random_mover`` of
``robot_control_demo``): an rclpy node with only the imports pointing at posekit (each
changed line says what it replaces).

At 2 Hz it sends a random ``geometry_msgs/TwistStamped`` on ``cmd_vel`` (``linear.x`` in
[-0.5, 0.5] m/s, ``angular.z`` in [-1.0, 1.0] rad/s) and logs the ``odometry/filtered`` pose
once a second.

Run it against the simulator (see docs/tutorial.md):

    posekit launch examples/random_mover_demo.launch.py --until-sim-time 10

Expected output (random: the numbers differ run to run)::

    [INFO] [...] [random_mover_demo]: Odom: x=0.12, y=-0.03, yaw=0.41
"""

import math
import random

from posekit import rclpy  # was: import rclpy
from posekit.msgs.geometry_msgs import TwistStamped  # was: from geometry_msgs.msg import ...
from posekit.msgs.nav_msgs import Odometry  # was: from nav_msgs.msg import Odometry
from posekit.rclpy.node import Node  # was: from rclpy.node import Node


class RandomMoverDemo(Node):
    def __init__(self):
        super().__init__("random_mover_demo")
        self.cmd_pub = self.create_publisher(TwistStamped, "cmd_vel", 10)
        self.create_subscription(Odometry, "odometry/filtered", self.odom_callback, 10)
        self.create_timer(0.5, self.move)  # 2 Hz
        self.last_log = None

    def move(self):
        cmd = TwistStamped()
        cmd.header.stamp = self.get_clock().now().to_msg()
        cmd.header.frame_id = "base_link"
        cmd.twist.linear.x = random.uniform(-0.5, 0.5)
        cmd.twist.angular.z = random.uniform(-1.0, 1.0)
        self.cmd_pub.publish(cmd)

    def odom_callback(self, msg: Odometry):
        now = self.get_clock().now()
        if self.last_log is not None and (now - self.last_log).nanoseconds < 1_000_000_000:
            return
        self.last_log = now
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
        self.get_logger().info(f"Odom: x={p.x:.2f}, y={p.y:.2f}, yaw={yaw:.2f}")


def main(args=None):
    rclpy.init(args=args)
    node = RandomMoverDemo()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
