"""posekit node list / topic list over real Zenoh sessions, including rmw_zenoh's own tokens.

The "ROS 2 node" here is a plain zenoh session declaring liveliness tokens in rmw_zenoh's
exact format (docs/specs/rmw_zenoh.md §2 worked example), sharing no code with posekit's token
builders.
"""

from __future__ import annotations

import io
import json
import time
from collections.abc import Iterator
from typing import Any

import pytest
import zenoh

from _support.ports import free_port
from posekit.cli import node_cmd, topic_cmd
from posekit.msgs.std_msgs import String
from posekit.runtime.context import Context
from posekit.runtime.node import Node
from posekit.transport.zenoh_transport import ZenohTransport

pytestmark = pytest.mark.slow  # real processes, sessions or a browser

ROS_ZID = "1234567890abcdef1234567890abcdef"
TF_HASH = "RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087"
ROS_TOKENS = [  # docs/specs/rmw_zenoh.md §2, verbatim, plus a hidden ROS node
    f"@ros2_lv/0/{ROS_ZID}/0/0/NN/%/%/zbridge",
    f"@ros2_lv/0/{ROS_ZID}/0/1/MP/%/%/zbridge/%tf/tf2_msgs::msg::dds_::TFMessage_/{TF_HASH}"
    "/::,100:,:,:,,",
    f"@ros2_lv/0/{ROS_ZID}/0/2/MS/%/%/zbridge/%tf_static/tf2_msgs::msg::dds_::TFMessage_/"
    f"{TF_HASH}/:1:,100:,:,:,,",
    f"@ros2_lv/0/{ROS_ZID}/3/3/NN/%/%robot1/_ros2cli_99",
]




@pytest.fixture
def endpoint(monkeypatch: pytest.MonkeyPatch) -> str:
    for var in ("ZENOH_SESSION_CONFIG_URI", "ZENOH_CONFIG_OVERRIDE", "ROS_DOMAIN_ID"):
        monkeypatch.delenv(var, raising=False)
    where = f"tcp/127.0.0.1:{free_port()}"
    monkeypatch.setenv("POSEKIT_ZENOH_ROUTER", where)
    return where


@pytest.fixture
def zenoh_context(endpoint: str) -> Iterator[Context]:
    context = Context()
    context.init(transport="zenoh")
    yield context
    context.try_shutdown()


def plain_ros_peer(endpoint: str) -> Any:
    config = zenoh.Config()
    config.insert_json5("mode", json.dumps("peer"))
    config.insert_json5("connect/endpoints", json.dumps([endpoint]))
    config.insert_json5("listen/endpoints", json.dumps(["tcp/127.0.0.1:0"]))
    config.insert_json5("scouting/multicast/enabled", "false")
    return zenoh.open(config)


def run(main: Any, argv: list[str], context: Context) -> tuple[str, str]:
    out, err = io.StringIO(), io.StringIO()
    assert main(argv, context=context, out=out, err=err) == 0
    return out.getvalue(), err.getvalue()


def wait_listed(context: Context, name: str, present: bool, timeout: float = 10.0) -> str:
    deadline = time.monotonic() + timeout
    while True:
        text, _ = run(node_cmd.main_list, ["-a"], context)
        if (name in text.splitlines()) == present:
            return text
        if time.monotonic() > deadline:
            break
        time.sleep(0.05)
    raise AssertionError(f"{name} {'never appeared in' if present else 'never left'}: {text!r}")


