# The type description service every Jazzy node serves (~/get_type_description,
# REP-2011): its parameter, and its answers by the hash of a type the node uses (the
# description of each field and nested type), with rcl's failure reasons.
from geometry_msgs.msg import TransformStamped, Twist
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from std_msgs.msg import String
from std_srvs.srv import SetBool
from type_description_interfaces.srv import GetTypeDescription

import rclpy

rclpy.init()
alpha = Node("alpha")
beta = Node("beta")
alpha.create_publisher(TransformStamped, "tf_out", 10)
alpha.create_subscription(String, "chat", lambda msg: None, 10)
alpha.create_service(SetBool, "flag", lambda request, response: response)
client = beta.create_client(GetTypeDescription, "/alpha/get_type_description")
executor = SingleThreadedExecutor()
executor.add_node(alpha)
executor.add_node(beta)

show("parameter", lambda: alpha.get_parameter("start_type_description_service").value)
show("descriptor", lambda: (lambda d: (d.name, d.type, d.description, d.read_only))(
    alpha.describe_parameter("start_type_description_service")))
show("read-only", lambda: alpha.set_parameters([
    Parameter("start_type_description_service", value=False)])[0].successful)
show("served", lambda: client.wait_for_service(timeout_sec=10.0))


def individual(t):
    return (t.type_name, [(f.name, f.type.type_id, f.type.capacity, f.type.string_capacity,
                           f.type.nested_type_name, f.default_value) for f in t.fields])


def ask(type_name, type_hash, sources=False):
    future = client.call_async(GetTypeDescription.Request(
        type_name=type_name, type_hash=type_hash, include_type_sources=sources))
    executor.spin_until_future_complete(future, timeout_sec=10.0)
    return future.result()


def answer(type_name, type_hash, sources=False):
    r = ask(type_name, type_hash, sources)
    d = r.type_description
    return (r.successful, r.failure_reason, individual(d.type_description),
            [individual(t) for t in d.referenced_type_descriptions],
            [(k.key, k.value) for k in r.extra_information])


def hash_of(infos, node="alpha"):
    return str(next(i for i in infos if i.node_name == node).topic_type_hash)


tf_hash = hash_of(alpha.get_publishers_info_by_topic("/tf_out"))
string_hash = hash_of(alpha.get_subscriptions_info_by_topic("/chat"))
log_hash = hash_of(alpha.get_publishers_info_by_topic("/rosout"))
event_hash = hash_of(alpha.get_publishers_info_by_topic("/parameter_events"))
# std_srvs/srv/SetBool's hash: an input here (the graph carries no service type hashes);
# a side that hashed it otherwise would not find the type
set_bool_hash = "RIHS01_abe9e4bb6b41b40e6789712c00ec8871923e089af3f667a79992a428cff2da0a"

show("TransformStamped", lambda: answer("geometry_msgs/msg/TransformStamped", tf_hash))
show("String, sources asked", lambda: answer("std_msgs/msg/String", string_hash, True))
show("sources", lambda: [(s.type_name, s.encoding) for s in ask(
    "std_msgs/msg/String", string_hash, True).type_sources])
show("rosout's Log", lambda: answer("rcl_interfaces/msg/Log", log_hash))
show("parameter events", lambda: answer("", event_hash))
show("a service's type", lambda: answer("", set_bool_hash))
show("the name is not looked at", lambda: answer("geometry_msgs/msg/Twist", string_hash)[:3])
show("a hash of no type in use", lambda: answer("x", "RIHS01_" + "00" * 32))
show("upper-case hex", lambda: answer("", string_hash.upper())[:2])
show("garbage", lambda: answer("std_msgs/msg/String", "garbage"))
show("empty", lambda: answer("std_msgs/msg/String", ""))
show("too short", lambda: answer("", string_hash[:-2])[:2])

twist_pub = alpha.create_publisher(Twist, "cmd", 10)
twist_hash = hash_of(alpha.get_publishers_info_by_topic("/cmd"))
show("a new publisher's type", lambda: answer("", twist_hash)[:3])
alpha.destroy_publisher(twist_pub)
show("after it is destroyed", lambda: answer("", twist_hash)[:2])

quiet = Node("quiet", parameter_overrides=[
    Parameter("start_type_description_service", value=False)])
show("switched off", lambda: (
    quiet.get_parameter("start_type_description_service").value,
    [n for n, _ in quiet.get_service_names_and_types_by_node("quiet", "/")
     if n.endswith("get_type_description")]))
executor.shutdown()
rclpy.shutdown()
