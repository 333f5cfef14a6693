# The rclpy.action / create_rate / wait_for_message API surface: parameter names, kinds and
# simple defaults, enum values, action_msgs constants, goal handles' public members.
import inspect

from action_msgs.msg import GoalStatus
from action_msgs.srv import CancelGoal
from rclpy.action import (
    ActionClient,
    ActionServer,
    CancelResponse,
    GoalResponse,
    get_action_client_names_and_types_by_node,
    get_action_names_and_types,
    get_action_server_names_and_types_by_node,
)
from rclpy.action.client import ClientGoalHandle
from rclpy.action.server import ServerGoalHandle
from rclpy.node import Node
from rclpy.timer import Rate
from rclpy.wait_for_message import wait_for_message

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
    show(fn.__qualname__, lambda fn=fn: params(fn))
show("GoalResponse", lambda: [(m.name, m.value) for m in GoalResponse])
show("CancelResponse", lambda: [(m.name, m.value) for m in CancelResponse])
show("GoalStatus", lambda: [(n, getattr(GoalStatus, n)) for n in dir(GoalStatus)
                            if n.startswith("STATUS_")])
show("CancelGoal errors", lambda: [(n, getattr(CancelGoal.Response, n))
                                   for n in dir(CancelGoal.Response) if n.startswith("ERROR_")])
for cls in (ServerGoalHandle, ClientGoalHandle, Rate):
    show(cls.__name__, lambda cls=cls: sorted(n for n in dir(cls) if not n.startswith("_")))
