"""In-process bus: mutation policy, depth, reliability matching, TRANSIENT_LOCAL, graph."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.sensor_msgs import Image
from posekit.msgs.std_msgs import Float64, String
from posekit.runtime.bus import SMALL_ARRAY_BYTES
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    QoSProfile,
    ReliabilityPolicy,
)
from posekit.runtime.transport import TopicTypeMismatchError

TL = DurabilityPolicy.TRANSIENT_LOCAL
BE = ReliabilityPolicy.BEST_EFFORT


def drain(ex: SingleThreadedExecutor) -> None:
    ex.spin_some()


def test_subscribers_cannot_corrupt_each_other_or_see_publisher_edits(ctx) -> None:
    node = Node("n", context=ctx)
    pub = node.create_publisher(Odometry, "odom", 10)
    seen_b: list[Odometry] = []

    def a(msg: Odometry) -> None:  # a rude subscriber mutating everything it can
        msg.header.frame_id = "corrupted"
        msg.pose.pose.position.x = -1.0
        msg.pose.covariance[0] = 99.0
        msg.child_frame_id = "x"

    node.create_subscription(Odometry, "odom", a, 10)
    node.create_subscription(Odometry, "odom", seen_b.append, 10)
    msg = Odometry()
    msg.header.frame_id = "odom"
    msg.pose.pose.position.x = 1.0
    msg.pose.covariance[0] = 0.5
    pub.publish(msg)
    msg.pose.pose.position.x = 2.0  # the publisher reuses its message object
    msg.pose.covariance[0] = 0.25
    pub.publish(msg)
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(node)
    drain(ex)
    assert [m.pose.pose.position.x for m in seen_b] == [1.0, 2.0]
    assert [m.pose.covariance[0] for m in seen_b] == [0.5, 0.25]
    assert all(m.header.frame_id == "odom" and m.child_frame_id == "" for m in seen_b)
    assert msg.pose.covariance.flags.writeable  # small arrays stay the publisher's own


def test_large_arrays_are_shared_read_only_not_copied(ctx) -> None:
    node = Node("cam", context=ctx)
    pub = node.create_publisher(Image, "image", 10)
    got: list[list[Image]] = [[], [], []]
    for sink in got:
        node.create_subscription(Image, "image", sink.append, 10)
    pixels = np.arange(720 * 1280 * 3, dtype=np.uint32).astype(np.uint8)
    assert pixels.nbytes > SMALL_ARRAY_BYTES
    img = Image(height=720, width=1280, encoding="rgb8", step=1280 * 3, data=pixels)
    pub.publish(img)
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(node)
    drain(ex)
    received = [g[0] for g in got]
    # Same buffer for everyone (no per-subscriber copy) but separate message objects.
    assert all(r.data is pixels for r in received)
    assert len({id(r) for r in received}) == 3
    assert all(r is not img for r in received)
    assert not pixels.flags.writeable
    with pytest.raises(ValueError, match="read-only"):
        received[0].data[0] = 1
    received[0].header.frame_id = "mine"  # structure is private
    assert received[1].header.frame_id == ""


def test_keep_last_depth_drops_oldest_keep_all_keeps_all(ctx) -> None:
    node = Node("n", context=ctx)
    pub = node.create_publisher(Float64, "x", QoSProfile(depth=100))
    last3: list[float] = []
    everything: list[float] = []
    node.create_subscription(Float64, "x", lambda m: last3.append(m.data), 3)
    node.create_subscription(Float64, "x", lambda m: everything.append(m.data),
                             QoSProfile(history=HistoryPolicy.KEEP_ALL, depth=0))
    for i in range(10):
        pub.publish(Float64(data=float(i)))
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(node)
    drain(ex)
    assert last3 == [7.0, 8.0, 9.0]
    assert everything == [float(i) for i in range(10)]


def test_best_effort_publisher_does_not_reach_reliable_subscription(ctx, logs) -> None:
    node = Node("n", context=ctx)
    reliable: list[str] = []
    best_effort: list[str] = []
    node.create_subscription(String, "t", lambda m: reliable.append(m.data), 10)
    node.create_subscription(String, "t", lambda m: best_effort.append(m.data),
                             QoSProfile(depth=10, reliability=BE))
    be_pub = node.create_publisher(String, "t", QoSProfile(depth=10, reliability=BE))
    assert any("incompatible QoS" in r.message and "RELIABILITY" in r.message for r in logs)
    rel_pub = node.create_publisher(String, "t", 10)
    be_pub.publish(String(data="from best effort"))
    rel_pub.publish(String(data="from reliable"))
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(node)
    drain(ex)
    assert reliable == ["from reliable"]
    assert best_effort == ["from best effort", "from reliable"]
    assert be_pub.get_subscription_count() == 1
    assert rel_pub.get_subscription_count() == 2


def test_transient_local_late_joiner_gets_last_depth(ctx) -> None:
    talker = Node("talker", context=ctx)
    pub = talker.create_publisher(String, "latched", QoSProfile(depth=2, durability=TL))
    for word in ["a", "b", "c"]:
        pub.publish(String(data=word))
    late = Node("late", context=ctx)
    tl_got: list[str] = []
    vol_got: list[str] = []
    late.create_subscription(String, "latched", lambda m: tl_got.append(m.data),
                             QoSProfile(depth=10, durability=TL))
    late.create_subscription(String, "latched", lambda m: vol_got.append(m.data), 10)
    pub.publish(String(data="d"))
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(late)
    drain(ex)
    assert tl_got == ["b", "c", "d"]
    assert vol_got == ["d"]


def test_volatile_publisher_does_not_match_transient_local_subscription(ctx, logs) -> None:
    node = Node("n", context=ctx)
    got: list[str] = []
    node.create_subscription(String, "t", lambda m: got.append(m.data),
                             QoSProfile(depth=1, durability=TL))
    pub = node.create_publisher(String, "t", 10)
    pub.publish(String(data="x"))
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(node)
    drain(ex)
    assert got == []
    assert any("DURABILITY" in r.message for r in logs)


def test_type_mismatch_and_graph(ctx) -> None:
    node = Node("n", context=ctx, namespace="/r")
    node.create_publisher(String, "chatter", 10)
    node.create_subscription(String, "/chatter2", lambda m: None, 10)
    with pytest.raises(TopicTypeMismatchError, match="std_msgs"):
        node.create_subscription(Float64, "chatter", lambda m: None, 10)
    with pytest.raises(TypeError, match="expects String"):
        node.create_publisher(String, "x", 10).publish(Float64())
    assert ("/r/chatter", ["std_msgs/msg/String"]) in node.get_topic_names_and_types()
    assert ("/chatter2", ["std_msgs/msg/String"]) in node.get_topic_names_and_types()
    assert node.count_publishers("chatter") == 1
    assert node.count_subscribers("/chatter2") == 1


def test_destroyed_subscription_stops_receiving(ctx) -> None:
    node = Node("n", context=ctx)
    pub = node.create_publisher(String, "t", 10)
    got: list[str] = []
    sub = node.create_subscription(String, "t", lambda m: got.append(m.data), 10)
    pub.publish(String(data="queued"))
    assert node.destroy_subscription(sub)
    assert not node.destroy_subscription(sub)
    pub.publish(String(data="after"))
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(node)
    drain(ex)
    assert got == []
    assert pub.get_subscription_count() == 0


def test_publish_transfer_hands_the_object_over_and_keeps_subscribers_apart(ctx) -> None:
    node = Node("n", context=ctx)
    single = node.create_publisher(Odometry, "single", 10)
    multi = node.create_publisher(Odometry, "multi", 10)
    got_single: list[Odometry] = []
    got_multi: list[list[Odometry]] = [[], [], []]
    node.create_subscription(Odometry, "single", got_single.append, 10)

    def rude(msg: Odometry) -> None:  # first subscriber edits everything it received
        msg.header.frame_id = "corrupted"
        msg.pose.covariance[0] = 99.0
        got_multi[0].append(msg)

    node.create_subscription(Odometry, "multi", rude, 10)
    node.create_subscription(Odometry, "multi", got_multi[1].append, 10)
    node.create_subscription(Odometry, "multi", got_multi[2].append, 10)
    one = Odometry()
    one.header.frame_id = "odom"
    single.publish_transfer(one)
    many = Odometry()
    many.header.frame_id = "odom"
    many.pose.covariance[0] = 0.5
    multi.publish_transfer(many)
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(node)
    drain(ex)
    assert got_single[0] is one  # a single subscriber gets the handed-over object: no copy
    assert got_multi[2][0] is many  # the last one does; the others get their own copies
    assert got_multi[0][0] is not many
    assert got_multi[1][0] is not many
    for received in got_multi[1:]:
        assert received[0].header.frame_id == "odom"
        assert received[0].pose.covariance[0] == 0.5


def test_publish_transfer_keeps_transient_local_history_and_checks_input(ctx) -> None:
    talker = Node("talker", context=ctx)
    pub = talker.create_publisher(String, "latched", QoSProfile(depth=1, durability=TL))
    first = String(data="a")
    pub.publish_transfer(first)
    late = Node("late", context=ctx)
    got: list[String] = []
    late.create_subscription(String, "latched", got.append, QoSProfile(depth=10, durability=TL))
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(late)
    drain(ex)
    assert [m.data for m in got] == ["a"]
    assert got[0] is not first  # the history's object is never handed to a subscriber
    with pytest.raises(TypeError, match="expects String"):
        pub.publish_transfer(Float64(data=1.0))
    talker.destroy_publisher(pub)
    with pytest.raises(RuntimeError, match="destruction was requested"):  # InvalidHandle
        pub.publish_transfer(String(data="b"))


@dataclasses.dataclass(frozen=True)
class _FrozenReading:
    stamp_ns: int = 0
    value: float = 0.0
    frame_id: str = ""


@dataclasses.dataclass(frozen=True)
class _FrozenWithList:
    values: list = dataclasses.field(default_factory=list)


def test_immutable_frozen_messages_are_shared_mutable_ones_copied(ctx) -> None:
    node = Node("n", context=ctx)
    got: dict[str, list[list[object]]] = {"reading": [[], []], "listed": [[], []]}
    for topic, msg_type in (("reading", _FrozenReading), ("listed", _FrozenWithList)):
        for sink in got[topic]:
            node.create_subscription(msg_type, topic, sink.append, 10)
    reading = _FrozenReading(5, 1.5, "imu")
    listed = _FrozenWithList([1.0, 2.0])
    node.create_publisher(_FrozenReading, "reading", 10).publish(reading)
    node.create_publisher(_FrozenWithList, "listed", 10).publish(listed)
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(node)
    drain(ex)
    assert [g[0] for g in got["reading"]] == [reading, reading]
    assert all(g[0] is reading for g in got["reading"])  # nothing to protect: shared
    first, second = (g[0] for g in got["listed"])
    assert first == listed
    assert second == listed
    assert first is not listed
    assert second is not listed
    first.values.append(3.0)  # type: ignore[attr-defined]  # its list is its own
    assert second.values == [1.0, 2.0]  # type: ignore[attr-defined]
    assert listed.values == [1.0, 2.0]
