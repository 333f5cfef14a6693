"""Parameter services and /parameter_events of every node, used through real clients.

Oracle: rclpy's ParameterService and Node behaviour (Jazzy), e.g. an undeclared name makes
GetParameters answer an empty list, SetParameters reports it as a failed result with the
ParameterNotDeclaredException text; the differential suite (tests/rclpy) runs the same kind
of script against the real rclpy.
"""

from __future__ import annotations

import pytest

from posekit.msgs.rcl_interfaces import (
    DescribeParameters,
    FloatingPointRange,
    GetParameters,
    GetParameterTypes,
    ListParameters,
    ParameterDescriptor,
    ParameterEvent,
    ParameterType,
    SetParameters,
    SetParametersAtomically,
)
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.parameters import Parameter, parameter_value_to_python


@pytest.fixture
def pair(ctx):
    server = Node("ctl", namespace="/robot", context=ctx)
    server.declare_parameter("k_rho", 0.4, ParameterDescriptor(
        description="distance gain",
        floating_point_range=[FloatingPointRange(from_value=0.0, to_value=2.0, step=0.0)],
    ))
    server.declare_parameter("name", "bot")
    server.declare_parameter("wheels.count", 4)
    server.declare_parameter("wheels.radius", 0.05)
    client_node = Node("cli", context=ctx)
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(server)
    ex.add_node(client_node)
    return server, client_node, ex


def _call(client_node, ex, srv_type, name, request):
    client = client_node.create_client(srv_type, name)
    assert client.wait_for_service(timeout_sec=1.0)
    future = client.call_async(request)
    ex.spin_until_future_complete(future, timeout_sec=5.0)
    assert future.done()
    return future.result()


def test_every_node_serves_the_six_parameter_services(pair) -> None:
    server, client_node, _ = pair
    served = dict(client_node.get_service_names_and_types_by_node("ctl", "/robot"))
    assert served == {  # and, without being asked to, its type descriptions (as rclpy)
        "/robot/ctl/get_type_description": [
            "type_description_interfaces/srv/GetTypeDescription"],
        "/robot/ctl/describe_parameters": ["rcl_interfaces/srv/DescribeParameters"],
        "/robot/ctl/get_parameter_types": ["rcl_interfaces/srv/GetParameterTypes"],
        "/robot/ctl/get_parameters": ["rcl_interfaces/srv/GetParameters"],
        "/robot/ctl/list_parameters": ["rcl_interfaces/srv/ListParameters"],
        "/robot/ctl/set_parameters": ["rcl_interfaces/srv/SetParameters"],
        "/robot/ctl/set_parameters_atomically": ["rcl_interfaces/srv/SetParametersAtomically"],
    }
    quiet = Node("quiet", context=server.context, start_parameter_services=False)
    assert client_node.get_service_names_and_types_by_node("quiet", "/") == [
        ("/quiet/get_type_description", ["type_description_interfaces/srv/GetTypeDescription"])]
    quiet.destroy_node()


