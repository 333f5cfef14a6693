"""Command-line ROS arguments (``--ros-args``): rclpy.init(args=None), Node(cli_args=...),
remove_ros_args. Oracle: the real ROS 2 Jazzy rclpy, running the same probe script
(tests/runtime/ros_args_probe.py) on the same argument lists; plus rcl's documented value
typing for the unit cases and a real ``python my_node.py --ros-args ...`` process."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Any

import pytest

from _support.differential import run_both
from posekit.runtime.arguments import (
    RCLError,
    UnknownROSArgsError,
    load_parameter_file,
    node_name_matches,
    parse_arguments,
    parse_parameter_value,
    remove_ros_args,
)

PROBE = Path(__file__).with_name("ros_args_probe.py")


def _cases(stdout: str) -> dict[str, dict[str, Any]]:
    cases = {}
    for line in stdout.splitlines():
        if line.startswith("{"):
            case = json.loads(line)
            cases[case.pop("case")] = case
    tmpdir = cases.pop("tmpdir")["dir"]  # the probe's parameter files: same names, other dir
    return json.loads(json.dumps(cases).replace(tmpdir, "<tmpdir>"))


def _normalised(case: dict[str, Any]) -> dict[str, Any]:
    """Drop rcl's source locations and wording after 'Error:'; keep what a user relies on:
    the exception type, rcl's message head (which flag and value failed) and every value."""
    out = dict(case)
    for key in ("init_msg", "node_msg", "msg"):
        if key in out:
            text = out[key].removeprefix("failed to initialize rcl: ")
            text = text.split(". Error:")[0].split(", at /")[0]
            if "[" in text:  # UnknownROSArgsError: compare the list of unknown arguments
                text = text[text.index("["):]
            out[key] = text
    return out


@pytest.mark.slow
def test_argument_forms_match_real_rclpy() -> None:
    reference, ours = run_both(PROBE.read_text(encoding="utf-8"), domain_id=117, timeout=120)
    ref_cases, our_cases = _cases(reference), _cases(ours)
    assert len(ref_cases) > 90
    assert set(our_cases) == set(ref_cases)
    mismatches = {
        name: (_normalised(ref), _normalised(our_cases[name]))
        for name, ref in ref_cases.items()
        if _normalised(ref) != _normalised(our_cases[name])
    }
    assert not mismatches, json.dumps(mismatches, indent=1)[:6000]


# -- units (rcl's documented rules) -------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "value"),
    [("7", 7), ("0x10", 16), ("010", 8), ("-3", -3), ("7.0", 7.0), (".5", 0.5),
     ("1e3", 1000.0), ("true", True), ("Yes", True), ("Y", True), ("off", False),
     ("'7'", "7"), ('"true"', "true"), ("hello", "hello"), ("[1, 2]", [1, 2]),
     ("[a, 'b']", ["a", "b"]), ("1_000", "1_000"), ("99999999999999999999", 1e20)],
)
def test_parameter_values_are_typed_as_rcl_types_them(text: str, value: object) -> None:
    parsed = parse_parameter_value(text)
    assert parsed == value
    assert type(parsed) is type(value)


def test_sections_and_removal() -> None:
    argv = ["prog", "a", "--ros-args", "-p", "x:=1", "-r", "chatter:=/c", "--", "b",
            "--ros-args", "--log-level", "debug", "-e", "/enclave"]
    parsed = parse_arguments(argv)
    assert parsed.unparsed == ["prog", "a", "b"] == remove_ros_args(argv)
    assert parsed.parameters_for("/any") == {"x": 1}
    assert [(r.from_name, r.to_name) for r in parsed.remaps] == [("chatter", "/c")]
    assert parsed.enclave == "/enclave"


