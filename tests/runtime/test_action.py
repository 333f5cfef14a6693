"""rclpy.action on the in-process bus: goals, feedback, cancel, results, status, errors.

Oracles: rcl_action's documented goal state machine and cancel rules (the status sequence
and CancelGoal return codes a client observes), rclpy's documented defaults (accept every
goal, reject every cancel, abort a goal the execute callback left active), and arithmetic
of the test's own execute callback (feedback counts down by one per 0.1 s of sim time).
Real-process Zenoh tests are in tests/runtime/test_action_zenoh.py.
"""

from __future__ import annotations

import threading
from collections.abc import Iterator
from typing import Any

import pytest

from posekit.msgs.action_msgs import CancelGoal, GoalInfo, GoalStatus, GoalStatusArray
from posekit.msgs.posekit_interfaces import NavigateToPose
from posekit.msgs.unique_identifier_msgs import UUID
from posekit.runtime.action import (
    ActionClient,
    ActionServer,
    CancelResponse,
    GoalResponse,
    InvalidGoalTransitionError,
    ServerGoalHandle,
    action_topic_names,
    get_action_client_names_and_types_by_node,
    get_action_names_and_types,
    get_action_server_names_and_types_by_node,
    qos_profile_action_status_default,
)
from posekit.runtime.context import Context
from posekit.runtime.executors import MultiThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.qos import DurabilityPolicy, QoSProfile
from posekit.runtime.sim_executor import SimulatedTimeExecutor
from posekit.runtime.task import Future

S = GoalStatus


def goal_of(distance: float) -> Any:
    goal = NavigateToPose.Goal()
    goal.pose.pose.position.x = distance
    return goal


class Countdown:
    """An action server whose goal is a distance it 'drives' 1 m per 0.1 s of node time,
    with feedback of the distance left; it honours cancel requests at each step."""

    def __init__(self, node: Node, **options: Any) -> None:
        self.node = node
        self.server = ActionServer(node, NavigateToPose, "navigate", self.execute, **options)

    def _tick(self) -> Future:
        done = Future()

        def fire() -> None:
            self.node.destroy_timer(timer)
            done.set_result(None)

        timer = self.node.create_timer(0.1, fire)
        return done

    async def execute(self, goal_handle: ServerGoalHandle) -> Any:
        left = goal_handle.request.pose.pose.position.x
        while left > 0:
            if goal_handle.is_cancel_requested:
                goal_handle.canceled()
                return NavigateToPose.Result(distance_remaining=left)
            goal_handle.publish_feedback(NavigateToPose.Feedback(distance_remaining=left))
            await self._tick()
            left -= 1.0
        goal_handle.succeed()
        return NavigateToPose.Result(distance_remaining=0.0)


class Rig:
    def __init__(self, ctx: Context, **server_options: Any) -> None:
        self.executor = SimulatedTimeExecutor(context=ctx, publish_clock=False)
        self.server_node = Node("server", context=ctx)
        self.client_node = Node("client", context=ctx)
        self.executor.add_node(self.server_node)
        self.executor.add_node(self.client_node)
        self.countdown = Countdown(self.server_node, **server_options)
        self.client = ActionClient(self.client_node, NavigateToPose, "navigate")
        self.statuses: list[list[int]] = []
        self.client_node.create_subscription(
            GoalStatusArray, "/navigate/_action/status",
            lambda m: self.statuses.append([s.status for s in m.status_list]),
            QoSProfile(depth=100, durability=DurabilityPolicy.TRANSIENT_LOCAL),  # every one
        )

    def run(self, seconds: float) -> None:
        self.executor.run_for(seconds)

    def send(self, distance: float, feedback: list[float] | None = None) -> Any:
        callback = None if feedback is None else (
            lambda m: feedback.append(m.feedback.distance_remaining))
        future = self.client.send_goal_async(goal_of(distance), feedback_callback=callback)
        self.run(0.01)
        assert future.done()
        return future.result()


@pytest.fixture
def rig(ctx: Context) -> Iterator[Rig]:
    r = Rig(ctx, cancel_callback=lambda _h: CancelResponse.ACCEPT)
    yield r
    r.executor.shutdown()


