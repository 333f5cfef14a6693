# AsyncParameterClient (rclpy.parameter_client): another node's parameters through its
# parameter services, answers as futures, parameter events.
import os
import tempfile

from rcl_interfaces.msg import ParameterDescriptor
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.parameter_client import AsyncParameterClient

import rclpy

rclpy.init()
server = Node("tuned", namespace="/robot")
server.declare_parameter("k_rho", 0.4)
server.declare_parameter("mode", "auto", ParameterDescriptor(description="drive mode"))
server.declare_parameter("wheels.count", 4, ParameterDescriptor(read_only=True))
server.declare_parameter("free", 1, ParameterDescriptor(dynamic_typing=True))
user = Node("tuner")
executor = SingleThreadedExecutor()
executor.add_node(server)
executor.add_node(user)
client = AsyncParameterClient(user, "/robot/tuned")
done = []


def wait(future):
    executor.spin_until_future_complete(future, timeout_sec=10.0)
    return future.result()


def value(v):
    return (v.type, v.bool_value, v.integer_value, v.double_value, v.string_value)


show("ready", lambda: client.wait_for_services(timeout_sec=10.0))
show("services_are_ready", lambda: client.services_are_ready())
show("remote name", lambda: client.remote_node_name)
show("list", lambda: (lambda r: (sorted(r.result.names), sorted(r.result.prefixes)))(
    wait(client.list_parameters())))
show("list prefix", lambda: sorted(wait(client.list_parameters(["wheels"], 1)).result.names))
show("get", lambda: [value(v) for v in wait(client.get_parameters(["k_rho", "mode"])).values])
show("get unknown", lambda: [value(v) for v in wait(client.get_parameters(["nope"])).values])
show("set", lambda: [(r.successful, r.reason) for r in wait(client.set_parameters([
    Parameter("k_rho", Parameter.Type.DOUBLE, 0.9),
    Parameter("wheels.count", Parameter.Type.INTEGER, 6).to_parameter_msg(),
    Parameter("mode", Parameter.Type.INTEGER, 3)])).results])
show("after set", lambda: server.get_parameter("k_rho").value)
show("types", lambda: [int(t) for t in wait(client.get_parameter_types(["k_rho", "mode"])).types])
show("describe", lambda: [(d.name, d.type, d.description, d.read_only) for d in wait(
    client.describe_parameters(["mode", "wheels.count"])).descriptors])
show("atomically", lambda: (lambda r: (r.result.successful, r.result.reason))(wait(
    client.set_parameters_atomically([Parameter("k_rho", Parameter.Type.DOUBLE, 1.5),
                                      Parameter("mode", Parameter.Type.STRING, "manual")]))))
show("after atomically", lambda: (server.get_parameter("k_rho").value,
                                  server.get_parameter("mode").value))
show("delete static", lambda: [(r.successful, r.reason) for r in wait(
    client.delete_parameters(["k_rho"])).results])
show("delete dynamic", lambda: [(r.successful, r.reason) for r in wait(
    client.delete_parameters(["free"])).results])
show("after delete", lambda: server.has_parameter("free"))

with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
    f.write("/robot/tuned:\n  ros__parameters:\n    k_rho: 2.5\n"
            "/**:\n  ros__parameters:\n    mode: wild\n")
show("load file", lambda: [(r.successful, r.reason) for r in wait(
    client.load_parameter_file(f.name)).results])
show("after load", lambda: (server.get_parameter("k_rho").value,
                            server.get_parameter("mode").value))
show("load with wildcard atomically", lambda: wait(
    client.load_parameter_file_atomically(f.name, use_wildcard=True)).result.successful)
show("after wildcard", lambda: server.get_parameter("mode").value)
os.unlink(f.name)

events = []
sub = client.on_parameter_event(lambda e: events.append(
    (e.node, [p.name for p in e.changed_parameters])))
show("subscription topic", lambda: sub.topic_name)
future = client.set_parameters([Parameter("k_rho", Parameter.Type.DOUBLE, 3.0)],
                               callback=lambda f: done.append(f.result().results[0].successful))
wait(future)
for _ in range(100):  # rclpy runs done-callbacks as executor tasks: spin until both came
    if events and done:
        break
    executor.spin_once(timeout_sec=0.02)
show("done callback", lambda: done)
show("event", lambda: [e for e in events if e[0] == "/robot/tuned"][-1:])

nobody = AsyncParameterClient(user, "nobody")
show("nobody ready", lambda: nobody.wait_for_services(timeout_sec=0.5))
executor.shutdown()
rclpy.shutdown()