def test_ros2_tokens_show_in_node_and_topic_lists(zenoh_context: Context, endpoint: str) -> None:
    # the router is hosted by the first posekit session (zero configuration)
    transport = zenoh_context.transport()
    assert isinstance(transport, ZenohTransport)
    assert transport.session.hosts_router
    ros = plain_ros_peer(endpoint)
    tokens = [ros.liveliness().declare_token(key) for key in ROS_TOKENS]
    try:
        wait_listed(zenoh_context, "/zbridge", True)
        out, err = run(node_cmd.main_list, [], zenoh_context)
        assert out == "/zbridge\n"
        assert err == ""
        out, _ = run(node_cmd.main_list, ["-a"], zenoh_context)
        assert out == "/robot1/_ros2cli_99\n/zbridge\n"
        out, _ = run(node_cmd.main_list, ["-c"], zenoh_context)
        assert out == "1\n"
        out, _ = run(topic_cmd.main_list, ["-t"], zenoh_context)
        # the tool's own node has /parameter_events and /rosout, as ros2's does
        assert out == (
            "/parameter_events [rcl_interfaces/msg/ParameterEvent]\n"
            "/rosout [rcl_interfaces/msg/Log]\n"
            "/tf [tf2_msgs/msg/TFMessage]\n/tf_static [tf2_msgs/msg/TFMessage]\n"
        )
        out, _ = run(topic_cmd.main_info, ["/tf_static", "-v"], zenoh_context)
        assert "Subscription count: 1\n\nNode name: zbridge\nNode namespace: /\n" in out
        assert "  Durability: TRANSIENT_LOCAL\n" in out
        assert "History (Depth): KEEP_LAST (100)" in out
        # a duplicate node name is warned about, like ros2 node list does
        dup = ros.liveliness().declare_token(f"@ros2_lv/0/{'f' * 32}/0/0/NN/%/%/zbridge")
        tokens.append(dup)
        wait_listed(zenoh_context, "/zbridge", True)
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:
            out, err = run(node_cmd.main_list, [], zenoh_context)
            if err:
                break
            time.sleep(0.05)
        assert out == "/zbridge\n/zbridge\n"  # both, as ros2node's list verb prints them
        assert err.startswith("WARNING: Be aware that there are nodes")
    finally:
        for token in tokens:
            token.undeclare()
        ros.close()
    wait_listed(zenoh_context, "/zbridge", False)


def test_nodes_without_endpoints_are_announced_and_withdrawn(zenoh_context: Context) -> None:
    transport = zenoh_context.transport()
    assert isinstance(transport, ZenohTransport)
    # Node.__init__ calls declare_node: visible with no endpoint at all
    node = Node("idle", namespace="/robot2", context=zenoh_context)
    wait_listed(zenoh_context, "/robot2/idle", True)
    pub = node.create_publisher(String, "chatter", 10)
    node.destroy_publisher(pub)  # the node itself still holds its announcement
    wait_listed(zenoh_context, "/robot2/idle", True)
    # references are counted: another declaration outlives the node's own
    transport.declare_node("idle", "/robot2")
    node.destroy_node()  # undeclare_node: one reference left
    wait_listed(zenoh_context, "/robot2/idle", True)
    transport.undeclare_node("idle", "/robot2")  # last reference: the NN token goes
    wait_listed(zenoh_context, "/robot2/idle", False)
    transport.undeclare_node("never", "/")  # unknown: no-op


def test_echo_decodes_a_ros2_publisher_of_a_type_posekit_has_no_class_for(
    zenoh_context: Context, endpoint: str
) -> None:
    import struct
    import threading

    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_JAZZY)
    name = "diagnostic_msgs/msg/KeyValue"
    type_hash = store.hash_rihs01(name)
    ros = plain_ros_peer(endpoint)
    zid = str(ros.info.zid())
    key = f"0/counter/diagnostic_msgs::msg::dds_::KeyValue_/{type_hash}"
    tokens = [
        ros.liveliness().declare_token(f"@ros2_lv/0/{zid}/0/0/NN/%/%/counter_node"),
        ros.liveliness().declare_token(
            f"@ros2_lv/0/{zid}/0/1/MP/%/%/counter_node/%counter/diagnostic_msgs::msg::dds_::KeyValue_/"
            f"{type_hash}/::,10:,:,:,,"),
    ]
    pub = ros.declare_publisher(key)
    out = io.StringIO()
    result: list[int] = []
    thread = threading.Thread(target=lambda: result.append(topic_cmd.main_echo(
        ["/counter", "--once"], context=zenoh_context, out=out, err=io.StringIO(),
        timeout_s=15)))
    thread.start()
    try:
        seq = 0
        while thread.is_alive() and seq < 1000:
            seq += 1
            payload = bytes(store.serialize_cdr(store.types[name](key="k", value="v"), name))
            attachment = struct.pack("<qqB", seq, time.time_ns(), 16) + bytes(range(16))
            pub.put(payload, attachment=attachment)
            time.sleep(0.02)
        thread.join(5)
    finally:
        for token in tokens:
            token.undeclare()
        pub.undeclare()
        ros.close()
    assert result == [0]
    assert out.getvalue() == "key: k\nvalue: v\n---\n"
    # and pub sends one, from its Jazzy definition (tests/cli/test_dds_tools.py checks that
    # a real subscriber decodes such a message)
    out, err = io.StringIO(), io.StringIO()
    assert topic_cmd.main_pub(["/counter", name, "{key: a}", "--once", "-w", "0"],
                              context=zenoh_context, out=out, err=err) == 0, err.getvalue()
    assert out.getvalue() == ("publisher: beginning loop\npublishing #1: "
                              "diagnostic_msgs.msg.KeyValue(key='a', value='')\n\n")