def test_names_follow_ros2s_action_mapping(rig: Rig, ctx: Context) -> None:
    topics = dict(ctx.transport().get_topic_names_and_types())
    assert topics["/navigate/_action/feedback"] == [
        "posekit_interfaces/action/NavigateToPose_FeedbackMessage"]
    assert topics["/navigate/_action/status"] == ["action_msgs/msg/GoalStatusArray"]
    services = dict(rig.server_node.get_service_names_and_types())
    assert services["/navigate/_action/send_goal"] == [
        "posekit_interfaces/action/NavigateToPose_SendGoal"]
    assert services["/navigate/_action/get_result"] == [
        "posekit_interfaces/action/NavigateToPose_GetResult"]
    assert services["/navigate/_action/cancel_goal"] == ["action_msgs/srv/CancelGoal"]
    assert action_topic_names("/a")["status"] == "/a/_action/status"
    # rclpy's qos_profile_action_status_default
    assert (qos_profile_action_status_default.depth,
            qos_profile_action_status_default.durability) == (1, DurabilityPolicy.TRANSIENT_LOCAL)
    assert rig.client.server_is_ready()
    assert rig.client.wait_for_server(timeout_sec=1.0)
    # rclpy.action.graph
    nav = "posekit_interfaces/action/NavigateToPose"
    assert get_action_names_and_types(rig.client_node) == [("/navigate", [nav])]
    assert get_action_server_names_and_types_by_node(rig.client_node, "server", "/") == [
        ("/navigate", [nav])]
    assert get_action_server_names_and_types_by_node(rig.client_node, "client", "/") == []
    assert get_action_client_names_and_types_by_node(rig.client_node, "client", "/") == [
        ("/navigate", [nav])]


def test_goal_with_feedback_reaches_its_result(rig: Rig) -> None:
    feedback: list[float] = []
    rig.run(0.5)
    handle = rig.send(3.0, feedback)
    assert handle.accepted
    assert (handle.stamp.sec, handle.stamp.nanosec) == (0, 500_000_000)  # sim time of accept
    result = handle.get_result_async()
    rig.run(1.0)
    assert result.done()
    assert result.result().status == S.STATUS_SUCCEEDED
    assert result.result().result.distance_remaining == 0.0
    assert feedback == [3.0, 2.0, 1.0]
    assert handle.status == S.STATUS_SUCCEEDED
    # the status topic went ACCEPTED -> EXECUTING -> SUCCEEDED
    assert rig.statuses == [[S.STATUS_ACCEPTED], [S.STATUS_EXECUTING], [S.STATUS_SUCCEEDED]]


def test_cancel_stops_the_goal_with_a_canceled_result(rig: Rig) -> None:
    feedback: list[float] = []
    handle = rig.send(10.0, feedback)
    rig.run(0.25)
    cancel = handle.cancel_goal_async()
    result = handle.get_result_async()
    rig.run(0.5)
    response = cancel.result()
    assert response.return_code == CancelGoal.Response.ERROR_NONE
    assert [bytes(g.goal_id.uuid) for g in response.goals_canceling] == [
        bytes(handle.goal_id.uuid)]
    assert result.result().status == S.STATUS_CANCELED
    # cancelled during the third step: 10, 9, 8 driven, the rest left
    assert feedback == [10.0, 9.0, 8.0]
    assert result.result().result.distance_remaining == 7.0
    assert rig.statuses[-2:] == [[S.STATUS_CANCELING], [S.STATUS_CANCELED]]


def test_cancel_return_codes(rig: Rig) -> None:
    done = rig.send(1.0)
    rig.run(0.5)
    assert done.status == S.STATUS_SUCCEEDED  # from the status topic
    terminated = done.cancel_goal_async()
    unknown = rig.client._cancel.call_async(CancelGoal.Request(
        goal_info=GoalInfo(goal_id=UUID(uuid=bytearray(range(1, 17))))))  # type: ignore[arg-type]
    rig.run(0.05)
    assert terminated.result().return_code == CancelGoal.Response.ERROR_GOAL_TERMINATED
    assert unknown.result().return_code == CancelGoal.Response.ERROR_UNKNOWN_GOAL_ID
    # a zero goal id with a zero stamp cancels every active goal
    first, second = rig.send(20.0), rig.send(20.0)
    everything = rig.client._cancel.call_async(CancelGoal.Request())
    results = [first.get_result_async(), second.get_result_async()]
    rig.run(0.5)
    assert everything.result().return_code == CancelGoal.Response.ERROR_NONE
    assert len(everything.result().goals_canceling) == 2
    assert [r.result().status for r in results] == [S.STATUS_CANCELED] * 2