@pytest.mark.parametrize(
    ("argv", "error", "head"),
    [(["--ros-args", "-p"], RCLError, "Couldn't parse trailing -p flag"),
     (["--ros-args", "-p", "oops"], RCLError, "Couldn't parse parameter override rule: "
                                              "'-p oops'"),
     (["--ros-args", "-r", "a:=b c"], RCLError, "Couldn't parse remap rule: '-r a:=b c'"),
     (["--ros-args", "--log-level", "loud"], RCLError, "Couldn't parse log level"),
     (["--ros-args", "--params-file", "/nonexistent.yaml"], RCLError,
      "Couldn't parse params file"),
     (["--ros-args", "--bogus", "x"], UnknownROSArgsError, "['--bogus', 'x']")],
)
def test_malformed_arguments_raise_one_clear_error(
    argv: list[str], error: type[Exception], head: str
) -> None:
    with pytest.raises(error) as info:
        parse_arguments(["prog", *argv])
    assert head in str(info.value)
    assert "\n" not in str(info.value)


def test_parameter_file_node_names_and_wildcards(tmp_path: Path) -> None:
    path = tmp_path / "params.yaml"
    path.write_text(textwrap.dedent("""
        /**:
          ros__parameters:
            shared: 1
        robot1:
          controller:
            ros__parameters:
              gains: {k_rho: 0.5, k_alpha: 1.5}
        /*/controller:
          ros__parameters:
            shared: 2
    """), encoding="utf-8")
    entries = dict(load_parameter_file(path))
    assert entries == {"/**": {"shared": 1},
                       "/robot1/controller": {"gains.k_rho": 0.5, "gains.k_alpha": 1.5},
                       "/*/controller": {"shared": 2}}
    parsed = parse_arguments(["prog", "--ros-args", "--params-file", str(path)])
    assert parsed.parameters_for("/robot1/controller") == {
        "shared": 2, "gains.k_rho": 0.5, "gains.k_alpha": 1.5}
    assert parsed.parameters_for("/controller") == {"shared": 1}
    assert node_name_matches("/**/controller", "/a/b/controller")
    assert not node_name_matches("/*/controller", "/a/b/controller")


def test_init_reads_sys_argv_and_use_sim_time_follows_clock(monkeypatch: Any) -> None:
    from posekit import rclpy
    from posekit.rclpy.node import Node

    monkeypatch.setattr(sys, "argv", ["my_node.py", "--ros-args", "-p", "goal_x:=7.0",
                                      "-p", "use_sim_time:=true", "-r", "__node:=renamed"])
    context = rclpy.Context()
    rclpy.init(context=context)
    try:
        node = Node("controller", context=context)
        assert node.get_name() == "renamed"
        assert node.declare_parameter("goal_x", 0.0).value == 7.0
        assert node.get_clock().ros_time_is_active
        assert node.get_clock().now().nanoseconds == 0  # no /clock yet
    finally:
        rclpy.shutdown(context=context)


def test_a_real_process_reads_its_own_ros_args(tmp_path: Path) -> None:
    script = tmp_path / "my_node.py"
    script.write_text(textwrap.dedent("""
        import sys
        from posekit import rclpy
        from posekit.rclpy.node import Node
        from posekit.rclpy.utilities import remove_ros_args

        rclpy.init()
        node = Node("goal_node")
        goal = node.declare_parameter("goal_x", 5.0)
        print(node.get_fully_qualified_name(), goal.type_.name, goal.value,
              node.resolve_topic_name("cmd_vel"), remove_ros_args()[1:])
        rclpy.shutdown()
    """), encoding="utf-8")
    env = {k: v for k, v in os.environ.items() if not k.startswith("POSEKIT_")}
    result = subprocess.run(
        [sys.executable, str(script), "extra", "--ros-args", "-p", "goal_x:=7.0",
         "-r", "__ns:=/robot1", "-r", "cmd_vel:=/remote/cmd_vel"],
        env=env, capture_output=True, text=True, timeout=60, stdin=subprocess.DEVNULL,
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.split() == ["/robot1/goal_node", "DOUBLE", "7.0",
                                     "/remote/cmd_vel", "['extra']"]


def test_bad_arguments_in_a_real_process_fail_with_one_line(tmp_path: Path) -> None:
    script = tmp_path / "my_node.py"
    script.write_text("from posekit import rclpy\nrclpy.init()\n", encoding="utf-8")
    result = subprocess.run(
        [sys.executable, str(script), "--ros-args", "-p", "goal_x"],
        capture_output=True, text=True, timeout=60, stdin=subprocess.DEVNULL,
    )
    assert result.returncode != 0
    assert "Couldn't parse parameter override rule: '-p goal_x'" in result.stderr