def test_list_get_types_and_describe(pair) -> None:
    _, client_node, ex = pair
    listed = _call(client_node, ex, ListParameters, "/robot/ctl/list_parameters",
                   ListParameters.Request()).result
    assert listed.names == ["use_sim_time", "start_type_description_service", "k_rho", "name",
                            "wheels.count", "wheels.radius"]
    assert listed.prefixes == ["wheels"]
    shallow = _call(client_node, ex, ListParameters, "/robot/ctl/list_parameters",
                    ListParameters.Request(prefixes=["wheels"], depth=1)).result
    assert shallow.names == ["wheels.count", "wheels.radius"]
    values = _call(client_node, ex, GetParameters, "/robot/ctl/get_parameters",
                   GetParameters.Request(names=["k_rho", "name"])).values
    assert [parameter_value_to_python(v) for v in values] == [0.4, "bot"]
    assert [v.type for v in values] == [ParameterType.PARAMETER_DOUBLE,
                                        ParameterType.PARAMETER_STRING]
    none = _call(client_node, ex, GetParameters, "/robot/ctl/get_parameters",
                 GetParameters.Request(names=["k_rho", "nope"])).values
    assert none == []  # rclpy: one undeclared name empties the whole answer
    types = _call(client_node, ex, GetParameterTypes, "/robot/ctl/get_parameter_types",
                  GetParameterTypes.Request(names=["wheels.count", "use_sim_time"])).types
    assert list(types) == [ParameterType.PARAMETER_INTEGER, ParameterType.PARAMETER_BOOL]
    (desc,) = _call(client_node, ex, DescribeParameters, "/robot/ctl/describe_parameters",
                    DescribeParameters.Request(names=["k_rho"])).descriptors
    assert (desc.name, desc.type, desc.description) == (
        "k_rho", ParameterType.PARAMETER_DOUBLE, "distance gain")
    assert desc.floating_point_range[0].to_value == 2.0


def test_set_parameters_over_the_service_and_parameter_events(pair) -> None:
    server, client_node, ex = pair
    events: list[ParameterEvent] = []
    client_node.create_subscription(ParameterEvent, "/parameter_events", events.append, 100)
    request = SetParameters.Request(parameters=[
        Parameter("k_rho", value=1.0).to_parameter_msg(),
        Parameter("k_rho", value=1).to_parameter_msg(),     # wrong type
        Parameter("k_rho", value=5.0).to_parameter_msg(),   # out of range
        Parameter("missing", value=1).to_parameter_msg(),
    ])
    results = _call(client_node, ex, SetParameters, "/robot/ctl/set_parameters", request).results
    assert [r.successful for r in results] == [True, False, False, False]
    assert results[1].reason == "Wrong parameter type, expected 'Type.DOUBLE' got 'Type.INTEGER'"
    assert results[2].reason == "Parameter k_rho out of range Min: 0.0, Max: 2.0, value: 5.0"
    # rclpy's text names the undeclared parameters after the first: none here
    assert results[3].reason == "Invalid access to undeclared parameter(s): []"
    assert server.get_parameter("k_rho").value == 1.0
    atomic = _call(client_node, ex, SetParametersAtomically,
                   "/robot/ctl/set_parameters_atomically",
                   SetParametersAtomically.Request(parameters=[
                       Parameter("name", value="robo").to_parameter_msg(),
                       Parameter("wheels.count", value="six").to_parameter_msg(),
                   ])).result
    assert not atomic.successful
    assert server.get_parameter("name").value == "bot"  # all or nothing
    ex.spin_some()
    mine = [e for e in events if e.node == "/robot/ctl"]
    assert len(mine) == 1
    (changed,) = mine[0].changed_parameters
    assert changed.name == "k_rho"
    assert changed.value.double_value == 1.0
    assert mine[0].new_parameters == []
    assert mine[0].deleted_parameters == []


def test_declare_publishes_new_parameters_and_not_set_undeclares_only_dynamic(ctx) -> None:
    node = Node("n", context=ctx)
    events: list[ParameterEvent] = []
    node.create_subscription(ParameterEvent, "/parameter_events", events.append, 100)
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(node)
    node.declare_parameter("typed", 1)
    node.declare_parameter("loose", 1, ParameterDescriptor(dynamic_typing=True))
    (refused,) = node.set_parameters([Parameter("typed", value=None)])
    assert not refused.successful
    assert refused.reason == "Static parameter cannot be undeclared"
    assert node.get_parameter("typed").value == 1
    (deleted,) = node.set_parameters([Parameter("loose", value=None)])
    assert deleted.successful
    assert not node.has_parameter("loose")
    ex.spin_some()
    assert [p.name for e in events for p in e.new_parameters] == ["typed", "loose"]
    assert [p.name for e in events for p in e.deleted_parameters] == ["loose"]
