# ParameterEventHandler (rclpy.parameter_event_handler), as the Jazzy tutorial "Monitoring
# for parameter changes" uses it: callbacks on one node's parameter, on every event, removal.
from rcl_interfaces.msg import ParameterEvent
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.parameter_event_handler import ParameterEventHandler

import rclpy

rclpy.init()
watched = Node("watched", namespace="/robot")
watcher = Node("watcher", namespace="/robot")
executor = SingleThreadedExecutor()
executor.add_node(watched)
executor.add_node(watcher)
handler = ParameterEventHandler(watcher)
seen = []
first = handler.add_parameter_callback(
    "gain", "watched", lambda p: seen.append(("first", p.name, p.value.double_value)))
second = handler.add_parameter_callback(
    "gain", "/robot/watched", lambda p: seen.append(("second", type(p).__name__)))
own = handler.add_parameter_callback("local", "", lambda p: seen.append(("own", p.name)))
events = handler.add_parameter_event_callback(
    lambda e: seen.append(("event", e.node, sorted(p.name for p in e.new_parameters),
                           sorted(p.name for p in e.changed_parameters))))
show("handle fields", lambda: (first.parameter_name, first.node_name, own.node_name))
show("subscription", lambda: handler.parameter_event_subscription.topic_name)


def settle():
    for _ in range(20):
        executor.spin_once(timeout_sec=0.02)


settle()
seen.clear()
watched.declare_parameter("gain", 0.5)
settle()
show("declared", lambda: seen)
seen.clear()
watched.set_parameters([Parameter("gain", value=1.5)])
settle()
show("changed", lambda: seen)
seen.clear()
watcher.declare_parameter("local", 1)
settle()
show("own node", lambda: seen)
seen.clear()
handler.remove_parameter_callback(second)
handler.remove_parameter_event_callback(events)
watched.set_parameters([Parameter("gain", value=2.5)])
settle()
show("after removal", lambda: seen)
kind("remove twice", lambda: handler.remove_parameter_callback(second))
kind("remove event twice", lambda: handler.remove_parameter_event_callback(events))

event = ParameterEvent(node="/robot/watched")
event.changed_parameters.append(Parameter("gain", value=3.0).to_parameter_msg())
show("from event", lambda: ParameterEventHandler.get_parameter_from_event(
    event, "gain", "/robot/watched").value.double_value)
show("from event, other node", lambda: ParameterEventHandler.get_parameter_from_event(
    event, "gain", "/robot/other"))
show("all from event", lambda: [p.name for p in ParameterEventHandler.get_parameters_from_event(
    event)])
show("subscribed", lambda: [n for n, _ in watcher.get_subscriber_names_and_types_by_node(
    "watcher", "/robot")])
handler.destroy()
show("destroyed", lambda: [n for n, _ in watcher.get_subscriber_names_and_types_by_node(
    "watcher", "/robot")])
executor.shutdown()
rclpy.shutdown()
