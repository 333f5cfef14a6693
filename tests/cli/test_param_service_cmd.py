"""``posekit param`` and ``posekit service`` against a node served by another thread
(in-process transport; the Zenoh cross-process runs are in test_cross_process.py).

Oracle: ros2cli's ros2param / ros2service (Jazzy) output formats, written out literally
here from their sources' format strings; values are what the node itself reports.
"""

from __future__ import annotations

import io
import threading
from collections.abc import Iterator
from pathlib import Path

import pytest
import yaml

from posekit.cli import param_cmd, service_cmd
from posekit.msgs.rcl_interfaces import IntegerRange, ParameterDescriptor
from posekit.msgs.std_srvs import SetBool
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node


@pytest.fixture
def served(ctx) -> Iterator[Node]:
    node = Node("ctl", namespace="/robot", context=ctx)
    node.declare_parameter("k_rho", 0.4)
    node.declare_parameter("mode", "auto", ParameterDescriptor(description="drive mode"))
    node.declare_parameter("wheels.count", 4, ParameterDescriptor(
        read_only=True, integer_range=[IntegerRange(from_value=2, to_value=8, step=2)]))
    node.declare_parameter("gains", [1.0, 2.0])
    node.create_service(SetBool, "enable",
                        lambda q, r: SetBool.Response(success=q.data, message=f"got {q.data}"))
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(node)
    spinner = threading.Thread(target=ex.spin, daemon=True)
    spinner.start()
    try:
        yield node
    finally:
        ex.shutdown()
        spinner.join(timeout=5.0)


def run(main, argv, ctx) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    code = main(argv, context=ctx, out=out, err=err)
    return code, out.getvalue(), err.getvalue()


def test_param_list_get_set_describe(ctx, served: Node) -> None:
    assert run(param_cmd.main_list, ["/robot/ctl"], ctx) == (
        0, "  gains\n  k_rho\n  mode\n  start_type_description_service\n  use_sim_time\n"
        "  wheels.count\n", "")
    code, out, _ = run(param_cmd.main_list, ["--param-type"], ctx)
    assert code == 0
    assert out.startswith("/robot/ctl:\n  gains (type: double array)\n  k_rho (type: double)\n")
    assert run(param_cmd.main_get, ["/robot/ctl", "k_rho"], ctx) == (
        0, "Double value is: 0.4\n", "")
    assert run(param_cmd.main_get, ["robot/ctl", "gains", "--hide-type"], ctx)[1] == "[1.0, 2.0]\n"
    assert run(param_cmd.main_get, ["/robot/ctl", "nope"], ctx) == (1, "", "Parameter not set\n")
    assert run(param_cmd.main_get, ["/nobody", "k_rho"], ctx) == (1, "", "Node not found\n")
    assert run(param_cmd.main_set, ["/robot/ctl", "k_rho", "1.0"], ctx) == (
        0, "Set parameter successful\n", "")
    assert served.get_parameter("k_rho").value == 1.0
    assert run(param_cmd.main_set, ["/robot/ctl", "k_rho", "1"], ctx) == (
        0, "", "Setting parameter failed: Wrong parameter type, expected 'Type.DOUBLE' "
        "got 'Type.INTEGER'\n")
    assert run(param_cmd.main_set, ["/robot/ctl", "wheels.count", "6"], ctx)[2] == (
        "Setting parameter failed: Trying to set a read-only parameter: wheels.count.\n")
    assert run(param_cmd.main_describe, ["/robot/ctl", "mode", "wheels.count"], ctx)[1] == (
        "Parameter name: mode\n  Type: string\n  Description: drive mode\n  Constraints:\n"
        "Parameter name: wheels.count\n  Type: integer\n  Constraints:\n    Read only: true\n"
        "    Min value: 2\n    Max value: 8\n    Step: 2\n"
    )


