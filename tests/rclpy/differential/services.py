from rcl_interfaces.srv import GetParameters, ListParameters, SetParameters
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import MultiThreadedExecutor, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from std_srvs.srv import Empty, SetBool, Trigger

import rclpy

rclpy.init()
server = Node("diff_server", namespace="/robot")
client_node = Node("diff_client")
executor = SingleThreadedExecutor()
executor.add_node(server)
executor.add_node(client_node)
server.declare_parameter("gain", 0.5)
server.declare_parameter("names", ["a", "b"])

calls = []


def on_set_bool(request, response):
    calls.append(request.data)
    response.success = not request.data
    response.message = f"flipped {request.data}"
    return response


srv = server.create_service(SetBool, "flip", on_set_bool)
private = server.create_service(Trigger, "~/reset", lambda q, r: Trigger.Response(
    success=True, message="reset"))
show("service name", lambda: srv.srv_name)
show("private name", lambda: private.srv_name)
show("service type", lambda: srv.srv_type.__name__)
kind("bad service name", lambda: server.create_service(Empty, "bad name", lambda q, r: r))
kind("bad service name 2", lambda: server.create_service(Empty, "1st", lambda q, r: r))
kind("bad client name", lambda: client_node.create_client(Empty, "a//b"))

client = client_node.create_client(SetBool, "/robot/flip")
show("client name", lambda: client.srv_name)
show("wait_for_service", lambda: client.wait_for_service(timeout_sec=10.0))
show("service_is_ready", lambda: client.service_is_ready())


def call(cli, request):
    future = cli.call_async(request)
    executor.spin_until_future_complete(future, timeout_sec=10.0)
    return future.result()


show("call true", lambda: (lambda r: (type(r).__name__, r.success, r.message))(
    call(client, SetBool.Request(data=True))))
show("call false", lambda: (lambda r: (r.success, r.message))(
    call(client, SetBool.Request(data=False))))
show("calls seen", lambda: calls)
show("counts", lambda: (client_node.count_services("/robot/flip"),
                        client_node.count_clients("/robot/flip"),
                        server.count_services("flip"), client_node.count_services("/none")))
kind("wrong request type", lambda: client.call_async(Trigger.Request()))
show("future before spin", lambda: (lambda f: (f.done(), f.result()))(
    client.call_async(SetBool.Request(data=True))))
pending = client.call_async(SetBool.Request(data=True))


def never(_f):
    print("never: called")


pending.add_done_callback(never)
show("remove done callback", lambda: (pending.remove_done_callback(never),
                                      pending.remove_done_callback(never)))
executor.spin_until_future_complete(pending, timeout_sec=10.0)
show("pending done", lambda: (pending.done(), pending.result().message))
absent = client_node.create_client(Empty, "/nobody_serves_this")
show("absent ready", lambda: absent.service_is_ready())
show("absent wait", lambda: absent.wait_for_service(timeout_sec=0.2))
show("call with timeout", lambda: absent.call(Empty.Request(), timeout_sec=0.2))

# -- the parameter services of a node, used as ros2 param does -------------------------------
get = client_node.create_client(GetParameters, "/robot/diff_server/get_parameters")
show("param services up", lambda: get.wait_for_service(timeout_sec=10.0))
show("get params", lambda: [(v.type, v.double_value, list(v.string_array_value))
                            for v in call(get, GetParameters.Request(
                                names=["gain", "names"])).values])
show("get params undeclared", lambda: list(call(get, GetParameters.Request(
    names=["gain", "nope"])).values))
setp = client_node.create_client(SetParameters, "/robot/diff_server/set_parameters")
setp.wait_for_service(timeout_sec=10.0)
show("set params", lambda: [(r.successful, r.reason) for r in call(
    setp, SetParameters.Request(parameters=[
        Parameter("gain", value=1.0).to_parameter_msg(),
        Parameter("gain", value="x").to_parameter_msg(),
        Parameter("nope", value=1).to_parameter_msg()])).results])
show("gain now", lambda: server.get_parameter("gain").value)
lister = client_node.create_client(ListParameters, "/robot/diff_server/list_parameters")
lister.wait_for_service(timeout_sec=10.0)
show("list params", lambda: sorted(call(lister, ListParameters.Request()).result.names))
show("services by node", lambda: client_node.get_service_names_and_types_by_node(
    "diff_server", "/robot"))
show("clients by node", lambda: sorted(
    client_node.get_client_names_and_types_by_node("diff_client", "/")))

# -- a blocking call inside a callback of a single-threaded executor ---------------------
inside = []


def tick():
    timer.cancel()
    inside.append(client.call(SetBool.Request(data=False), timeout_sec=1.0))


timer = client_node.create_timer(0.01, tick)
executor.spin_once(timeout_sec=5.0)
# rclpy: the executor is blocked in tick, the server never runs: None after the timeout.
show("call inside a callback", lambda: inside[0] if inside[0] is None else inside[0].message)

# -- destroy ------------------------------------------------------------------------------------
show("destroy service", lambda: server.destroy_service(srv))
show("destroy twice", lambda: server.destroy_service(srv))
show("destroy client", lambda: client_node.destroy_client(absent))

# -- a multi-threaded executor: a service calling another service inside its callback --------
both = Node("diff_both")
group = ReentrantCallbackGroup()
both.create_service(Trigger, "inner", lambda q, r: Trigger.Response(success=True, message="in"),
                    callback_group=group)
inner = both.create_client(Trigger, "inner", callback_group=group)


def outer_cb(request, response):
    got = inner.call(Trigger.Request(), timeout_sec=10.0)
    response.success = got.success
    response.message = "outer+" + got.message
    return response


both.create_service(Trigger, "outer", outer_cb, callback_group=group)
outer = both.create_client(Trigger, "outer", callback_group=group)
mt = MultiThreadedExecutor(num_threads=3)
mt.add_node(both)
outer.wait_for_service(timeout_sec=10.0)
inner.wait_for_service(timeout_sec=10.0)
future = outer.call_async(Trigger.Request())
mt.spin_until_future_complete(future, timeout_sec=10.0)
show("nested call", lambda: (future.result().success, future.result().message))
rclpy.shutdown()
