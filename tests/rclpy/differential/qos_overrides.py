# QoS overrides by parameter (rclpy.qos_overriding_options): the read-only qos_overrides.*
# parameters an entity declares, the profile they change, validation callbacks and errors.
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import QoSPolicyKind, QoSProfile, ReliabilityPolicy
from rclpy.qos_overriding_options import (
    QosCallbackResult,
    QoSOverridingOptions,
)
from std_msgs.msg import String

import rclpy

rclpy.init()
node = Node("qos", namespace="/ns", parameter_overrides=[
    Parameter("qos_overrides./ns/chatter.publisher.depth", value=20),
    Parameter("qos_overrides./ns/chatter.publisher.reliability", value="best_effort"),
    Parameter("qos_overrides./scan.subscription_lidar.durability", value="transient_local"),
    Parameter("qos_overrides./bad.publisher.reliability", value="sometimes"),
])


def qos_params():
    return sorted((n, p.value) for n, p in node.get_parameters_by_prefix("qos_overrides").items())


def profile(q):
    return (q.history.name, q.depth, q.reliability.name, q.durability.name,
            q.deadline.nanoseconds, q.lifespan.nanoseconds)


show("defaults", lambda: [k.name for k in QoSOverridingOptions.with_default_policies()
                          .policy_kinds])
plain = node.create_publisher(String, "plain", 10)
show("no options, no parameters", qos_params)
pub = node.create_publisher(String, "chatter", 10,
                            qos_overriding_options=QoSOverridingOptions.with_default_policies())
show("publisher parameters", qos_params)
show("publisher profile", lambda: profile(pub.qos_profile))
show("descriptor", lambda: (lambda d: (d.description, d.read_only, d.type))(
    node.describe_parameter("qos_overrides./ns/chatter.publisher.depth")))
show("read-only", lambda: node.set_parameters([
    Parameter("qos_overrides./ns/chatter.publisher.depth", value=5)])[0].successful)
again = node.create_publisher(String, "chatter", QoSProfile(depth=3),
                              qos_overriding_options=QoSOverridingOptions.with_default_policies())
show("second publisher", lambda: profile(again.qos_profile))
sub = node.create_subscription(
    String, "/scan", lambda m: None, 5,
    qos_overriding_options=QoSOverridingOptions(
        [QoSPolicyKind.DURABILITY, QoSPolicyKind.LIFESPAN, QoSPolicyKind.DEADLINE],
        entity_id="lidar"))
show("subscription parameters", lambda: [p for p in qos_params() if "scan" in p[0]])
show("subscription profile", lambda: profile(sub.qos_profile))


def refuse(qos):
    return QosCallbackResult(successful=qos.reliability == ReliabilityPolicy.RELIABLE,
                             reason="must be reliable")


kind("callback refuses", lambda: node.create_publisher(
    String, "chatter", 10, qos_overriding_options=QoSOverridingOptions.with_default_policies(
        callback=refuse)))
show("callback accepts", lambda: profile(node.create_publisher(
    String, "other", 10, qos_overriding_options=QoSOverridingOptions.with_default_policies(
        callback=refuse)).qos_profile))
kind("bad override", lambda: node.create_publisher(
    String, "/bad", 10, qos_overriding_options=QoSOverridingOptions.with_default_policies()))
show("options fields", lambda: (lambda o: (sorted(k.name for k in o.policy_kinds), o.entity_id,
                                           o.callback))(QoSOverridingOptions(
    [QoSPolicyKind.DEPTH], entity_id="x")))
node.destroy_node()
rclpy.shutdown()
