from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    QoSProfile,
    ReliabilityPolicy,
    qos_profile_parameter_events,
    qos_profile_parameters,
    qos_profile_services_default,
)
from std_msgs.msg import String

import rclpy

rclpy.init()
for name in ["good_name", "bad-name", "1abc", "", "with space", "ok_9"]:
    kind(f"node name {name!r}", lambda name=name: Node(name).get_name())
for ns in ["/ns", "ns", "/bad-ns", "/a//b", "/1a", "/a/"]:
    kind(f"namespace {ns!r}", lambda ns=ns: Node("n", namespace=ns).get_namespace())
node = Node("talker", namespace="/robot")
for topic in ["chatter", "/abs", "~/private", "~", "{node}/sub", "bad topic", "a//b", "1x",
              "a/", "/", "a/~b", "{bad", "x{node}y"]:
    kind(f"topic {topic!r}",
         lambda topic=topic: node.create_publisher(String, topic, 10).topic_name)
show("fq name", lambda: node.get_fully_qualified_name())
show("resolve", lambda: node.resolve_topic_name("~/x"))
show("resolve only expand", lambda: node.resolve_topic_name("chatter", only_expand=True))
for depth in [0, 1, 10]:
    show(f"qos depth {depth}", lambda depth=depth: QoSProfile(depth=depth).depth)
kind("qos negative depth", lambda: QoSProfile(depth=-1))
kind("qos no depth", lambda: QoSProfile())
kind("qos keep all", lambda: QoSProfile(history=HistoryPolicy.KEEP_ALL).depth)
show("qos defaults", lambda: (lambda q: (q.history, q.depth, q.reliability, q.durability))(
    QoSProfile(depth=5)))
show("qos parameters", lambda: (qos_profile_parameters.depth,
                                qos_profile_parameters.reliability))
show("qos parameter events", lambda: (qos_profile_parameter_events.depth,
                                      qos_profile_parameter_events.durability))
show("qos services", lambda: (qos_profile_services_default.depth,
                              qos_profile_services_default.history))
show("qos eq", lambda: QoSProfile(depth=5) == QoSProfile(depth=5))
show("qos neq", lambda: QoSProfile(depth=5) == QoSProfile(
    depth=5, reliability=ReliabilityPolicy.BEST_EFFORT))
show("policy by name", lambda: ReliabilityPolicy["BEST_EFFORT"])
show("durability value", lambda: DurabilityPolicy.TRANSIENT_LOCAL.value)
show("publisher int qos", lambda: node.create_publisher(String, "q1", 7).qos_profile.depth)
kind("publisher bad qos", lambda: node.create_publisher(String, "q2", "ten"))
show("count publishers", lambda: node.count_publishers("q1"))
show("duration", lambda: Duration(seconds=1.5).nanoseconds)
rclpy.shutdown()
