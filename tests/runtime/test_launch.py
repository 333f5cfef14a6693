"""posekit.launch: descriptions with names, namespaces, parameters, remappings; launch files."""

from __future__ import annotations

import textwrap

import pytest

from posekit.launch import (
    DeclareLaunchArgument,
    LaunchConfiguration,
    LaunchDescription,
    LaunchDescriptionError,
    Node,
    launch,
    main,
    run_launch_file,
    start,
)
from posekit.msgs.rosgraph_msgs import Clock
from posekit.msgs.std_msgs import Float64
from posekit.runtime.node import Node as RosNode

RECEIVED: list[tuple[str, float, int]] = []


class Talker(RosNode):
    """Hard-codes its name like lecture nodes do; publishes its 'value' parameter."""

    def __init__(self) -> None:
        super().__init__("talker")
        self.value = self.declare_parameter("value", 1.0).value
        self.pub = self.create_publisher(Float64, "out", 10)
        self.create_timer(0.5, lambda: self.pub.publish(Float64(data=self.value)))


class Sink(RosNode):
    def __init__(self) -> None:
        super().__init__("sink")
        self.create_subscription(
            Float64, "in",
            lambda m: RECEIVED.append((self.get_fully_qualified_name(), m.data,
                                       self.get_clock().now().nanoseconds)), 10)


def test_description_applies_names_parameters_remappings() -> None:
    RECEIVED.clear()
    description = LaunchDescription([
        DeclareLaunchArgument("v", default_value=2.5),
        Node(Talker, name="renamed_talker", namespace="robot",
             parameters=[{"value": LaunchConfiguration("v")}], remappings=[("out", "/data")]),
        Node(f"{__name__}:Sink", remappings=[("in", "/data")]),
    ])
    run = start(description, launch_arguments={"v": 4.0})
    talker = run.node("renamed_talker")
    assert talker.get_fully_qualified_name() == "/robot/renamed_talker"
    assert talker.get_parameter("value").value == 4.0
    assert talker.get_parameter("use_sim_time").value is True
    run.executor.run_for(1.0)  # type: ignore[attr-defined]
    run.shutdown()
    assert RECEIVED == [("/sink", 4.0, 500_000_000), ("/sink", 4.0, 1_000_000_000)]


def test_launch_file_and_cli_entry(tmp_path) -> None:
    RECEIVED.clear()
    path = tmp_path / "demo.launch.py"
    path.write_text(textwrap.dedent(f"""
        from posekit.launch import LaunchDescription, Node
        from {__name__} import Sink, Talker

        def generate_launch_description():
            return LaunchDescription([
                Node(Talker, parameters=[{{"value": 7.0}}], remappings=[("out", "/in")]),
                Node(Sink),
            ])
    """))
    run = run_launch_file(path, duration=2.0)
    assert not run.context.ok()  # shut down after the run
    assert [r[1] for r in RECEIVED] == [7.0] * 4
    RECEIVED.clear()
    assert main([str(path), "--duration", "1.0"]) == 0
    assert len(RECEIVED) == 2
    assert main([str(tmp_path / "missing.py")]) == 2


def test_bad_descriptions_are_clear_errors(tmp_path) -> None:
    with pytest.raises(LaunchDescriptionError, match=r"posekit\.launch Node"):
        LaunchDescription(["not a node"])  # type: ignore[list-item]
    with pytest.raises(LaunchDescriptionError, match="did not return a posekit Node"):
        launch(LaunchDescription([Node(lambda: 42)]), duration=0.1)
    with pytest.raises(LaunchDescriptionError, match="cannot import"):
        Node("no_such_module_xyz:Thing").factory()
    bad = tmp_path / "bad.py"
    bad.write_text("x = 1\n")
    with pytest.raises(LaunchDescriptionError, match="generate_launch_description"):
        run_launch_file(bad)


