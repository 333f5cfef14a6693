"""The rclpy.action, create_rate and wait_for_message API surface, differentially.

Oracle: the real ROS 2 Jazzy rclpy. One script prints, under both, the parameter names,
kinds and simple defaults of the entry points, the GoalResponse/CancelResponse values, the
action_msgs constants and the public members of the goal handles and Rate; the outputs must
be identical, so code written against rclpy's signatures runs unchanged.
"""

from __future__ import annotations

import pytest

from _support.differential import run_both

SCRIPT = """
import inspect
import rclpy
from rclpy.action import ActionClient, ActionServer, CancelResponse, GoalResponse
from rclpy.action import get_action_client_names_and_types_by_node
from rclpy.action import get_action_names_and_types, get_action_server_names_and_types_by_node
from rclpy.action.client import ClientGoalHandle
from rclpy.action.server import ServerGoalHandle
from rclpy.node import Node
from rclpy.timer import Rate
from rclpy.wait_for_message import wait_for_message
from action_msgs.msg import GoalStatus
from action_msgs.srv import CancelGoal

SIMPLE = (int, float, str, type(None))

def params(fn):
    out = []
    for p in inspect.signature(fn).parameters.values():
        simple = p.default is not inspect.Parameter.empty and isinstance(p.default, SIMPLE)
        out.append((p.name, p.kind.name, p.default if simple else "-"))
    return out

for fn in (ActionServer.__init__, ActionClient.__init__, ActionClient.send_goal_async,
           ActionClient.wait_for_server, ActionClient.server_is_ready, ActionClient.destroy,
           ServerGoalHandle.execute, ServerGoalHandle.publish_feedback,
           ClientGoalHandle.get_result_async, ClientGoalHandle.cancel_goal_async,
           Node.create_rate, Node.destroy_rate, wait_for_message, get_action_names_and_types,
           get_action_server_names_and_types_by_node,
           get_action_client_names_and_types_by_node):
    print(fn.__qualname__, params(fn))
print([(m.name, m.value) for m in GoalResponse], [(m.name, m.value) for m in CancelResponse])
print([(n, getattr(GoalStatus, n)) for n in dir(GoalStatus) if n.startswith("STATUS_")])
print([(n, getattr(CancelGoal.Response, n)) for n in dir(CancelGoal.Response)
       if n.startswith("ERROR_")])
for cls in (ServerGoalHandle, ClientGoalHandle, Rate):
    print(cls.__name__, sorted(n for n in dir(cls) if not n.startswith("_")))
"""


@pytest.mark.slow
def test_action_rate_and_wait_for_message_signatures_match_rclpy() -> None:
    ref, ours = run_both(SCRIPT, domain_id=139)
    assert ours == ref
    lines = ref.splitlines()
    assert len(lines) == 22  # every probe printed (16 signatures, 3 constants, 3 classes)
    assert lines[0].startswith("ActionServer.__init__ [('self'")
