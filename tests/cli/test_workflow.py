"""The two-terminal ROS workflow: a launch in one process, tools and demos in others (Zenoh;
the graph listings also over DDS).

Oracles, each independent of what the tools print:

* the graph a launch must show: the same scenario built in this test process on the
  isolated in-process bus (its nodes and the topics its bus carries), with no network;
* the P controller demo started against a running world: the world's ``/ground_truth/odom``
  (the simulator's true pose, read by a separate tool process) must be within the
  controller's documented position tolerance (0.10 m) of the commanded goal, and the
  world's ``/clock`` must still have exactly one publisher (the demo owns no clock).

Every process is started on a fresh loopback router endpoint and killed at the end; every
wait is bounded.
"""

from __future__ import annotations

import io
import math
import re
import socket
import sys
import time

import pytest
import yaml

from _support.procs import Proc
from _support.world import World

pytestmark = pytest.mark.slow


def expected_graph(scenario: str) -> tuple[set[str], set[str]]:
    """(node names, topic names) of ``scenario`` as ``posekit launch`` runs it, built here on
    the isolated in-process bus."""
    import posekit.demos.scenarios  # noqa: F401 - registers every scenario
    from posekit.launch.scenarios import start_scenario

    run = start_scenario(scenario, {}, 0, publish_clock=True,
                         transport="inprocess")
    try:
        run.executor.run_until(0.1)  # creates the /clock publisher
        nodes = {n.get_fully_qualified_name() for n in run.nodes}
        clock_node = run.executor._clock_node  # the executor's own /clock publisher node
        assert clock_node is not None
        nodes.add(clock_node.get_fully_qualified_name())
        # as `topic list` shows them: hidden ones (an action's /_action/ topics) left out
        from posekit.cli.topic_cmd import is_hidden_name

        topics = {name for name, _ in run.context.transport().get_topic_names_and_types()
                  if not is_hidden_name(name)}
    finally:
        run.shutdown()
    return nodes, topics


def list_once(transport: str = "zenoh") -> tuple[set[str], set[str], str]:
    """``topic list`` and ``node list`` as one fresh CLI invocation would run them (a new
    context and Zenoh session or DDS participant, in this process to save the interpreter
    start)."""
    from posekit.cli import node_cmd, topic_cmd
    from posekit.runtime.context import Context

    ctx = Context()
    ctx.init(transport=transport)
    try:
        topics_out, nodes_out, err = io.StringIO(), io.StringIO(), io.StringIO()
        assert topic_cmd.main_list([], context=ctx, out=topics_out, err=err) == 0
        assert node_cmd.main_list([], context=ctx, out=nodes_out, err=err) == 0
    finally:
        ctx.shutdown()
    return set(topics_out.getvalue().split()), set(nodes_out.getvalue().split()), err.getvalue()


def wait_for_router(endpoint: str, timeout: float) -> None:
    """Until the launch hosts the router on ``endpoint`` (a tool started earlier would host
    its own and take it away when it exits)."""
    host, _, port = endpoint.removeprefix("tcp/").rpartition(":")
    deadline = time.monotonic() + timeout
    while True:
        try:
            socket.create_connection((host, int(port)), timeout=0.2).close()
            return
        except OSError:
            if time.monotonic() > deadline:
                raise AssertionError(f"nothing listens on {endpoint} after {timeout} s") from None
            time.sleep(0.1)


def wait_for_graph(nodes: set[str], topics: set[str], timeout: float,
                   transport: str = "zenoh") -> None:
    deadline = time.monotonic() + timeout
    while True:
        got_topics, got_nodes, _ = list_once(transport)
        if nodes <= got_nodes and topics <= got_topics:
            return
        if time.monotonic() > deadline:
            raise AssertionError(f"the launch never showed up: missing nodes "
                                 f"{nodes - got_nodes}, topics {topics - got_topics}")
        time.sleep(0.2)


def test_graph_listings_are_complete_in_100_of_100_runs(joined: World) -> None:
    nodes, topics = expected_graph("p_controller")
    assert {"/world_simulation", "/ekf_node", "/p_controller"} <= nodes
    assert {"/cmd_vel", "/odometry/filtered", "/tf", "/clock"} <= topics
    launch = joined.cli("launch", "p_controller", "--realtime")
    wait_for_router(joined.endpoint, 40)
    wait_for_graph(nodes, topics, 40)

    failures = []
    for i in range(100):
        got_topics, got_nodes, err = list_once()
        if got_topics != topics or got_nodes != nodes:
            failures.append((i, topics - got_topics, nodes - got_nodes,
                             got_topics - topics, got_nodes - nodes, err))
    assert not failures, f"{len(failures)} of 100 incomplete: {failures[:3]}"

    # A few real command-line processes, as a user types them.
    topic_list = joined.cli("topic", "list").finish(30, "topic list")
    assert set(topic_list.split()) == topics
    node_list = joined.cli("node", "list").finish(30, "node list")
    assert set(node_list.split()) == nodes
    for topic in ("/odometry/filtered", "/cmd_vel", "/tf_static"):
        info = joined.cli("topic", "info", topic)
        text = info.finish(30, f"topic info {topic}")
        assert info.popen.returncode == 0, info.describe()
        assert "Publisher count: 1" in text, info.describe()
    echo = joined.cli("topic", "echo", "/odometry/filtered", "--once")
    assert "frame_id: odom" in echo.finish(30, "topic echo --once")
    assert not any("does not appear to be published" in line for line in echo.err), (
        echo.describe())
    assert launch.popen.poll() is None, launch.describe()


