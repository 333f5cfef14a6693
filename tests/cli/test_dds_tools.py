"""posekit's command-line tools with ``--transport dds`` on a real ROS 2 Jazzy system.

Oracles: real rclpy publishers (Fast DDS) with known content, rate, node name and QoS, and a
real rclpy subscription for ``topic pub``; the bag is read back with rosbags (not posekit's
reader).
"""

from __future__ import annotations

import io
import re
import sys
import textwrap
from pathlib import Path

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