def test_start_publish_clock_switch() -> None:
    description = LaunchDescription([Node(Talker)])
    quiet = start(description, publish_clock=False)
    loud = start(description, publish_clock=True)
    try:
        stamps: list[int] = []
        for run in (quiet, loud):
            observer = RosNode("observer", context=run.context)
            observer.create_subscription(
                Clock, "/clock",
                lambda m: stamps.append(m.clock.sec * 10**9 + m.clock.nanosec), 10
            )
            run.executor.add_node(observer)
            run.executor.run_until(2.0)  # type: ignore[attr-defined]
            run.nodes.append(observer)
        assert quiet.executor.publish_clock is False  # type: ignore[attr-defined]
        # Only the run that publishes: one /clock per step of the 0.5 s timer.
        assert stamps == [500_000_000, 1_000_000_000, 1_500_000_000, 2_000_000_000]
    finally:
        quiet.shutdown()
        loud.shutdown()


RUN_PARAMS = """\
/r/*:
  ros__parameters:
    value: 3.0
    gain: 5
/talker:
  ros__parameters:
    value: 9.0
"""

#: What the reference reports: a node created as ``Node("talker")`` in a process started
#: with these ROS arguments (``ros2 run`` hands its ``--ros-args`` to the process).
ROS_RUN_PROBE = """
import json, sys
import rclpy
from rclpy.node import Node
rclpy.init(args=["probe", *json.loads(sys.argv[1])])
node = Node("talker")
print(json.dumps({
    "fqn": node.get_fully_qualified_name(),
    "value": node.declare_parameter("value", 1.0).value,
    "gain": node.declare_parameter("gain", 1).value,
    "out": node.resolve_topic_name("out"),
    "warn_only": int(node.get_logger().get_effective_level()),
}))
rclpy.shutdown()
"""


class RunProbe(RosNode):
    """The reference probe's node: hard-codes its name, declares two parameters."""

    def __init__(self) -> None:
        super().__init__("talker")
        self.value = self.declare_parameter("value", 1.0).value
        self.gain = self.declare_parameter("gain", 1).value


def test_start_gives_every_node_the_runs_ros_arguments_as_ros2_run_does(tmp_path) -> None:
    import json
    import subprocess

    from _support.dds import free_domain
    from _support.ros2 import ros2_env, ros2_python
    from posekit.runtime.arguments import parse_arguments
    from posekit.runtime.logging import LoggingSeverity, set_logger_level

    params = tmp_path / "run.yaml"
    params.write_text(RUN_PARAMS)
    args = ["--ros-args", "-r", "__ns:=/r", "-r", "__node:=mover", "-r", "out:=/elsewhere",
            "--params-file", str(params), "-p", "gain:=7", "--log-level", "r.mover:=warn"]
    reference = subprocess.run(
        [str(ros2_python()), "-c", ROS_RUN_PROBE, json.dumps(args)],
        env=ros2_env(free_domain()), capture_output=True, text=True, timeout=60,
        stdin=subprocess.DEVNULL)
    assert reference.returncode == 0, reference.stderr
    expected = json.loads(reference.stdout)
    # the launch's own name and parameter are what the run's arguments override
    run = start(LaunchDescription([Node(RunProbe, name="launch_name",
                                        parameters=[{"value": 0.5}])]),
                arguments=parse_arguments(args))
    try:
        node = run.nodes[0]
        assert isinstance(node, RunProbe)
        ours = {"fqn": node.get_fully_qualified_name(), "value": node.value,
                "gain": node.gain, "out": node.resolve_topic_name("out"),
                "warn_only": int(node.get_logger().get_effective_level())}
    finally:
        run.shutdown()
        set_logger_level("r.mover", LoggingSeverity.UNSET)
    assert ours == expected
    assert expected["fqn"] == "/r/mover"  # the probe really exercised the arguments


