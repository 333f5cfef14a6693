"""p_controller node: course parameters, control law on cmd_vel, goal_reached + log, goal_pose."""

from __future__ import annotations

import math

import pytest

from posekit.msgs.geometry_msgs import PoseStamped, TwistStamped
from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.std_msgs import Bool
from posekit.robot._msgutil import yaw_quaternion
from posekit.robot.nodes import PControllerNode
from posekit.runtime.node import Node

SIM = {"use_sim_time": True}


class _Plant(Node):
    """Publishes a fixed filtered pose and records what the controller sends."""

    def __init__(self, ctx, pose: tuple[float, float, float]) -> None:
        super().__init__("plant", context=ctx, parameter_overrides=SIM)
        self.pose = pose
        self.cmds: list[TwistStamped] = []
        self.reached: list[bool] = []
        self.odom_pub = self.create_publisher(Odometry, "odometry/filtered", 10)
        self.goal_pub = self.create_publisher(PoseStamped, "goal_pose", 10)
        self.create_subscription(TwistStamped, "cmd_vel", self.cmds.append, 100)
        self.create_subscription(Bool, "goal_reached", lambda m: self.reached.append(m.data), 10)
        self.create_timer(0.05, self._tick)

    def _tick(self) -> None:
        msg = Odometry()
        msg.header.frame_id = "odom"
        msg.pose.pose.position.x, msg.pose.pose.position.y = self.pose[:2]
        msg.pose.pose.orientation = yaw_quaternion(self.pose[2])
        self.odom_pub.publish(msg)


def _start(ctx, executor, pose, **params):
    node = PControllerNode(context=ctx, parameter_overrides={**SIM, **params})
    plant = _Plant(ctx, pose)
    executor.add_node(node)
    executor.add_node(plant)
    return node, plant


def test_defaults_are_the_course_node_defaults(ctx, executor) -> None:
    node, plant = _start(ctx, executor, (0.0, 0.0, 0.0))
    values = {n: node.get_parameter(n).value for n in (
        "k_rho", "k_alpha", "k_yaw", "goal_tolerance", "yaw_tolerance", "goal_x", "goal_y",
        "goal_yaw")}
    assert values == {"k_rho": 0.4, "k_alpha": 0.8, "k_yaw": 0.8, "goal_tolerance": 0.10,
                      "yaw_tolerance": 0.05, "goal_x": 0.0, "goal_y": 0.0, "goal_yaw": 0.0}
    executor.run_until(1.0)
    assert plant.cmds == []  # goal (0, 0, 0) = no goal: nothing published


def test_phase_one_law_on_cmd_vel_at_20_hz(ctx, executor) -> None:
    # Robot at (1, 1) facing -x, goal (4, 5): rho = 5, alpha = wrap(atan2(4, 3) - pi).
    _node, plant = _start(ctx, executor, (1.0, 1.0, math.pi), goal_x=4.0, goal_y=5.0)
    executor.run_until(1.0)
    stamps = [c.header.stamp.sec + 1e-9 * c.header.stamp.nanosec for c in plant.cmds]
    assert stamps == pytest.approx([0.1 + 0.05 * k for k in range(len(stamps))], abs=1e-9)
    alpha = math.atan2(4.0, 3.0) - math.pi
    cmd = plant.cmds[-1].twist
    assert cmd.linear.x == pytest.approx(min(0.4 * 5.0, 0.5))
    assert cmd.angular.z == pytest.approx(max(-1.0, 0.8 * alpha))  # clamped at -1 rad/s
    assert plant.cmds[-1].header.frame_id == "base_link"


def test_goal_reached_publishes_zero_twist_true_and_logs_the_pose(ctx, executor, logs) -> None:
    # Inside the position tolerance (5 cm) and the yaw tolerance (0.03 rad).
    node, plant = _start(
        ctx, executor, (4.96, 5.03, math.pi / 2 - 0.03), goal_x=5.0, goal_y=5.0,
        goal_yaw=math.pi / 2,
    )
    executor.run_until(1.0)
    assert plant.reached == [True]  # once per goal
    assert all(c.twist.linear.x == 0.0 and c.twist.angular.z == 0.0 for c in plant.cmds)
    lines = [r.message for r in logs if r.name == "p_controller" and "Goal reached" in r.message]
    assert lines == ["Goal reached: x=4.96, y=5.03, yaw=1.54"]
    assert node.goal_reached_ns == 100_000_000


def test_phase_two_turns_the_short_way_across_pi(ctx, executor) -> None:
    # At the goal position; yaw 3.0, goal yaw -3.0: the short way is +0.283 rad (through pi).
    _node, plant = _start(ctx, executor, (2.0, 0.0, 3.0), goal_x=2.0, goal_yaw=-3.0)
    executor.run_until(0.5)
    err = 2 * math.pi - 6.0
    cmd = plant.cmds[-1].twist
    assert cmd.linear.x == 0.0
    assert cmd.angular.z == pytest.approx(0.8 * err)
    assert plant.reached == []


def test_goal_pose_topic_sets_a_new_goal_and_bad_goals_are_refused(ctx, executor, logs) -> None:
    node, plant = _start(ctx, executor, (0.0, 0.0, 0.0))
    executor.run_until(0.2)
    goal = PoseStamped()
    goal.header.frame_id = "map"
    goal.pose.position.x = 3.0
    plant.goal_pub.publish(goal)
    executor.run_until(0.4)
    assert plant.cmds == []
    assert any("Ignoring goal_pose in frame 'map'" in r.message for r in logs)
    goal.header.frame_id = "odom"
    plant.goal_pub.publish(goal)
    executor.run_until(0.6)
    assert node.controller.goal == (3.0, 0.0, 0.0)
    assert plant.cmds[-1].twist.linear.x == pytest.approx(0.5)  # clip(0.4 * 3, 0.5)


def test_gains_change_live_through_the_parameter_service(ctx, executor) -> None:
    """The lecture's tip: retune k_rho of the running controller (here through the
    set_parameters service a ``ros2 param set`` uses) and the next command follows it."""
    from posekit.msgs.rcl_interfaces import SetParameters
    from posekit.runtime.parameters import Parameter

    # rho = 0.5 m straight ahead: v = k_rho * 0.5 stays below the 0.5 m/s clamp for k <= 1.
    _node, plant = _start(ctx, executor, (0.0, 0.0, 0.0), goal_x=0.5, goal_y=0.0)
    executor.run_until(0.5)
    assert plant.cmds[-1].twist.linear.x == pytest.approx(0.4 * 0.5)
    client = plant.create_client(SetParameters, "/p_controller/set_parameters")
    request = SetParameters.Request(parameters=[
        Parameter("k_rho", value=1.0).to_parameter_msg(),
        Parameter("goal_tolerance", value=-1.0).to_parameter_msg(),
    ])
    future = client.call_async(request)
    executor.spin_until_future_complete(future, timeout_sec=1.0)
    assert [r.successful for r in future.result().results] == [True, False]
    assert future.result().results[1].reason == "goal_tolerance must be > 0"
    n = len(plant.cmds)
    executor.run_for(0.2)
    assert plant.cmds[n:]  # it kept commanding
    assert all(c.twist.linear.x == pytest.approx(1.0 * 0.5) for c in plant.cmds[n + 1:])
