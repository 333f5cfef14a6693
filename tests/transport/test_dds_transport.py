"""DdsTransport behind the runtime's Node API: two contexts (two DDS participants) in one
process, selection by name and environment, and its rejections.

Oracles: what the other participant receives and announces (the contract says a transport
delivers copies, keeps TRANSIENT_LOCAL history for late joiners, reports the graph), the
module list of a fresh interpreter for the lazy import, and for ``ROS_AUTOMATIC_DISCOVERY_
RANGE=OFF`` a twin process left at LOCALHOST as the control that is discovered.
"""

from __future__ import annotations

import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from typing import Any

import pytest

from _support.dds import dds_context, dds_domain, spin_until, two_dds_contexts
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
    with two_dds_contexts(monkeypatch) as pair:
        yield pair


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
    dds_domain(monkeypatch)
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


CHILD = """
import sys, time
import posekit.rclpy as rclpy
from posekit.msgs.std_msgs import String
rclpy.init(transport="dds")
node = rclpy.create_node(sys.argv[1])
pub = node.create_publisher(String, sys.argv[2], 10)
print("ready", flush=True)
deadline = time.monotonic() + 30
while time.monotonic() < deadline:
    pub.publish(String(data="x"))
    time.sleep(0.1)
"""


def test_discovery_range_off_keeps_a_process_out_of_the_graph(
        monkeypatch: pytest.MonkeyPatch) -> None:
    from _support.dds import posekit_env
    from _support.procs import Proc

    domain = dds_domain(monkeypatch)
    on = Proc([sys.executable, "-c", CHILD, "on_child", "/on_probe"], env=posekit_env(domain))
    off = Proc([sys.executable, "-c", CHILD, "off_child", "/off_probe"],
               env=posekit_env(domain, ROS_AUTOMATIC_DISCOVERY_RANGE="OFF"))
    context = dds_context()
    try:
        node = Node("observer", context=context)
        transport = node.transport
        on.wait_line(lambda line: line.startswith("ready"), 30, "the LOCALHOST child")
        off.wait_line(lambda line: line.startswith("ready"), 30, "the OFF child")
        deadline = time.monotonic() + 20
        while "/on_child" not in transport.get_node_names():  # type: ignore[attr-defined]
            assert time.monotonic() < deadline, "the LOCALHOST child was never discovered"
            transport.sync_graph(0.5)  # type: ignore[attr-defined]
        transport.sync_graph(2.0)  # type: ignore[attr-defined]  # time for the other one too
        names = transport.get_node_names()  # type: ignore[attr-defined]
        on_count = node.count_publishers("/on_probe")
        off_count = node.count_publishers("/off_probe")
    finally:
        on.kill()
        off.kill()
        context.try_shutdown()
    assert "/off_child" not in names
    assert on_count == 1
    assert off_count == 0


def test_a_lifespan_becomes_the_writers_lifespan_policy() -> None:
    """rcl's /rosout profile (lifespan 10 s) on a DDS writer; readers carry no lifespan."""
    from cyclonedds.qos import Policy

    from posekit.runtime.rosout import qos_profile_rosout_default
    from posekit.transport.dds_transport import endpoint_qos, wire_qos_of

    writer = endpoint_qos(qos_profile_rosout_default, b"", writer=True)
    assert writer[Policy.Lifespan] == Policy.Lifespan(lifespan=10_000_000_000)
    assert wire_qos_of(writer).lifespan == (10, 0)
    reader = endpoint_qos(qos_profile_rosout_default, b"", writer=False)
    assert Policy.Lifespan not in reader
    assert Policy.Lifespan not in endpoint_qos(LATCHED, b"", writer=True)


