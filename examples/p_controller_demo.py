"""The lecture's go-to-goal P controller (Mobile Robot Control > Proportional Controller),
written the way ``p_controller_demo.py`` of ``robot_control_demo`` is: an rclpy node with
only the imports pointing at posekit (each changed line says what it replaces).

Control law (the lecture's): while the robot is farther than ``goal_tolerance`` from the
goal, ``v = k_rho * rho`` and ``omega = k_alpha * alpha`` with ``rho`` the distance and
``alpha`` the heading error towards the goal; then it turns in place to ``goal_yaw`` with
``omega = k_yaw * (goal_yaw - yaw)``. Commands are clamped to 0.5 m/s and 1.0 rad/s and sent
as ``geometry_msgs/TwistStamped`` on ``cmd_vel`` at 20 Hz, from ``odometry/filtered``.

Run it against the simulator (see docs/tutorial.md):

    posekit launch examples/p_controller_demo.launch.py --until-sim-time 40

Expected output (seed 0; the goal is (5, 5, pi/2), reached after about 25 s)::

    [INFO] [...] [p_controller_demo]: Goal reached: x=4.95, y=4.96, yaw=1.54
"""

import math

from posekit import rclpy  # was: import rclpy
from posekit.msgs.geometry_msgs import TwistStamped  # was: from geometry_msgs.msg import ...
from posekit.msgs.nav_msgs import Odometry  # was: from nav_msgs.msg import Odometry
from posekit.rclpy.node import Node  # was: from rclpy.node import Node

MAX_LINEAR = 0.5  # m/s
MAX_ANGULAR = 1.0  # rad/s


def wrap(angle):
    return math.atan2(math.sin(angle), math.cos(angle))


def clamp(value, limit):
    return max(-limit, min(limit, value))


class PControllerDemo(Node):
    def __init__(self):
        super().__init__("p_controller_demo")
        self.k_rho = self.declare_parameter("k_rho", 0.4).value
        self.k_alpha = self.declare_parameter("k_alpha", 0.8).value
        self.k_yaw = self.declare_parameter("k_yaw", 0.8).value
        self.goal_tolerance = self.declare_parameter("goal_tolerance", 0.10).value
        self.yaw_tolerance = self.declare_parameter("yaw_tolerance", 0.05).value
        self.goal_x = self.declare_parameter("goal_x", 5.0).value
        self.goal_y = self.declare_parameter("goal_y", 5.0).value
        self.goal_yaw = self.declare_parameter("goal_yaw", math.pi / 2).value
        self.pose = None
        self.goal_reached = False
        self.cmd_pub = self.create_publisher(TwistStamped, "cmd_vel", 10)
        self.create_subscription(Odometry, "odometry/filtered", self.odom_callback, 10)
        self.create_timer(0.05, self.control_loop)  # 20 Hz

    def odom_callback(self, msg: Odometry):
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
        self.pose = (p.x, p.y, yaw)

    def control_loop(self):
        if self.pose is None:
            return
        x, y, yaw = self.pose
        e_x, e_y = self.goal_x - x, self.goal_y - y
        rho = math.hypot(e_x, e_y)
        v = omega = 0.0
        if self.goal_reached:
            pass
        elif rho > self.goal_tolerance:
            alpha = wrap(math.atan2(e_y, e_x) - yaw)  # e_theta = theta_g - theta_r
            v = clamp(self.k_rho * rho, MAX_LINEAR)  # v = K_pv * sqrt(e_x^2 + e_y^2)
            omega = clamp(self.k_alpha * alpha, MAX_ANGULAR)  # omega = K_pw * e_theta
        elif abs(wrap(self.goal_yaw - yaw)) >= self.yaw_tolerance:
            omega = clamp(self.k_yaw * wrap(self.goal_yaw - yaw), MAX_ANGULAR)
        else:
            self.goal_reached = True
            self.get_logger().info(f"Goal reached: x={x:.2f}, y={y:.2f}, yaw={yaw:.2f}")
        cmd = TwistStamped()
        cmd.header.stamp = self.get_clock().now().to_msg()
        cmd.header.frame_id = "base_link"
        cmd.twist.linear.x = v
        cmd.twist.angular.z = omega
        self.cmd_pub.publish(cmd)


def main(args=None):
    rclpy.init(args=args)
    node = PControllerDemo()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