def test_default_callbacks_accept_goals_and_reject_cancels(ctx: Context) -> None:
    rig = Rig(ctx)  # rclpy's defaults
    handle = rig.send(2.0)
    cancel = handle.cancel_goal_async()
    result = handle.get_result_async()
    rig.run(0.5)
    assert handle.accepted
    assert cancel.result().return_code == CancelGoal.Response.ERROR_REJECTED
    assert cancel.result().goals_canceling == []
    assert result.result().status == S.STATUS_SUCCEEDED


def test_rejected_goal_and_unknown_result(ctx: Context) -> None:
    rig = Rig(ctx, goal_callback=lambda goal: (
        GoalResponse.ACCEPT if goal.pose.pose.position.x < 5 else GoalResponse.REJECT))
    handle = rig.send(9.0)
    assert not handle.accepted
    # asking for the result of a goal the server never accepted: STATUS_UNKNOWN at once
    result = handle.get_result_async()
    rig.run(0.01)
    assert result.result().status == S.STATUS_UNKNOWN
    assert rig.send(1.0).accepted
    assert len(rig.countdown.server._goals) == 1  # the rejected goal was never tracked


def test_goal_left_active_is_aborted_with_a_warning(ctx: Context, logs: list[Any]) -> None:
    executor = SimulatedTimeExecutor(context=ctx, publish_clock=False)
    node = Node("lazy", context=ctx)
    executor.add_node(node)
    ActionServer(node, NavigateToPose, "lazy", lambda handle: NavigateToPose.Result())
    client = ActionClient(node, NavigateToPose, "lazy")
    sent = client.send_goal_async(goal_of(1.0))
    executor.run_for(0.01)
    result = sent.result().get_result_async()
    executor.run_for(0.01)
    assert result.result().status == S.STATUS_ABORTED
    assert any("Goal state not set, assuming aborted" in r.message for r in logs)


def test_invalid_transitions_raise(ctx: Context) -> None:
    executor = SimulatedTimeExecutor(context=ctx, publish_clock=False)
    node = Node("strict", context=ctx)
    executor.add_node(node)
    errors: list[str] = []

    def execute(handle: ServerGoalHandle) -> Any:
        for wrong in (handle.canceled, handle.execute):
            try:
                wrong()
            except InvalidGoalTransitionError as exc:
                errors.append(str(exc).split(" in state ")[1])
        handle.succeed()
        return NavigateToPose.Result()

    ActionServer(node, NavigateToPose, "strict", execute)
    client = ActionClient(node, NavigateToPose, "strict")
    sent = client.send_goal_async(goal_of(1.0))
    executor.run_for(0.02)
    result = sent.result().get_result_async()
    executor.run_for(0.02)
    assert errors == ["EXECUTING", "EXECUTING"]
    assert result.result().status == S.STATUS_SUCCEEDED


def test_blocking_send_goal_with_a_multithreaded_executor(ctx: Context) -> None:
    node = Node("mt", context=ctx)
    executor = MultiThreadedExecutor(context=ctx)
    executor.add_node(node)
    server_node = Node("mt_server", context=ctx)
    executor.add_node(server_node)

    def execute(handle: ServerGoalHandle) -> Any:
        handle.publish_feedback(NavigateToPose.Feedback(distance_remaining=0.5))
        handle.succeed()
        return NavigateToPose.Result(distance_remaining=0.25)

    ActionServer(server_node, NavigateToPose, "blocking", execute)
    client = ActionClient(node, NavigateToPose, "blocking")
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    try:
        assert client.wait_for_server(timeout_sec=5)
        response = client.send_goal(goal_of(1.0))
        assert response.status == S.STATUS_SUCCEEDED
        assert response.result.distance_remaining == 0.25
    finally:
        ctx.shutdown()
        thread.join(5)


def test_send_goal_checks_the_goal_type(rig: Rig) -> None:
    with pytest.raises(TypeError, match="NavigateToPose_Goal"):
        rig.client.send_goal_async(NavigateToPose.Result())
