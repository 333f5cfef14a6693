# Managed (lifecycle) nodes: the state machine and its callbacks, the services
# (change_state, get_state, get_available_states, get_available_transitions,
# get_transition_graph), ~/transition_event and the lifecycle publisher.
import lifecycle_msgs.msg
from lifecycle_msgs.msg import Transition
from lifecycle_msgs.srv import ChangeState, GetAvailableStates, GetAvailableTransitions, GetState
from rclpy.executors import SingleThreadedExecutor
from rclpy.lifecycle import LifecycleNode, LifecyclePublisher, LifecycleState
from rclpy.lifecycle import TransitionCallbackReturn as R
from rclpy.node import Node
from std_msgs.msg import String

import rclpy

rclpy.init()
calls = []
answers = {}


class Managed(LifecycleNode):
    def __init__(self):
        super().__init__("lc")
        self.pub = self.create_lifecycle_publisher(String, "out", 10)

    def record(self, name, state):
        calls.append((name, state.state_id, state.label))
        answer = answers.get(name, R.SUCCESS)
        if answer == "raise":
            raise RuntimeError("boom")
        return answer

    def on_configure(self, state):
        return self.record("configure", state)

    def on_activate(self, state):
        answer = self.record("activate", state)
        return super().on_activate(state) if answer == R.SUCCESS else answer

    def on_deactivate(self, state):
        answer = self.record("deactivate", state)
        return super().on_deactivate(state) if answer == R.SUCCESS else answer

    def on_cleanup(self, state):
        return self.record("cleanup", state)

    def on_shutdown(self, state):
        return self.record("shutdown", state)

    def on_error(self, state):
        return self.record("error", state)


node = Managed()
other = Node("watcher")
events, heard = [], []
other.create_subscription(
    lifecycle_msgs.msg.TransitionEvent, "/lc/transition_event",
    lambda m: events.append((m.transition.id, m.transition.label, m.start_state.label,
                             m.goal_state.label, m.timestamp > 0)), 10)
other.create_subscription(String, "/out", lambda m: heard.append(m.data), 10)
executor = SingleThreadedExecutor()
executor.add_node(node)
executor.add_node(other)


def spin(times=20):
    for _ in range(times):
        executor.spin_once(timeout_sec=0.02)


def call(srv_type, name, request):
    client = other.create_client(srv_type, name)
    client.wait_for_service(timeout_sec=10.0)
    future = client.call_async(request)
    executor.spin_until_future_complete(future, timeout_sec=10.0)
    other.destroy_client(client)
    return future.result()


def state():
    s = call(GetState, "/lc/get_state", GetState.Request()).current_state
    return (s.id, s.label)


def transitions(name="/lc/get_available_transitions"):
    got = call(GetAvailableTransitions, name, GetAvailableTransitions.Request())
    return [(t.transition.id, t.transition.label, t.start_state.label, t.goal_state.label)
            for t in got.available_transitions]


show("return codes", lambda: [(r.name, int(r), r.to_label()) for r in (R.SUCCESS, R.FAILURE,
                                                                    R.ERROR)])
show("aliases", lambda: [c.__name__ for c in (rclpy.lifecycle.Node, rclpy.lifecycle.State,
                                             rclpy.lifecycle.Publisher)])
show("LifecycleState", lambda: LifecycleState(label="x", state_id=3))
show("services", lambda: sorted(n for n, _ in other.get_service_names_and_types_by_node(
    "lc", "/") if "parameter" not in n and "type_description" not in n))
show("service types", lambda: sorted({t[0] for n, t in other.get_service_names_and_types_by_node(
    "lc", "/") if "parameter" not in n and "type_description" not in n}))
show("topics", lambda: sorted(n for n, _ in other.get_publisher_names_and_types_by_node(
    "lc", "/")))
show("initial state", state)
show("available states", lambda: [(s.id, s.label) for s in call(
    GetAvailableStates, "/lc/get_available_states", GetAvailableStates.Request()
).available_states])
show("transition graph", lambda: transitions("/lc/get_transition_graph"))
show("transitions unconfigured", transitions)
show("publisher class", lambda: (type(node.pub).__name__, isinstance(node.pub,
                                                                     LifecyclePublisher)))
show("inactive publisher", lambda: node.pub.is_activated)
node.pub.publish(String(data="before"))
show("configure", lambda: node.trigger_configure())
show("after configure", state)
show("transitions inactive", transitions)
show("activate", lambda: node.trigger_activate())
show("after activate", lambda: (state(), node.pub.is_activated))
show("transitions active", transitions)
node.pub.publish(String(data="while active"))
spin()
show("deactivate", lambda: node.trigger_deactivate())
node.pub.publish(String(data="after deactivate"))
spin()
show("heard", lambda: heard)
show("cleanup", lambda: node.trigger_cleanup())
show("after cleanup", state)
kind("activate from unconfigured", lambda: node.trigger_activate())
show("still unconfigured", state)

answers["configure"] = R.FAILURE
show("configure fails", lambda: node.trigger_configure())
show("after a failure", state)
answers["configure"] = R.ERROR
show("configure errs", lambda: node.trigger_configure())
show("after an error", state)
answers["configure"] = "raise"
show("configure raises", lambda: node.trigger_configure())
show("after it raised", state)
answers.pop("configure")

show("by label", lambda: call(ChangeState, "/lc/change_state", ChangeState.Request(
    transition=Transition(label="configure"))).success)
show("by id", lambda: call(ChangeState, "/lc/change_state", ChangeState.Request(
    transition=Transition(id=Transition.TRANSITION_ACTIVATE))).success)
show("after the service", state)
show("unknown label", lambda: call(ChangeState, "/lc/change_state", ChangeState.Request(
    transition=Transition(label="fly"))).success)
answers["deactivate"] = R.ERROR
answers["error"] = R.FAILURE
show("deactivate errs, error fails", lambda: node.trigger_deactivate())
show("finalized", state)
show("transitions finalized", transitions)
kind("shutdown when finalized", lambda: node.trigger_shutdown())
spin()
show("callbacks", lambda: calls)
show("events", lambda: events)

quiet = LifecycleNode("quiet", enable_communication_interface=False)
show("without interface", lambda: sorted(n for n, _ in other.get_service_names_and_types_by_node(
    "quiet", "/") if "parameter" not in n and "type_description" not in n))
show("shutdown from unconfigured", lambda: quiet.trigger_shutdown())
executor.shutdown()
rclpy.shutdown()
