"""Actions between real processes over Zenoh (rmw_zenoh's service and topic wire format).

A server process and a client process (``POSEKIT_TRANSPORT=zenoh``, one fresh loopback
endpoint per test, the first session hosting the router) run a goal with feedback to its
result, then a goal cancelled half-way. Oracle: the server's own arithmetic (feedback counts
down by one per step) and rcl_action's status codes, as in tests/runtime/test_action.py.
"""

from __future__ import annotations

import os
import sys
import textwrap
from pathlib import Path

import pytest

from _support.ports import free_port
from _support.procs import Proc

SERVER = """
from posekit import rclpy
from posekit.rclpy.action import ActionServer, CancelResponse
from posekit.rclpy.executors import SingleThreadedExecutor
from posekit.rclpy.node import Node
from posekit.rclpy.task import Future
from posekit.msgs.posekit_interfaces import NavigateToPose

rclpy.init()
node = Node("countdown_server")

def step():
    done = Future()
    def fire():
        node.destroy_timer(timer)
        done.set_result(None)
    timer = node.create_timer(0.05, fire)
    return done

async def execute(goal_handle):
    left = goal_handle.request.pose.pose.position.x
    while left > 0:
        if goal_handle.is_cancel_requested:
            goal_handle.canceled()
            return NavigateToPose.Result(distance_remaining=left)
        goal_handle.publish_feedback(NavigateToPose.Feedback(distance_remaining=left))
        await step()
        left -= 1.0
    goal_handle.succeed()
    return NavigateToPose.Result(distance_remaining=0.0)

ActionServer(node, NavigateToPose, "countdown", execute,
             cancel_callback=lambda handle: CancelResponse.ACCEPT)
executor = SingleThreadedExecutor()
executor.add_node(node)
print("server ready", flush=True)
executor.spin()
"""

CLIENT = """
from posekit import rclpy
from posekit.rclpy.action import ActionClient
from posekit.rclpy.executors import SingleThreadedExecutor
from posekit.rclpy.node import Node
from posekit.msgs.posekit_interfaces import NavigateToPose

rclpy.init()
node = Node("countdown_client")
executor = SingleThreadedExecutor()
executor.add_node(node)
client = ActionClient(node, NavigateToPose, "countdown")
print("server found", client.wait_for_server(timeout_sec=20), flush=True)

def goal(distance):
    g = NavigateToPose.Goal()
    g.pose.pose.position.x = distance
    return g

feedback = []
sent = client.send_goal_async(goal(3.0), feedback_callback=lambda m: feedback.append(
    m.feedback.distance_remaining))
executor.spin_until_future_complete(sent, timeout_sec=20)
handle = sent.result()
print("accepted", handle.accepted, flush=True)
result = handle.get_result_async()
executor.spin_until_future_complete(result, timeout_sec=20)
print("result", result.result().status, result.result().result.distance_remaining, flush=True)
print("feedback", feedback, flush=True)

feedback.clear()
sent = client.send_goal_async(goal(1000.0), feedback_callback=lambda m: feedback.append(
    m.feedback.distance_remaining))
executor.spin_until_future_complete(sent, timeout_sec=20)
handle = sent.result()
while len(feedback) < 3:
    executor.spin_once(timeout_sec=1.0)
cancel = handle.cancel_goal_async()
executor.spin_until_future_complete(cancel, timeout_sec=20)
print("cancel", cancel.result().return_code, len(cancel.result().goals_canceling), flush=True)
result = handle.get_result_async()
executor.spin_until_future_complete(result, timeout_sec=20)
r = result.result()
print("canceled", r.status, flush=True)
# the goal stopped within one step of its last feedback, far from the end
print("stopped near the last feedback",
      feedback[-1] - 1.0 <= r.result.distance_remaining <= feedback[-1] < 1000.0, flush=True)
"""


@pytest.fixture
def env() -> dict[str, str]:
    base = {k: v for k, v in os.environ.items()
            if not k.startswith(("ZENOH_", "ROS_DOMAIN", "POSEKIT_"))}
    base.update(POSEKIT_ZENOH_ROUTER=f"tcp/127.0.0.1:{free_port()}", PYTHONUNBUFFERED="1",
                POSEKIT_TRANSPORT="zenoh")
    return base


@pytest.mark.slow
def test_goal_feedback_result_and_cancel_between_processes(env: dict[str, str],
                                                           tmp_path: Path) -> None:
    server = Proc([sys.executable, "-c", textwrap.dedent(SERVER)], env, cwd=tmp_path)
    client: Proc | None = None
    try:
        server.wait_line(lambda s: "server ready" in s, 30, "the action server")
        client = Proc([sys.executable, "-c", textwrap.dedent(CLIENT)], env, cwd=tmp_path)
        out = client.finish(90, "the action client")
        assert client.popen.returncode == 0, client.describe()
        lines = out.splitlines()
        assert lines[:5] == [
            "server found True",
            "accepted True",
            "result 4 0.0",  # STATUS_SUCCEEDED
            "feedback [3.0, 2.0, 1.0]",
            "cancel 0 1",  # ERROR_NONE, one goal canceling
        ], client.describe()
        assert lines[5:] == [
            "canceled 5",  # STATUS_CANCELED
            "stopped near the last feedback True",
        ], client.describe()
    finally:
        if client is not None:
            client.kill()
        server.kill()