def test_param_dump_and_load_round_trip(ctx, served: Node, tmp_path: Path) -> None:
    code, out, _ = run(param_cmd.main_dump, ["/robot/ctl"], ctx)
    assert code == 0
    dumped = yaml.safe_load(out)
    assert dumped == {"/robot/ctl": {"ros__parameters": {
        "gains": [1.0, 2.0], "k_rho": 0.4, "mode": "auto", "use_sim_time": False,
        "start_type_description_service": True, "wheels": {"count": 4}}}}
    dumped["/robot/ctl"]["ros__parameters"].update(k_rho=0.9, mode="manual")
    del dumped["/robot/ctl"]["ros__parameters"]["wheels"]
    path = tmp_path / "params.yaml"
    path.write_text(yaml.safe_dump(dumped))
    code, out, err = run(param_cmd.main_load, ["/robot/ctl", str(path)], ctx)
    assert code == 0
    assert "Set parameter k_rho successful\n" in out
    assert "Set parameter mode successful\n" in out
    # the dump's read-only parameter is refused, as ros2 param load reports it
    assert err == ("Set parameter start_type_description_service failed: Trying to set a "
                   "read-only parameter: start_type_description_service.\n")
    assert served.get_parameter("k_rho").value == 0.9
    assert served.get_parameter("mode").value == "manual"
    bad = tmp_path / "bad.yaml"
    bad.write_text("just: text\n")
    code, _, err = run(param_cmd.main_load, ["/robot/ctl", str(bad)], ctx)
    assert code == 1
    assert err.count("\n") == 1
    assert "not a valid ROS parameter file" in err


def test_service_list_type_find_call(ctx, served: Node) -> None:
    code, out, _ = run(service_cmd.main_list, ["-t"], ctx)
    assert "/robot/enable [std_srvs/srv/SetBool]\n" in out
    assert "/robot/ctl/set_parameters [rcl_interfaces/srv/SetParameters]\n" in out
    assert run(service_cmd.main_type, ["/robot/enable"], ctx) == (0, "std_srvs/srv/SetBool\n", "")
    assert run(service_cmd.main_type, ["/nothing"], ctx)[0] == 1
    assert run(service_cmd.main_find, ["std_srvs/srv/SetBool"], ctx)[1] == "/robot/enable\n"
    code, out, err = run(service_cmd.main_call,
                         ["/robot/enable", "std_srvs/srv/SetBool", "{data: true}"], ctx)
    assert (code, err) == (0, "")
    assert out == (
        "requester: making request: std_srvs.srv.SetBool_Request(data=True)\n\n"
        "response:\nstd_srvs.srv.SetBool_Response(success=True, message='got True')\n\n"
    )
    assert run(service_cmd.main_call, ["/robot/enable", "std_srvs/srv/Nope"], ctx)[2] == (
        "The passed service type is invalid\n")
    code, _, err = run(service_cmd.main_call,
                       ["/robot/enable", "std_srvs/srv/SetBool", "{dat: 1}"], ctx)
    assert code == 1
    assert err.startswith("Failed to populate field: ")
    code, out, err = run(service_cmd.main_call,
                         ["/absent", "std_srvs/srv/Empty", "--timeout", "0.2"], ctx)
    assert (code, out) == (1, "waiting for service to become available...\n")
    assert err == "service '/absent' did not become available within 0.2 s\n"


def test_bad_input_is_one_line_never_a_traceback(ctx) -> None:
    code, _, err = run(service_cmd.main_call, ["bad name", "std_srvs/srv/Empty"], ctx)
    assert code == 1
    assert err.startswith("posekit service call: error: Invalid service name 'bad name'")
    assert err.count("\n") == 1
    code, _, err = run(param_cmd.main_set, ["/nobody", "x", "1"], ctx)
    assert (code, err) == (1, "Node not found\n")
    code, _, err = run(param_cmd.main_list, ["--filter", "("], ctx)  # a bad regex
    assert code == 1
    assert err.count("\n") == 1
