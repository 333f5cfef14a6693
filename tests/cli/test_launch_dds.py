"""``posekit launch empty_world --transport dds --realtime`` as the simulator for real ROS 2 code.

Oracle: a real rclpy controller (ROS 2 Jazzy on Fast DDS, imports unchanged, ``use_sim_time``)
that only sees posekit through DDS: it drives to a goal on ``odometry/filtered`` and
``cmd_vel``, its own clock follows posekit's ``/clock``, and the simulator's ground truth it
receives says where the robot really is.
"""

from __future__ import annotations

import json
import math
import sys
import textwrap

import pytest

from _support.dds import free_domain, posekit_env
from _support.procs import Proc
from _support.ros2 import ros2_env, ros2_python

pytestmark = pytest.mark.slow

GOAL = (1.0, 0.5)

CONTROLLER = textwrap.dedent("""
    import json, math, sys, time
    import rclpy
    from rclpy.node import Node
    from rclpy.parameter import Parameter
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from geometry_msgs.msg import TwistStamped
    from nav_msgs.msg import Odometry
    from rosgraph_msgs.msg import Clock

    def yaw_of(q):
        return math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))

    class GoToGoal(Node):
        def __init__(self, goal):
            super().__init__("ros_controller", parameter_overrides=[
                Parameter("use_sim_time", Parameter.Type.BOOL, True)])
            self.goal, self.odom, self.truth, self.clock = goal, None, None, []
            self.reached = None
            self.create_subscription(Odometry, "odometry/filtered", self.on_odom, 10)
            self.create_subscription(Odometry, "ground_truth/odom", self.on_truth, 10)
            self.create_subscription(Clock, "/clock", self.on_clock, QoSProfile(
                depth=10, reliability=ReliabilityPolicy.BEST_EFFORT))
            self.cmd = self.create_publisher(TwistStamped, "cmd_vel", 10)
            self.create_timer(0.1, self.step)  # on the simulation's clock

        def on_odom(self, msg):
            self.odom = msg.pose.pose

        def on_truth(self, msg):
            self.truth = msg.pose.pose

        def on_clock(self, msg):
            now = self.get_clock().now().nanoseconds
            self.clock.append((msg.clock.sec + msg.clock.nanosec * 1e-9, now * 1e-9))

        def step(self):
            if self.odom is None or self.reached is not None:
                return
            p = self.odom.position
            dx, dy = self.goal[0] - p.x, self.goal[1] - p.y
            dist = math.hypot(dx, dy)
            cmd = TwistStamped()
            cmd.header.stamp = self.get_clock().now().to_msg()
            cmd.header.frame_id = "base_link"
            if dist < 0.08:
                self.reached = self.get_clock().now().nanoseconds * 1e-9
            else:
                err = math.atan2(dy, dx) - yaw_of(self.odom.orientation)
                err = math.atan2(math.sin(err), math.cos(err))
                cmd.twist.angular.z = max(-1.5, min(1.5, 2.0 * err))
                if abs(err) < 0.4:
                    cmd.twist.linear.x = min(0.4, 0.8 * dist)
            self.cmd.publish(cmd)

    rclpy.init()
    node = GoToGoal((float(sys.argv[1]), float(sys.argv[2])))
    deadline = time.monotonic() + float(sys.argv[3])
    while time.monotonic() < deadline and node.reached is None:
        rclpy.spin_once(node, timeout_sec=0.05)
    stop = time.monotonic() + 1.0
    while time.monotonic() < stop:  # let the truth settle after the stop command
        rclpy.spin_once(node, timeout_sec=0.05)
    t = node.truth.position if node.truth else None
    print(json.dumps({
        "reached": node.reached,
        "truth": [t.x, t.y] if t else None,
        "clock": node.clock[-20:],
        "wall": time.time(),
    }), flush=True)
    rclpy.shutdown()
""")


def test_real_rclpy_controller_drives_the_simulated_rosbot_to_a_goal() -> None:
    domain = free_domain()
    sim = Proc([sys.executable, "-m", "posekit.cli.main", "launch", "empty_world",
                "--transport", "dds", "--realtime", "--until-sim-time", "60"],
               env=posekit_env(domain))
    controller = Proc([str(ros2_python()), "-c", CONTROLLER, str(GOAL[0]), str(GOAL[1]), "40"],
                      env=ros2_env(domain))
    try:
        out = controller.finish(60, "the real rclpy controller")
    finally:
        controller.kill()
        sim.kill()
    result = json.loads(out.strip().splitlines()[-1])
    assert result["reached"] is not None, f"{out}\n{sim.describe()}"
    # the simulator's ground truth agrees the robot is at the goal
    assert result["truth"] is not None
    assert math.dist(result["truth"], GOAL) < 0.2, result
    # use_sim_time: the real node's clock is posekit's /clock (seconds since the run
    # started), not the wall clock, and it follows every /clock message closely
    clock = result["clock"]
    assert len(clock) >= 10
    assert all(0 < sim_s < 120 for sim_s, _ in clock)
    assert result["wall"] > 1e9
    assert all(abs(node_s - sim_s) < 0.25 for sim_s, node_s in clock), clock
    assert [s for s, _ in clock] == sorted(s for s, _ in clock)
    assert result["reached"] < 120
