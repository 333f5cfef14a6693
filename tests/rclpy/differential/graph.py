# The node's graph API: node names (with namespaces, enclaves), endpoint info by topic
# (rclpy's TopicEndpointInfo and its text), names and types by node (and their errors),
# wait_for_node, guard conditions,
# default_callback_group, and the modules users import classes from for type hints.
import time

import rclpy.context
import rclpy.guard_condition
import rclpy.publisher
import rclpy.subscription
import rclpy.topic_endpoint_info
from rclpy.duration import Duration
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node, NodeNameNonExistentError
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.topic_endpoint_info import TopicEndpointTypeEnum
from std_msgs.msg import String
from std_srvs.srv import Trigger

import rclpy

rclpy.init()
alpha = Node("alpha", namespace="/robot")
beta = Node("beta")
pub = alpha.create_publisher(String, "chatter", QoSProfile(
    depth=3, durability=DurabilityPolicy.TRANSIENT_LOCAL, lifespan=Duration(seconds=2)))
sub = beta.create_subscription(String, "/robot/chatter", lambda msg: None, QoSProfile(
    depth=7, reliability=ReliabilityPolicy.BEST_EFFORT))
server = beta.create_service(Trigger, "reset", lambda request, response: response)
client = alpha.create_client(Trigger, "/reset")
time.sleep(0.5)  # discovery (Fast DDS)
show("node names", lambda: sorted(alpha.get_node_names()))
show("names and namespaces", lambda: sorted(alpha.get_node_names_and_namespaces()))
show("with enclaves", lambda: sorted(alpha.get_node_names_and_namespaces_with_enclaves()))
show("fully qualified", lambda: sorted(alpha.get_fully_qualified_node_names()))


for query in ("publisher", "subscriber", "service", "client"):
    method = getattr(beta, f"get_{query}_names_and_types_by_node")
    show(f"{query}s of alpha", lambda m=method: m("alpha", "/robot"))
    show(f"{query}s of beta", lambda m=method: m("beta", "/"))
    show(f"{query}s of beta, empty namespace", lambda m=method: m("beta", ""))
    kind(f"{query}s of nobody", lambda m=method: m("nobody", "/"))
    kind(f"{query}s, relative namespace", lambda m=method: m("alpha", "robot"))
    kind(f"{query}s, bad node name", lambda m=method: m("bad name", "/"))
show("publishers, no_demangle=False", lambda: beta.get_publisher_names_and_types_by_node(
    "alpha", "/robot", False))
show("nonexistent is an RCLError", lambda: [
    c.__name__ for c in NodeNameNonExistentError.__mro__[1:] if c.__name__ == "RuntimeError"])


def fields(info):
    q = info.qos_profile
    # the history and depth a middleware reports differ (Fast DDS: UNKNOWN, 0)
    return (info.node_name, info.node_namespace, info.topic_type, str(info.topic_type_hash),
            info.endpoint_type, len(info.endpoint_gid), type(info.endpoint_gid).__name__,
            q.reliability, q.durability, str(q.lifespan), str(q.deadline), q.liveliness,
            str(q.liveliness_lease_duration), q.avoid_ros_namespace_conventions)


def text(info):
    return [line for line in str(info).splitlines()
            if not line.startswith(("GID: ", "  History (Depth): "))]


pubs = alpha.get_publishers_info_by_topic("chatter")
subs = beta.get_subscriptions_info_by_topic("/robot/chatter")
show("publishers", lambda: [fields(i) for i in pubs])
show("publisher text", lambda: text(pubs[0]))
show("subscriptions", lambda: [fields(i) for i in subs])
show("subscription text", lambda: text(subs[0]))
show("info class", lambda: (type(pubs[0]).__name__, type(pubs[0]).__module__.split(".")[-1]))
show("relative name of another namespace", lambda: beta.get_publishers_info_by_topic("chatter"))
show("private name", lambda: alpha.get_publishers_info_by_topic("~/x"))


def value_error(fn):
    try:
        fn()
    except ValueError:  # rclpy: ValueError itself; posekit: InvalidTopicNameException
        return True
    return False


show("bad topic name", lambda: value_error(lambda: alpha.get_publishers_info_by_topic("a b")))
show("endpoint types", lambda: list(TopicEndpointTypeEnum))
show("count", lambda: (alpha.count_publishers("chatter"), alpha.count_subscribers("chatter")))

show("wait for itself", lambda: alpha.wait_for_node("/robot/alpha", 1.0))
show("wait without slash", lambda: alpha.wait_for_node("beta", 1.0))
started = time.monotonic()
show("wait for nobody", lambda: alpha.wait_for_node("/nobody", 0.3))
show("waited", lambda: 0.25 < time.monotonic() - started < 1.0)
show("wait negative", lambda: alpha.wait_for_node("/beta", -1))

show("default group", lambda: type(alpha.default_callback_group).__name__)
kind("set default group", lambda: setattr(alpha, "default_callback_group", None))
hits = []
guard = alpha.create_guard_condition(lambda: hits.append(len(hits)))
show("guard class", lambda: type(guard) is rclpy.guard_condition.GuardCondition)
executor = SingleThreadedExecutor()
executor.add_node(alpha)
executor.spin_once(timeout_sec=0.1)
show("not triggered", lambda: hits)
guard.trigger()
guard.trigger()
executor.spin_once(timeout_sec=1.0)
executor.spin_once(timeout_sec=0.1)
show("triggered twice, run once", lambda: hits)
guard.trigger()
executor.spin_once(timeout_sec=1.0)
show("triggered again", lambda: hits)
show("destroy guard", lambda: alpha.destroy_guard_condition(guard))
show("destroy guard again", lambda: alpha.destroy_guard_condition(guard))
show("trigger destroyed", lambda: guard.trigger())

show("publisher module", lambda: type(pub) is rclpy.publisher.Publisher)
show("subscription module", lambda: type(sub) is rclpy.subscription.Subscription)
show("context module", lambda: type(alpha.context) is rclpy.context.Context)
show("topic_endpoint_info module", lambda: sorted(
    n for n in ("TopicEndpointInfo", "TopicEndpointTypeEnum", "TypeHash")
    if hasattr(rclpy.topic_endpoint_info, n)))
executor.shutdown()
rclpy.shutdown()