def test_the_graph_thread_reads_what_discovery_announced_and_sleeps_when_idle(
        two: tuple[Context, Context]) -> None:
    """The graph is read again only when discovery data arrives or sync_graph asks, and a
    participant that leaves takes its endpoints out of the graph (its instances dispose)
    and leaves nothing behind in the builtin readers."""
    a, b = two
    watcher = Node("watcher", context=a, transport="dds")
    transport = watcher.transport
    peer = Node("peer", context=b, transport="dds")
    peer.create_publisher(String, "/only_peer", 10)
    deadline = time.monotonic() + 15
    while watcher.count_publishers("/only_peer") != 1:
        assert time.monotonic() < deadline, "the peer's publisher was never discovered"
        transport.sync_graph(0.5)  # type: ignore[attr-defined]
    reads: list[float] = []
    checks: list[float] = []
    refresh = transport._refresh  # type: ignore[attr-defined]
    check = transport._check_incompatible_qos  # type: ignore[attr-defined]

    def counted_refresh() -> None:
        reads.append(time.monotonic())
        refresh()

    def counted_check() -> None:
        checks.append(time.monotonic())
        check()

    transport._refresh = counted_refresh  # type: ignore[attr-defined]
    transport._check_incompatible_qos = counted_check  # type: ignore[attr-defined]
    transport.sync_graph(0.2)  # type: ignore[attr-defined]  # asks for one read
    # two of the loop's one-second timeouts with nothing announced
    deadline = time.monotonic() + 10
    while len(checks) < 3:
        assert time.monotonic() < deadline, "the graph thread stopped going round"
        time.sleep(0.05)
    assert 1 <= len(reads) <= 2, f"an idle graph was read {len(reads)} times"
    assert not transport._wake.read()  # type: ignore[attr-defined]  # sync's wake handled
    b.try_shutdown()  # the peer's participant and all its endpoints leave
    deadline = time.monotonic() + 15
    while watcher.count_publishers("/only_peer") != 0 or "/peer" in transport.get_node_names():  # type: ignore[attr-defined]
        assert time.monotonic() < deadline, "the peer's endpoints stayed in the graph"
        time.sleep(0.05)
    # What the graph has seen is taken from the builtin readers: Cyclone keeps no sample of
    # a peer that left (read samples stayed for good, and every re-read converted them)
    from cyclonedds.core import InstanceState, ReadCondition, SampleState, ViewState

    for name, reader in transport._builtin.items():  # type: ignore[attr-defined]
        seen = ReadCondition(reader, SampleState.Read | ViewState.Any | InstanceState.Any)
        assert reader.read(N=1000, condition=seen) == [], name


def test_an_announcement_taken_before_its_participant_is_read_stays_on_the_graph(
        two: tuple[Context, Context], monkeypatch: pytest.MonkeyPatch) -> None:
    """A read of the graph reads the participants first, then takes ros_discovery_info: a
    participant discovered in between has its nodes' announcement taken before its builtin
    sample is read. The announcement must wait for it (it is not sent again)."""
    import posekit.transport.dds_transport as dds

    a, b = two
    watcher = Node("watcher", context=a, transport="dds")
    transport = watcher.transport
    participants_reader = transport._builtin["participant"]  # type: ignore[attr-defined]
    hold = threading.Event()
    hold.set()
    take_new = dds._take_new

    def late_participants(reader: Any, condition: Any) -> list[Any]:
        if reader is participants_reader and hold.is_set():
            return []  # the peer's builtin sample "not arrived yet"
        return take_new(reader, condition)

    decoded: list[bytes] = []
    decode = dds.decode_participant_entities

    def recording_decode(data: bytes) -> Any:
        entities = decode(data)
        decoded.append(entities.gid)
        return entities

    monkeypatch.setattr(dds, "_take_new", late_participants)
    monkeypatch.setattr(dds, "decode_participant_entities", recording_decode)
    peer = Node("peer", context=b, transport="dds")
    peer_gid = peer.transport.gid  # type: ignore[attr-defined]
    deadline = time.monotonic() + 15
    while peer_gid not in decoded:
        assert time.monotonic() < deadline, "the peer's announcement never arrived"
        time.sleep(0.02)
    hold.clear()  # now the participant sample is read
    deadline = time.monotonic() + 10
    while "/peer" not in transport.get_node_names():  # type: ignore[attr-defined]
        assert time.monotonic() < deadline, "the peer's announcement was dropped"
        time.sleep(0.05)