LAUNCH_PARAMS = """\
/**:
  ros__parameters:
    everywhere: 1
    shadowed: 1
    under: 1_000
/ns1/*:
  ros__parameters:
    in_ns1: true
a:
  ros__parameters:
    root_a: 2
/*:
  ros__parameters:
    root_only: x
/ns2/talker:
  ros__parameters:
    shadowed: 3
    nested:
      gain: 0.5
/b:
  ros__parameters:
    b_only: [1, 2]
"""

#: Each launch entry's node as rcl sees it: its name and namespace, and the --params-file
#: arguments launch_ros gives it (a dict goes into a file of its own, under the node's
#: fully qualified name when name and namespace are both given, else under /**).
ROS_PARAMS_PROBE = """
import json, sys
import rclpy
from rclpy.node import Node
rclpy.init(args=[])
for case in json.loads(sys.argv[1]):
    args = ["--ros-args"] + [a for f in case["files"] for a in ("--params-file", f)]
    node = Node(case["name"], namespace=case["ns"], cli_args=args,
                automatically_declare_parameters_from_overrides=True)
    print(json.dumps({n: p.value if not hasattr(p.value, "tolist") else p.value.tolist()
                      for n, p in sorted(node.get_parameters_by_prefix("").items())
                      if n != "use_sim_time"}))
    node.destroy_node()
rclpy.shutdown()
"""


class ParamsProbe(RosNode):
    """A node that hard-codes its name and takes every parameter it is given."""

    def __init__(self) -> None:
        super().__init__("talker", automatically_declare_parameters_from_overrides=True)


def test_parameter_files_reach_nodes_by_fully_qualified_name_as_rcl_matches_them(
        tmp_path) -> None:
    import json
    import subprocess

    import yaml

    from _support.dds import free_domain
    from _support.ros2 import ros2_env, ros2_python

    params = tmp_path / "params.yaml"
    params.write_text(LAUNCH_PARAMS)
    override = {"shadowed": 9}

    def dict_file(key: str) -> str:  # launch_ros's file for a dict
        path = tmp_path / f"dict_{len(list(tmp_path.iterdir()))}.yaml"
        path.write_text(yaml.safe_dump({key: {"ros__parameters": override}}))
        return str(path)

    entries = [  # (launch entry, what rcl is given for its node)
        (Node(ParamsProbe, name="a", namespace="ns1", parameters=[params, override]),
         {"name": "a", "ns": "/ns1", "files": [str(params), dict_file("/ns1/a")]}),
        (Node(ParamsProbe, parameters=[override, str(params)]),
         {"name": "talker", "ns": "/", "files": [dict_file("/**"), str(params)]}),
        (Node(ParamsProbe, namespace="/ns2", parameters=[params]),
         {"name": "talker", "ns": "/ns2", "files": [str(params)]}),
        (Node(ParamsProbe, name="b", parameters=[params]),
         {"name": "b", "ns": "/", "files": [str(params)]}),
    ]
    reference = subprocess.run(
        [str(ros2_python()), "-c", ROS_PARAMS_PROBE, json.dumps([e[1] for e in entries])],
        env=ros2_env(free_domain()), capture_output=True, text=True, timeout=60,
        stdin=subprocess.DEVNULL)
    assert reference.returncode == 0, reference.stderr
    expected = [json.loads(line) for line in reference.stdout.splitlines()]
    run = start(LaunchDescription([e[0] for e in entries]))
    try:
        ours = [{n: p.value for n, p in sorted(node.get_parameters_by_prefix("").items())
                 if n != "use_sim_time"} for node in run.nodes]
        assert [n.get_fully_qualified_name() for n in run.nodes] == [
            "/ns1/a", "/talker", "/ns2/talker", "/b"]
    finally:
        run.shutdown()
    assert ours == expected
    assert expected[2]["nested.gain"] == 0.5  # the probe saw the sections it should
    assert expected[1]["shadowed"] == 1
    assert expected[0]["shadowed"] == 9
