"""posekit's command-line tools with ``--transport dds`` on a real ROS 2 Jazzy system.

Oracles: real rclpy publishers (Fast DDS) with known content, rate, node name and QoS, and a
real rclpy subscription for ``topic pub``; the bag is read back with rosbags (not posekit's
reader).
"""

from __future__ import annotations

import io
import json
import re
import sys
import textwrap
import threading
from pathlib import Path
from typing import Any

import pytest

from _support.dds import dds_context, dds_domain, posekit_env
from _support.procs import Proc
from _support.ros2 import ros2_env, ros2_python

pytestmark = pytest.mark.slow

TALKER = textwrap.dedent("""
    import sys, time
    import rclpy
    from rclpy.qos import DurabilityPolicy, QoSProfile
    from nav_msgs.msg import Odometry
    from sensor_msgs.msg import NavSatFix
    from std_msgs.msg import String
    rclpy.init()
    node = rclpy.create_node("ros_talker", namespace="/robot")
    chatter = node.create_publisher(String, "/chatter", 10)
    odom = node.create_publisher(
        Odometry, "odom", QoSProfile(depth=5, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    i = 0
    def tick():
        global i
        chatter.publish(String(data=f"hello {i}"))
        msg = Odometry()
        msg.header.frame_id, msg.child_frame_id = "odom", "base_link"
        msg.pose.pose.position.x = 0.5 * i
        odom.publish(msg)
        i += 1
    node.create_timer(0.05, tick)  # 20 Hz
    node.create_subscription(String, "/from_cli", lambda m: print(f"heard: {m.data}",
                                                                  flush=True), 10)
    node.create_subscription(NavSatFix, "/fix_from_cli", lambda m: print(
        f"fix: {m.latitude} {m.status.status} {m.status.service}", flush=True), 10)
    print("ready", flush=True)
    deadline = time.monotonic() + float(sys.argv[1])
    while time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.1)
    rclpy.shutdown()
""")


def _cli(domain: int, *args: str) -> Proc:
    return Proc([sys.executable, "-m", "posekit.cli.main", *args], env=posekit_env(domain))


