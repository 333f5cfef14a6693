# Entities used after destroy (rclpy raises InvalidHandle; destroy returns None and may be
# repeated), and small API points: a None timer callback, non-str log messages,
# Publisher.topic vs topic_name, Future(executor=...).
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.task import Future
from std_msgs.msg import String

import rclpy

rclpy.init()
node = Node("doomed")
pub = node.create_publisher(String, "x", 10)
timer = node.create_timer(1.0, lambda: None)
show("destroy_node", lambda: node.destroy_node())
show("destroy_node again", lambda: node.destroy_node())
for method in ["get_name", "get_namespace", "get_fully_qualified_name", "get_node_names",
               "get_topic_names_and_types"]:
    show(method, lambda method=method: getattr(node, method)())
show("get_logger", lambda: type(node.get_logger()).__name__)
show("get_clock", lambda: node.get_clock())
show("get_parameter", lambda: node.get_parameter("use_sim_time").value)
show("create_publisher", lambda: node.create_publisher(String, "y", 10))
show("create_timer", lambda: type(node.create_timer(1.0, None)).__name__)
show("count_publishers", lambda: node.count_publishers("x"))
show("publish", lambda: pub.publish(String()))
show("topic_name", lambda: pub.topic_name)
show("timer of a destroyed node", lambda: timer.is_canceled())

other = Node("other")
timer = other.create_timer(1.0, lambda: None)
show("timer destroy", lambda: timer.destroy())
show("timer destroy again", lambda: timer.destroy())
for method in ["reset", "cancel", "is_canceled", "is_ready", "time_until_next_call",
               "time_since_last_call"]:
    show(f"timer {method}", lambda method=method: getattr(timer, method)())
show("timer period", lambda: timer.timer_period_ns)
pub = other.create_publisher(String, "z", 10)
show("publisher destroy", lambda: pub.destroy())
show("publish after destroy", lambda: pub.publish(String()))
show("subscription count after destroy", lambda: pub.get_subscription_count())
show("publisher destroy again", lambda: pub.destroy())
show("destroy_publisher after destroy", lambda: other.destroy_publisher(pub))
sub = other.create_subscription(String, "z", lambda msg: None, 10)
show("subscription destroy", lambda: sub.destroy())
show("publisher count after destroy", lambda: sub.get_publisher_count())

show("timer without callback", lambda: type(other.create_timer(1.0, None)).__name__)
logger = other.get_logger()
kind("log an int", lambda: logger.info(5))
kind("log a list", lambda: logger.warning([1]))
show("log None", lambda: logger.info(None))
show("filtered int", lambda: logger.debug(5))
ns_node = Node("n3", namespace="/ns")
for name in ["rel", "/abs", "~/private"]:
    show(f"publisher topic {name}", lambda name=name: (
        lambda p: (p.topic, p.topic_name))(ns_node.create_publisher(String, name, 10)))
    show(f"subscription topic {name}", lambda name=name: (lambda s: (s.topic, s.topic_name))(
        ns_node.create_subscription(String, name, lambda msg: None, 10)))
executor = SingleThreadedExecutor()
executor.add_node(ns_node)
calls = []
future = Future(executor=executor)
future.add_done_callback(lambda f: calls.append(f.result()))
future.set_result(3)
show("executor future callback deferred", lambda: calls)
executor.spin_once(timeout_sec=1.0)
show("executor future callback ran", lambda: calls)
show("plain future", lambda: Future().done())
executor.shutdown()
rclpy.shutdown()
