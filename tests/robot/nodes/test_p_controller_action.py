"""The P controller's navigate_to_pose action in the simulated ROSbot scenario.

Oracles: the simulator's ground truth (``ground_truth/odom``, the robot's true pose) for
arriving at the goal and for standing still after a cancel; the controller's own tolerances
(goal_tolerance 0.10 m); rcl_action's status codes for success, cancel and preemption.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import pytest

import posekit.robot.scenarios  # noqa: F401 - registers the robot's scenarios
from posekit.launch.scenarios import start_scenario
from posekit.msgs.action_msgs import CancelGoal, GoalStatus
from posekit.msgs.geometry_msgs import TwistStamped
from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.posekit_interfaces import NavigateToPose
from posekit.robot._msgutil import yaw_quaternion
from posekit.runtime.action import ActionClient
from posekit.runtime.node import Node

IDLE = {"goal_x": 0.0, "goal_y": 0.0, "goal_yaw": 0.0}  # the controller starts without a goal


class Operator:
    """A client node in the scenario: sends goals, keeps feedback, truth and commands."""

    def __init__(self, run: Any) -> None:
        self.run = run
        self.node = Node("operator", context=run.context)
        run.executor.add_node(self.node)
        self.client = ActionClient(self.node, NavigateToPose, "/navigate_to_pose")
        self.feedback: list[float] = []
        self.truth: list[Odometry] = []
        self.cmds: list[TwistStamped] = []
        self.node.create_subscription(Odometry, "/ground_truth/odom", self.truth.append, 10)
        self.node.create_subscription(TwistStamped, "/cmd_vel", self.cmds.append, 10)

    def send(self, x: float, y: float, yaw: float, frame: str = "odom") -> Any:
        goal = NavigateToPose.Goal()
        goal.pose.header.frame_id = frame
        goal.pose.pose.position.x, goal.pose.pose.position.y = x, y
        goal.pose.pose.orientation = yaw_quaternion(yaw)
        future = self.client.send_goal_async(
            goal, feedback_callback=lambda m: self.feedback.append(m.feedback.distance_remaining))
        self.run_for(0.1)
        return future.result()

    def run_for(self, seconds: float) -> None:
        self.run.executor.run_for(seconds)

    def run_until(self, future: Any, limit_s: float) -> Any:
        waited = 0.0
        while not future.done() and waited < limit_s:
            self.run_for(0.5)
            waited += 0.5
        assert future.done(), f"no result after {limit_s} s of sim time"
        return future.result()

    def true_pose(self) -> tuple[float, float, float]:
        p = self.truth[-1].pose.pose
        q = p.orientation
        yaw = math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))
        return p.position.x, p.position.y, yaw


@pytest.fixture
def operator() -> Iterator[Operator]:
    run = start_scenario("p_controller", IDLE)
    try:
        yield Operator(run)
    finally:
        run.shutdown()


def test_goal_reached_in_simulated_time_with_decreasing_feedback(operator: Operator) -> None:
    handle = operator.send(1.5, 1.0, math.pi / 2)
    assert handle.accepted
    response = operator.run_until(handle.get_result_async(), 60.0)
    assert response.status == GoalStatus.STATUS_SUCCEEDED
    assert response.result.distance_remaining <= 0.10  # goal_tolerance
    x, y, yaw = operator.true_pose()
    assert math.hypot(x - 1.5, y - 1.0) < 0.2  # truth, within tolerance + odometry drift
    assert abs(math.remainder(yaw - math.pi / 2, 2 * math.pi)) < 0.15
    start = math.hypot(1.5, 1.0)
    assert operator.feedback[0] == pytest.approx(start, abs=0.05)
    assert operator.feedback[-1] <= 0.10
    assert len(operator.feedback) > 20  # one per 20 Hz tick while driving


def test_cancel_stops_the_robot(operator: Operator) -> None:
    handle = operator.send(5.0, 5.0, 0.0)
    operator.run_for(3.0)
    assert operator.feedback[-1] < operator.feedback[0] - 0.3  # it was driving there
    cancel = handle.cancel_goal_async()
    result = handle.get_result_async()
    operator.run_for(0.2)
    assert cancel.result().return_code == CancelGoal.Response.ERROR_NONE
    assert result.result().status == GoalStatus.STATUS_CANCELED
    assert result.result().result.distance_remaining > 4.0
    assert operator.cmds[-1].twist.linear.x == 0.0
    assert operator.cmds[-1].twist.angular.z == 0.0
    operator.run_for(1.0)  # no command since: the robot has come to rest
    x0, y0, _ = operator.true_pose()
    operator.run_for(1.0)
    x1, y1, _ = operator.true_pose()
    assert math.hypot(x1 - x0, y1 - y0) < 0.01


def test_new_goal_preempts_and_bad_goals_are_rejected(operator: Operator) -> None:
    first = operator.send(3.0, 0.0, 0.0)
    first_result = first.get_result_async()
    operator.run_for(1.0)
    second = operator.send(0.5, 0.0, 0.0)
    operator.run_for(0.2)
    assert first_result.result().status == GoalStatus.STATUS_ABORTED
    assert second.accepted
    assert not operator.send(1.0, 1.0, 0.0, frame="map").accepted
    assert not operator.send(math.nan, 1.0, 0.0).accepted


def test_without_services_the_controller_runs_without_the_action(ctx: Any) -> None:
    from posekit.robot.nodes import PControllerNode
    from posekit.runtime.bus import InProcessBus

    class TopicsOnly(InProcessBus):  # a transport with topics only (no services)
        supports_services = False

    node = PControllerNode(context=ctx, transport=TopicsOnly())
    assert node.navigate_action is None
    assert node.controller.goal is None  # still a working (idle) controller