def test_topic_node_and_bag_tools_on_real_rclpy_publishers(
        monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    from rosbags.highlevel import AnyReader

    from posekit.cli import topic_cmd

    domain = dds_domain(monkeypatch)
    talker = Proc([str(ros2_python()), "-c", TALKER, "40"], env=ros2_env(domain))
    context = dds_context()
    try:
        talker.wait_line(lambda line: line.startswith("ready"), 30, "the talker")
        # separate processes, as a user runs them (discovery from a cold start)
        topics = _cli(domain, "topic", "list", "-t", "--transport", "dds")
        nodes = _cli(domain, "node", "list", "--transport", "dds")
        echo = _cli(domain, "topic", "echo", "/chatter", "--once", "--transport", "dds")
        bag_dir = tmp_path / "real_bag"
        bag = _cli(domain, "bag", "record", "/chatter", "/robot/odom", "-o", str(bag_dir),
                   "--duration", "3", "--transport", "dds")
        topic_text = topics.finish(30, "topic list")
        node_text = nodes.finish(30, "node list")
        echo_text = echo.finish(30, "topic echo")
        bag.finish(40, "bag record")
        # topic pub --once waits for the real subscription, then its one message arrives
        pub = _cli(domain, "topic", "pub", "--once", "/from_cli", "std_msgs/msg/String",
                   "{data: from posekit}", "--transport", "dds")
        pub.finish(30, "topic pub")
        talker.wait_line(lambda line: line.startswith("heard:"), 15, "the talker hearing it")
        # a type posekit has no class for: its Jazzy definition, ROS defaults (status -2)
        fix = _cli(domain, "topic", "pub", "--once", "/fix_from_cli", "sensor_msgs/msg/NavSatFix",
                   "{latitude: 1.5, status: {service: 1}}", "--transport", "dds")
        fix.finish(30, "topic pub of a NavSatFix")
        talker.wait_line(lambda line: line.startswith("fix:"), 15, "the talker hearing the fix")
        # in this process: hz and info -v
        hz_out, info_out = io.StringIO(), io.StringIO()
        assert topic_cmd.main_hz(["/chatter", "--count", "3", "-w", "15"], context=context,
                                 out=hz_out, timeout_s=20) == 0
        assert topic_cmd.main_info(["/robot/odom", "-v"], context=context, out=info_out) == 0
        # bad input: an unknown topic on the DDS graph is one line, not a traceback
        err = io.StringIO()
        assert topic_cmd.main_info(["/nope"], context=context, out=io.StringIO(),
                                   err=err) == 1
    finally:
        talker.kill()
        context.try_shutdown()

    assert "/chatter [std_msgs/msg/String]" in topic_text.splitlines()
    assert "/robot/odom [nav_msgs/msg/Odometry]" in topic_text.splitlines()
    assert "/robot/ros_talker" in node_text.splitlines()
    assert re.search(r"^data: hello \d+$", echo_text, re.MULTILINE), echo_text
    assert "heard: from posekit\n" in talker.out
    assert "fix: 1.5 -2 1\n" in talker.out
    rates = [float(m) for m in re.findall(r"average rate: ([0-9.]+)", hz_out.getvalue())]
    assert len(rates) == 3, hz_out.getvalue()
    # the talker's 20 Hz timer, over the last 15 messages (the first report may include a
    # start-up bunch when the machine is busy)
    assert 14.0 < rates[-1] < 28.0, rates
    info = info_out.getvalue()
    assert "Type: nav_msgs/msg/Odometry" in info
    assert "Publisher count: 1" in info
    assert "Node name: ros_talker" in info
    assert "Node namespace: /robot" in info
    assert "Durability: TRANSIENT_LOCAL" in info
    assert "History (Depth): UNKNOWN" in info  # RTPS discovery does not carry it (as ROS 2)
    assert re.search(r"Topic type hash: RIHS01_[0-9a-f]{64}", info), info
    assert re.search(r"GID: ([0-9a-f]{2}\.){15}[0-9a-f]{2}", info), info
    assert err.getvalue().strip() == "Unknown topic '/nope'"
    with AnyReader([bag_dir]) as reader:
        counts = {c.topic: c.msgcount for c in reader.connections}
        texts = [reader.deserialize(raw, c.msgtype).data
                 for c, _t, raw in reader.messages() if c.topic == "/chatter"]
        xs = [reader.deserialize(raw, c.msgtype).pose.pose.position.x
              for c, _t, raw in reader.messages() if c.topic == "/robot/odom"]
    assert counts["/chatter"] >= 20, counts
    assert counts["/robot/odom"] >= 20, counts
    numbers = [int(t.split()[1]) for t in texts]
    assert numbers == sorted(numbers)
    assert len(set(numbers)) == len(numbers)
    assert all(x == pytest.approx(0.5 * round(x / 0.5)) for x in xs)


ROS_INFO_NODE = textwrap.dedent("""
    import json, sys, time
    import rclpy
    from std_msgs.msg import String
    from std_srvs.srv import SetBool
    rclpy.init()
    node = rclpy.create_node("ros_info", namespace="/robot")
    node.create_publisher(String, "chatter", 10)
    node.create_subscription(String, "/cmd", lambda m: None, 10)
    node.create_service(SetBool, "flip", lambda q, r: r)
    node.create_client(SetBool, "/remote_flip")
    rclpy.spin_once(node, timeout_sec=0.2)
    # what ros2node's get_node_info asks rclpy for, for this node: the oracle
    by_node = {
        "Subscribers": node.get_subscriber_names_and_types_by_node,
        "Publishers": node.get_publisher_names_and_types_by_node,
        "Service Servers": node.get_service_names_and_types_by_node,
        "Service Clients": node.get_client_names_and_types_by_node,
    }
    print(json.dumps({title: sorted([n, sorted(t)] for n, t in get("ros_info", "/robot"))
                      for title, get in by_node.items()}), flush=True)
    deadline = time.monotonic() + float(sys.argv[1])
    while time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.1)
    rclpy.shutdown()
""")

POSEKIT_INFO_NODE = textwrap.dedent("""
    import sys, time
    from posekit import rclpy
    from posekit.msgs.posekit_interfaces import NavigateToPose
    from posekit.msgs.std_msgs import String
    from posekit.msgs.std_srvs import SetBool
    from posekit.rclpy.action import ActionClient, ActionServer
    from posekit.rclpy.node import Node
    rclpy.init()
    node = Node("pk_info", namespace="/robot")
    node.create_publisher(String, "chatter", 10)
    node.create_subscription(String, "/cmd", lambda m: None, 10)
    node.create_service(SetBool, "flip", lambda q, r: r)
    node.create_client(SetBool, "/remote_flip")
    ActionServer(node, NavigateToPose, "navigate", lambda goal: NavigateToPose.Result())
    ActionClient(node, NavigateToPose, "/elsewhere")
    print("ready", flush=True)
    deadline = time.monotonic() + float(sys.argv[1])
    while time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.1)
""")


def _sections(text: str) -> dict[str, list[list[Any]]]:
    """``node info``'s output as {section title: [[name, [types]], ...]}."""
    sections: dict[str, list[list[Any]]] = {}
    current: list[list[Any]] = []
    for line in text.splitlines()[1:]:
        if line.startswith("  ") and not line.startswith("    "):
            current = sections.setdefault(line.strip().rstrip(":"), [])
        elif line.strip():
            name, _, types = line.strip().partition(": ")
            current.append([name, sorted(types.split(", "))])
    return sections


def test_node_info_lists_a_real_rclpy_node_and_a_posekit_node_over_dds(
        monkeypatch: pytest.MonkeyPatch) -> None:
    domain = dds_domain(monkeypatch)
    ros_node = Proc([str(ros2_python()), "-c", ROS_INFO_NODE, "60"], env=ros2_env(domain))
    pk_node = Proc([sys.executable, "-c", POSEKIT_INFO_NODE, "60"], env=posekit_env(domain))
    try:
        oracle = json.loads(ros_node.wait_line(lambda line: line.startswith("{"), 30,
                                               "the rclpy node's own graph view"))
        pk_node.wait_line(lambda line: line.startswith("ready"), 30, "the posekit node")
        ros_info = _cli(domain, "node", "info", "/robot/ros_info", "--include-hidden",
                        "--transport", "dds")
        pk_info = _cli(domain, "node", "info", "/robot/pk_info", "--transport", "dds")
        ros_text = ros_info.finish(30, "node info of the rclpy node")
        pk_text = pk_info.finish(30, "node info of the posekit node")
    finally:
        ros_node.kill()
        pk_node.kill()
    assert ros_info.popen.returncode == 0, ros_info.describe()
    assert ros_text.startswith("/robot/ros_info\n")
    sections = _sections(ros_text)
    for title, expected in oracle.items():
        assert sections[title] == expected, (title, ros_text)
    assert sections["Action Servers"] == sections["Action Clients"] == []
    assert pk_info.popen.returncode == 0, pk_info.describe()
    parameter_services = "".join(
        f"    /robot/pk_info/{name}: {kind}\n" for name, kind in (
            ("describe_parameters", "rcl_interfaces/srv/DescribeParameters"),
            ("get_parameter_types", "rcl_interfaces/srv/GetParameterTypes"),
            ("get_parameters", "rcl_interfaces/srv/GetParameters"),
            ("get_type_description", "type_description_interfaces/srv/GetTypeDescription"),
            ("list_parameters", "rcl_interfaces/srv/ListParameters"),
            ("set_parameters", "rcl_interfaces/srv/SetParameters"),
            ("set_parameters_atomically", "rcl_interfaces/srv/SetParametersAtomically")))
    assert pk_text == (
        "/robot/pk_info\n"
        "  Subscribers:\n    /cmd: std_msgs/msg/String\n"
        "  Publishers:\n    /parameter_events: rcl_interfaces/msg/ParameterEvent\n"
        "    /robot/chatter: std_msgs/msg/String\n    /rosout: rcl_interfaces/msg/Log\n"
        "  Service Servers:\n    /robot/flip: std_srvs/srv/SetBool\n" + parameter_services +
        "  Service Clients:\n    /remote_flip: std_srvs/srv/SetBool\n"
        "  Action Servers:\n    /robot/navigate: posekit_interfaces/action/NavigateToPose\n"
        "  Action Clients:\n    /elsewhere: posekit_interfaces/action/NavigateToPose\n"
    ), pk_info.describe()


def test_node_lookups_wait_for_a_node_discovered_late(monkeypatch: pytest.MonkeyPatch) -> None:
    """``node info`` and ``param list NODE`` wait for a node that is not on the graph yet.

    The node is created only after the tool's first graph sync returned, which is when the
    tools used to decide (and say "not found").
    """
    from posekit.cli import node_cmd, param_cmd
    from posekit.runtime.executors import SingleThreadedExecutor
    from posekit.runtime.node import Node

    dds_domain(monkeypatch)
    tool_context, node_context = dds_context(), dds_context()
    tool_transport = tool_context.transport()
    synced = threading.Event()
    real_sync = tool_transport.sync_graph

    def sync_then_tell(timeout: float = 2.0) -> int:
        generation = real_sync(timeout)
        synced.set()
        return generation

    monkeypatch.setattr(tool_transport, "sync_graph", sync_then_tell)
    results: dict[str, tuple[int, str, str]] = {}

    def run_tool(name: str, main: Any, argv: list[str]) -> None:
        out, err = io.StringIO(), io.StringIO()
        results[name] = (main(argv, context=tool_context, out=out, err=err),
                         out.getvalue(), err.getvalue())

    executor = SingleThreadedExecutor(context=node_context)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    try:
        for name, main, node_name in (("info", node_cmd.main_info, "talker"),
                                      ("param", param_cmd.main_list, "listener")):
            synced.clear()
            tool = threading.Thread(target=run_tool, args=(name, main, [f"/late/{node_name}"]))
            tool.start()
            assert synced.wait(30), "the tool never synced its graph"
            # the node appears once the tool has looked
            node = Node(node_name, namespace="/late", context=node_context)
            node.declare_parameter("rate", 2.0)
            executor.add_node(node)
            tool.join(60)
            assert not tool.is_alive()
    finally:
        executor.shutdown()
        spinner.join(5)
        node_context.try_shutdown()
        tool_context.try_shutdown()
    code, out, err = results["info"]
    assert (code, err) == (0, ""), out
    assert out.startswith("/late/talker\n  Subscribers:\n")
    assert results["param"] == (
        0, "  rate\n  start_type_description_service\n  use_sim_time\n", "")
