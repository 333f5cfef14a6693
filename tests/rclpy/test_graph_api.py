"""The node's graph API over every transport's records, guard conditions across threads.

tests/rclpy/differential/graph.py compares the same API with the real rclpy in process;
these cover what it cannot: the network transports' records, and threads.
"""

from __future__ import annotations

import threading
import time
from types import SimpleNamespace

from posekit.msgs.std_msgs import String
from posekit.runtime.executors import MultiThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.qos import HistoryPolicy, QoSProfile
from posekit.runtime.topic_endpoint_info import (
    TopicEndpointTypeEnum,
    endpoint_info_from_record,
)
from posekit.transport.zenoh_wire import WireQoS, entity_gid, parse_token


def test_a_wire_record_becomes_rclpys_endpoint_info() -> None:
    record = SimpleNamespace(
        node_name="talker", namespace="/", ros_type="std_msgs/msg/String",
        type_hash="RIHS01_" + "ab" * 32, qos=WireQoS(depth=5, lifespan=(2, 5)),
        gid=bytes(range(16)))
    info = endpoint_info_from_record(record, TopicEndpointTypeEnum.PUBLISHER)
    assert str(info).splitlines() == [
        "Node name: talker",
        "Node namespace: /",
        "Topic type: std_msgs/msg/String",
        "Topic type hash: RIHS01_" + "ab" * 32,
        "Endpoint type: PUBLISHER",
        "GID: 00.01.02.03.04.05.06.07.08.09.0a.0b.0c.0d.0e.0f",
        "QoS profile:",
        "  Reliability: RELIABLE",
        "  History (Depth): KEEP_LAST (5)",
        "  Durability: VOLATILE",
        "  Lifespan: 2000000005 nanoseconds",
        "  Deadline: Infinite",
        "  Liveliness: AUTOMATIC",
        "  Liveliness lease duration: Infinite",
    ]


def test_a_zenoh_token_carries_rmw_zenohs_gid() -> None:
    key = ("@ros2_lv/0/aac3178e146ba6f1fc6e6a4085e77f21/0/10/MP/%/%/talker/%chatter/"
           "std_msgs::msg::dds_::String_/RIHS01_" + "df" * 32 + "/::,7:,:,:,,")
    token = parse_token(key)
    assert token.gid == entity_gid(key)
    info = endpoint_info_from_record(token, TopicEndpointTypeEnum.PUBLISHER)
    assert (info.node_name, info.topic_type, info.qos_profile.depth) == (
        "talker", "std_msgs/msg/String", 7)
    assert info.qos_profile.history == HistoryPolicy.KEEP_LAST


def test_in_process_endpoints_report_their_profile(ctx) -> None:
    node = Node("n", context=ctx)
    node.create_publisher(String, "t", QoSProfile(history=HistoryPolicy.KEEP_ALL, depth=0))
    (info,) = node.get_publishers_info_by_topic("t")
    assert "  History (Depth): KEEP_ALL" in str(info).splitlines()
    assert len(info.endpoint_gid) == 16
    assert str(info.topic_type_hash).startswith("RIHS01_")


def test_a_trigger_from_another_thread_runs_the_callback(ctx) -> None:
    node = Node("guarded", context=ctx)
    ran = threading.Event()
    guard = node.create_guard_condition(ran.set)
    executor = MultiThreadedExecutor(num_threads=2, context=ctx)
    executor.add_node(node)
    spinner = threading.Thread(target=executor.spin)
    spinner.start()
    try:
        threading.Timer(0.05, guard.trigger).start()
        assert ran.wait(5.0)
    finally:
        executor.shutdown()
        spinner.join(5.0)
    node.destroy_node()
    assert list(node.guards) == []


def test_wait_for_node_sees_a_node_made_later(ctx) -> None:
    node = Node("waiter", context=ctx)
    threading.Timer(0.1, lambda: Node("late", namespace="/x", context=ctx)).start()
    started = time.monotonic()
    assert node.wait_for_node("/x/late", 5.0)
    assert time.monotonic() - started < 4.0


def test_dds_discovery_without_history_reports_unknown() -> None:
    # RTPS discovery carries no HISTORY; rmw (and posekit's DDS transport) say UNKNOWN, 0
    record = SimpleNamespace(node_name="n", namespace="/", ros_type="std_msgs/msg/String",
                             type_hash=None, qos=WireQoS(history=3, depth=0), gid=b"")
    info = endpoint_info_from_record(record, TopicEndpointTypeEnum.SUBSCRIPTION)
    assert "  History (Depth): UNKNOWN" in str(info).splitlines()
    assert "Topic type hash: INVALID" in str(info).splitlines()
    assert WireQoS(history=3, depth=0).to_profile().depth == 1  # a profile to request with
