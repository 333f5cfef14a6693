"""DdsTransport behind the runtime's Node API: two contexts (two DDS participants) in one
process, selection by name and environment, and its rejections.

Oracles: what the other participant receives and announces (the contract says a transport
delivers copies, keeps TRANSIENT_LOCAL history for late joiners, reports the graph), and
the module list of a fresh interpreter for the lazy import.
"""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Iterator

import pytest

from _support.dds import dds_context, dds_domain, spin_until
from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.std_msgs import String
from posekit.msgs.tf2_msgs import TFMessage
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.logging import LogRecord
from posekit.runtime.node import Node
from posekit.runtime.qos import DurabilityPolicy, QoSProfile
from posekit.runtime.transport import TopicTypeMismatchError

pytestmark = pytest.mark.slow

LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)


@pytest.fixture
def two(monkeypatch: pytest.MonkeyPatch) -> Iterator[tuple[Context, Context]]:
    dds_domain(monkeypatch, 160)
    a, b = dds_context(), dds_context()
    yield a, b
    b.try_shutdown()
    a.try_shutdown()


def test_importing_the_runtime_does_not_import_cyclonedds() -> None:
    code = ("import sys, posekit.rclpy, posekit.runtime.transport as t\n"
            "print('dds' in t.registered_transports(), 'cyclonedds' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=60, check=True).stdout.split()
    assert out == ["True", "False"]


def test_two_participants_exchange_messages_latched_history_and_graph(
        two: tuple[Context, Context]) -> None:
    a, b = two
    talker = Node("talker", context=a, transport="dds")
    listener = Node("listener", namespace="/robot", context=b, transport="dds")
    static = talker.create_publisher(TFMessage, "/tf_static", LATCHED)
    t = TransformStamped()
    t.header.frame_id, t.child_frame_id = "base_link", "camera"
    t.transform.translation.x = 0.25
    static.publish(TFMessage(transforms=[t]))
    t.transform.translation.x = 99.0  # the transport must have copied what was published
    pub = talker.create_publisher(String, "/chatter", 10)
    got: list[str] = []
    latched: list[TFMessage] = []
    listener.create_subscription(String, "/chatter", lambda m: got.append(m.data), 10)
    listener.create_subscription(TFMessage, "/tf_static", latched.append, LATCHED)
    executor = SingleThreadedExecutor(context=b)
    executor.add_node(listener)
    n = [0]

    def send() -> None:
        pub.publish(String(data=f"msg {n[0]}"))
        n[0] += 1

    assert spin_until(executor, lambda: len(got) >= 3 and bool(latched), 15, send)
    assert got[0].startswith("msg ")
    assert latched[0].transforms[0].child_frame_id == "camera"
    assert latched[0].transforms[0].transform.translation.x == 0.25
    transport = listener.transport
    transport.sync_graph(3.0)  # type: ignore[attr-defined]
    names = transport.get_node_names()  # type: ignore[attr-defined]
    assert "/talker" in names
    assert "/robot/listener" in names
    assert ("/chatter", ["std_msgs/msg/String"]) in listener.get_topic_names_and_types()
    assert listener.count_publishers("/chatter") == 1
    assert listener.count_subscribers("/chatter") == 1
    assert pub.get_subscription_count() == 1
    infos = transport.get_publishers_info_by_topic("/tf_static")  # type: ignore[attr-defined]
    assert [(i.node_name, i.namespace, i.qos.transient_local) for i in infos] == [
        ("talker", "/", True)]
    assert infos[0].type_hash.startswith("RIHS01_")
    # a node that leaves disappears from the other side's graph
    talker.destroy_node()
    assert spin_until(executor, lambda: "/talker" not in transport.get_node_names(),  # type: ignore[attr-defined]
                      10)


def test_selected_by_environment_and_rejections(
        monkeypatch: pytest.MonkeyPatch, logs: list[LogRecord]) -> None:
    dds_domain(monkeypatch, 161)
    monkeypatch.setenv("POSEKIT_TRANSPORT", "dds")
    context = Context()
    context.init()
    try:
        node = Node("strict", context=context)
        assert node.transport.name == "dds"
        node.create_publisher(String, "/one", 10)
        with pytest.raises(TopicTypeMismatchError, match="already carries std_msgs/msg/String"):
            node.create_publisher(TFMessage, "/one", 10)
        received: list[String] = []
        node.create_subscription(String, "/two", received.append, 10)
        sub = node.transport._subscriptions[0]  # type: ignore[attr-defined]
        sub._deliver(b"\x00\x01\x00\x00\xff\xff\xff\x7f")  # a string longer than the sample
        sub._deliver(b"\x00\x01")
        warnings = [r.message for r in logs if "does not decode" in r.message]
        assert len(warnings) == 1, warnings
        assert "'/two'" in warnings[0]
        assert "std_msgs/msg/String" in warnings[0]
        assert received == []
        assert sub.dropped == 2
        sub._deliver(b"\x00\x01\x00\x00\x03\x00\x00\x00ok\x00")
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        assert spin_until(executor, lambda: bool(received), 5)
        assert received[0].data == "ok"
    finally:
        context.try_shutdown()
