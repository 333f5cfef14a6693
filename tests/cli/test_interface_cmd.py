"""posekit interface list|packages|package|show|proto.

Oracles: ROS 2 Jazzy's own interface files in the reference environment (.venv-ros2/share),
read with rosidl_adapter's parser there and expanded the way ``ros2 interface show
--no-comments`` does (nested definitions one tab deeper), normalised only where posekit
documents a difference (constants listed first, no default values); rosidl's generated
classes for ``proto`` (rosidl_runtime_py is not installed there, so the reference YAML is
PyYAML's dump of the default message, which is what message_to_yaml does).
"""

from __future__ import annotations

import io
import json

import pytest

from _support.ros2 import run_ros2_script
from posekit.cli import interface_cmd
from posekit.cli.main import main as posekit_main

SHOWN = [
    "geometry_msgs/msg/Twist", "geometry_msgs/msg/PoseWithCovarianceStamped",
    "geometry_msgs/msg/TransformStamped", "nav_msgs/msg/Odometry", "sensor_msgs/msg/CameraInfo",
    "sensor_msgs/msg/Image", "rcl_interfaces/msg/Log", "action_msgs/msg/GoalStatusArray",
    "std_srvs/srv/SetBool", "std_srvs/srv/Empty", "rcl_interfaces/srv/GetParameters",
    "rcl_interfaces/srv/ListParameters",
]

REFERENCE = """
import json, os, sys
from rosidl_adapter.parser import parse_message_string
share = os.path.join(sys.prefix, "share")

def show(pkg, kind, name, indent, out):
    path = os.path.join(share, pkg, kind, name + "." + kind)
    blocks = [[]]
    for raw in open(path).read().splitlines():
        if raw.strip() == "---":
            blocks.append([])
        else:
            blocks[-1].append(raw)
    for b, block in enumerate(blocks):
        if b:
            out.append("---")
        consts, fields = [], []
        for raw in block:
            spec = parse_message_string(pkg, name, raw)
            for c in spec.constants:
                consts.append(("\\t" * indent + f"{c.type} {c.name}={c.value}", None))
            for f in spec.fields:
                token = raw.split()[0]
                nested = None
                if "/" in str(f.type):
                    npkg, nname = str(f.type).split("[")[0].split("/")
                    nested = (npkg, nname)
                fields.append(("\\t" * indent + f"{token} {f.name}", nested))
        for line, nested in consts + fields:
            out.append(line)
            if nested:
                show(nested[0], "msg", nested[1], indent + 1, out)

result = {}
for full in json.loads(NAMES):
    pkg, kind, name = full.split("/")
    lines = []
    show(pkg, kind, name, 0, lines)
    result[full] = lines
print(json.dumps(result))
"""


def run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    code = interface_cmd.main(argv, out=out, err=err)
    return code, out.getvalue(), err.getvalue()


@pytest.mark.slow
def test_show_matches_ros2_interface_show_no_comments() -> None:
    result = run_ros2_script(f"NAMES = {json.dumps(json.dumps(SHOWN))}\n" + REFERENCE,
                             domain_id=136)
    assert result.returncode == 0, result.stderr
    reference = json.loads(result.stdout)
    assert sorted(reference) == sorted(SHOWN)
    for name, lines in reference.items():
        code, out, err = run(["show", name])
        assert code == 0, err
        assert out.splitlines() == lines, name


def test_show_twist_expands_nested_types_with_tabs() -> None:
    code, out, _ = run(["show", "geometry_msgs/msg/Twist", "--no-comments"])
    assert code == 0
    assert out == ("Vector3 linear\n\tfloat64 x\n\tfloat64 y\n\tfloat64 z\n"
                   "Vector3 angular\n\tfloat64 x\n\tfloat64 y\n\tfloat64 z\n")


def test_proto_prints_the_default_message_in_quotes() -> None:
    code, out, _ = run(["proto", "geometry_msgs/msg/Twist"])
    assert code == 0
    assert out == ('"linear:\n  x: 0.0\n  y: 0.0\n  z: 0.0\n'
                   'angular:\n  x: 0.0\n  y: 0.0\n  z: 0.0\n"\n')
    code, out, _ = run(["proto", "std_srvs/srv/SetBool", "--no-quotes"])
    assert (code, out) == (0, "data: false\n\n")
    # a Jazzy type posekit has no class for (rosbags' class, defaults from the definition)
    code, out, _ = run(["proto", "geometry_msgs/msg/Polygon", "--no-quotes"])
    assert (code, out) == (0, "points: []\n\n")


def test_list_packages_and_package() -> None:
    code, out, _ = run(["list"])
    assert code == 0
    lines = out.splitlines()
    assert lines[0] == "Messages:"
    assert "    geometry_msgs/msg/Twist" in lines
    assert lines.index("Services:") < lines.index("    std_srvs/srv/SetBool") < lines.index(
        "Actions:")
    code, out, _ = run(["list", "-s"])
    assert out.splitlines()[0] == "Services:"
    assert "Messages:" not in out
    code, out, _ = run(["package", "std_srvs"])
    assert out == "std_srvs/srv/Empty\nstd_srvs/srv/SetBool\nstd_srvs/srv/Trigger\n"
    code, out, _ = run(["packages", "-s"])
    services = out.splitlines()
    assert {"rcl_interfaces", "std_srvs"} <= set(services)
    assert "geometry_msgs" not in services
    assert services == sorted(services)
    code, out, _ = run(["packages"])
    assert out.splitlines() == sorted(out.splitlines())
    assert "geometry_msgs" in out.splitlines()


def test_unknown_names_are_one_line_errors() -> None:
    assert run(["show", "foo/msg/Bar"]) == (1, "", "Unknown interface 'foo/msg/Bar'\n")
    code, _, err = run(["show", "Twist"])
    assert code == 1
    assert err.count("\n") == 1
    assert "three parts" in err
    assert run(["package", "nope"]) == (1, "", "Unknown package 'nope'\n")


def test_registered_in_the_posekit_command(capsys: pytest.CaptureFixture[str]) -> None:
    assert posekit_main(["interface", "show", "std_msgs/msg/String"]) == 0
    assert capsys.readouterr().out == "string data\n"