def test_graph_listings_over_dds_are_complete_in_30_of_30_runs(
        monkeypatch: pytest.MonkeyPatch) -> None:
    pytest.importorskip("cyclonedds")
    from _support.dds import dds_domain, posekit_env

    domain = dds_domain(monkeypatch)
    nodes, topics = expected_graph("p_controller")
    cli = [sys.executable, "-m", "posekit.cli.main"]
    launch = Proc([*cli, "launch", "p_controller", "--transport", "dds", "--realtime"],
                  posekit_env(domain))
    try:
        wait_for_graph(nodes, topics, 60, "dds")
        failures = []
        for i in range(30):
            got_topics, got_nodes, err = list_once("dds")
            if got_topics != topics or got_nodes != nodes:
                failures.append((i, topics - got_topics, nodes - got_nodes,
                                 got_topics - topics, got_nodes - nodes, err))
        assert not failures, f"{len(failures)} of 30 incomplete: {failures[:3]}"
        # real command-line processes, as a user types them
        topic_list = Proc([*cli, "topic", "list"], posekit_env(domain))
        assert set(topic_list.finish(30, "topic list").split()) == topics
        node_list = Proc([*cli, "node", "list"], posekit_env(domain))
        assert set(node_list.finish(30, "node list").split()) == nodes
        assert launch.popen.poll() is None, launch.describe()
    finally:
        launch.kill()


def test_empty_graph_prints_one_hint_line(joined: World) -> None:
    # Nothing runs on this endpoint: the listing is empty and says what to check.
    topics, nodes, err = list_once()
    assert topics <= {"/parameter_events", "/rosout"}  # the tool node's own, as in ROS 2
    assert nodes == set()
    lines = err.splitlines()
    assert len(lines) == 2, err  # one per tool
    assert all(joined.endpoint in line and "ROS_DOMAIN_ID" in line for line in lines), err


def ground_truth(joined: World) -> tuple[float, float]:
    echo = joined.cli("topic", "echo", "/ground_truth/odom", "--once")
    doc = yaml.safe_load(echo.finish(30, "echo ground truth").split("---")[0])
    position = doc["pose"]["pose"]["position"]
    return float(position["x"]), float(position["y"])


def test_p_controller_demo_reaches_its_goal_against_a_world_in_another_process(
    joined: World,
) -> None:
    world = joined.cli("launch", "rosbot_gazebo", "empty_world.launch.py", "--realtime")
    world.wait_stderr("[world_simulation]", 40, "the world to start")
    goal = (1.0, 0.5)
    demo = joined.cli("launch", "robot_control_demo", "p_controller.launch.py",
                         f"goal_x:={goal[0]}", "--until-sim-time", "200", f"goal_y:={goal[1]}",
                         "goal_yaw:=0.0")
    demo.wait_stderr("Goal reached", 90, "the P controller to reach its goal")
    x, y = ground_truth(joined)
    assert math.hypot(x - goal[0], y - goal[1]) < 0.10 + 0.02, (x, y)
    # One clock in the system: the world's.
    info = joined.cli("topic", "info", "/clock").finish(30, "topic info /clock")
    assert re.search(r"Publisher count: 1\b", info), info
    assert world.popen.poll() is None, world.describe()
    assert demo.popen.poll() is None, demo.describe()
    assert not any("Rejected cmd_vel" in line for line in world.err), world.describe()


def test_a_demo_without_a_world_waits_and_says_what_is_missing(joined: World) -> None:
    demo = joined.cli("run", "robot_control_demo", "random_mover")
    demo.wait_stderr("no /clock yet", 40, "the hint that no world runs")
    hint = [line for line in demo.err if "no /clock yet" in line]
    assert len(hint) == 1, demo.describe()
    assert "posekit launch empty_world --realtime" in hint[0]
    # It follows a clock, it does not make one: nothing publishes /clock.
    info = joined.cli("topic", "info", "/clock")
    text = info.finish(30, "topic info /clock")
    assert "Publisher count: 1" not in text, info.describe()
    assert demo.popen.poll() is None, demo.describe()


def test_run_gives_its_node_the_ros_args_of_the_command_line(joined: World) -> None:
    # Oracle: rcl's rules for a process's --ros-args (checked against the real rclpy in
    # tests/runtime/test_launch.py), seen from other processes: the node's name, its
    # parameters (the file's wildcard section, then -p) and its remapped topic.
    params = joined.tmp / "mover.yaml"
    params.write_text("/r/*:\n  ros__parameters:\n    publish_rate: 4.0\n    seed: 99\n"
                      "/other/mover:\n  ros__parameters:\n    publish_rate: 9.0\n")
    demo = joined.cli("run", "robot_control_demo", "random_mover", "--ros-args",
                      "-r", "__ns:=/r", "-r", "__node:=mover", "-r", "cmd_vel:=/r_cmd",
                      "--params-file", str(params), "-p", "seed:=7", "--log-level", "warn")
    demo.wait_stderr("no /clock yet", 40, "the demo's node to be up (waiting for a world)")
    dump = joined.cli("param", "dump", "/r/mover", "--timeout", "10")
    dumped = yaml.safe_load(dump.finish(30, "param dump"))
    assert dumped == {"/r/mover": {"ros__parameters": {
        "publish_rate": 4.0, "seed": 7, "use_sim_time": True,
        "start_type_description_service": True}}}, dump.describe()
    info = joined.cli("node", "info", "/r/mover").finish(30, "node info")
    assert "    /r_cmd: geometry_msgs/msg/TwistStamped\n" in info, info
    assert "    /r/odometry/filtered: nav_msgs/msg/Odometry\n" in info, info
    assert demo.popen.poll() is None, demo.describe()
