"""TransformListener guards against what peers can send, and BufferCore.forget_frames.

Oracles: tf2's own semantics, reproduced by a plain Buffer fed the same samples (a sample
stamped years ahead makes later real samples fail with TF_OLD_DATA there, which is what the
listener guard prevents); a fresh Buffer holding only the frames that remain (lookups after
forgetting must equal it); counts of frames kept.
"""

from __future__ import annotations

import random

import pytest

from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.tf2_msgs import TFMessage
from posekit.runtime.node import Node
from posekit.tf2 import Buffer, TransformException
from posekit.tf2_ros.transform_listener import DEFAULT_MAX_FRAMES, TransformListener
from posekit.time import Duration, Time

NS = 1_000_000_000
YEAR_NS = 365 * 24 * 3600 * NS


def tf(parent: str, child: str, x: float, stamp_ns: int = 0) -> TransformStamped:
    t = TransformStamped()
    t.header.frame_id = parent
    t.child_frame_id = child
    t.header.stamp.sec, t.header.stamp.nanosec = divmod(stamp_ns, NS)
    t.transform.translation.x = x
    t.transform.rotation.w = 1.0
    return t


def test_far_future_stamp_cannot_freeze_a_frame(ctx, executor, logs) -> None:
    executor.set_time(100.0)
    node = Node("listener", context=ctx)
    peer = Node("peer", context=ctx)
    executor.add_node(node)
    executor.add_node(peer)
    buffer = Buffer()
    listener = TransformListener(buffer, node)
    pub = peer.create_publisher(TFMessage, "/tf", 100)
    future = tf("odom", "base_link", 9.0, 100 * NS + YEAR_NS)
    pub.publish(TFMessage([future]))
    executor.run_for(0.05)
    for k in range(1, 4):
        pub.publish(TFMessage([tf("odom", "base_link", float(k), 100 * NS + k * NS // 10)]))
        executor.run_for(0.05)
    latest = buffer.lookup_transform("odom", "base_link", Time())
    assert latest.transform.translation.x == 3.0
    assert listener.future_dropped == 1
    warned = [r for r in logs if "far in the future" in r.message]
    assert len(warned) == 1
    assert "base_link" in warned[0].message

    # tf2's semantics, unchanged in the Buffer itself: the same samples set directly.
    plain = Buffer()
    assert plain.set_transform(future, "peer")
    assert not plain.set_transform(tf("odom", "base_link", 1.0, 100 * NS + NS // 10), "peer")


def test_guard_off_and_clock_at_zero_pass_everything(ctx, executor) -> None:
    node = Node("listener", context=ctx)
    executor.add_node(node)  # sim time at 0: "no clock yet"
    at_zero = Buffer()
    TransformListener(at_zero, node)
    off = Buffer()
    TransformListener(off, node, max_future=None)
    pub = node.create_publisher(TFMessage, "/tf", 10)
    pub.publish(TFMessage([tf("odom", "base_link", 1.0, YEAR_NS)]))
    executor.run_for(0.01)
    for buffer in (at_zero, off):
        assert buffer.lookup_transform("odom", "base_link", Time()).transform.translation.x == 1


def test_random_frames_from_a_peer_are_bounded(ctx, executor) -> None:
    node = Node("listener", context=ctx)
    peer = Node("peer", context=ctx)
    executor.add_node(node)
    executor.add_node(peer)
    buffer = Buffer()
    TransformListener(buffer, node)
    pub = peer.create_publisher(TFMessage, "/tf", 1000)
    rng = random.Random(3)
    n = 30_000
    for batch in range(n // 100):
        stamp = (batch + 1) * NS // 100
        transforms = [tf("map", f"junk_{rng.getrandbits(48):012x}", 1.0, stamp)
                      for _ in range(100)]
        transforms.append(tf("odom", "base_link", float(batch), stamp))  # a real frame
        pub.publish(TFMessage(transforms))
        executor.run_for(0.01)
    names = buffer.get_all_frame_names()
    assert len(names) <= DEFAULT_MAX_FRAMES + 2  # plus the parents map and odom
    assert buffer.lookup_transform("odom", "base_link", Time()).transform.translation.x == (
        n // 100 - 1)


def test_forget_frames_matches_a_buffer_that_never_had_them() -> None:
    kept = [tf("map", "odom", 1.0), tf("odom", "base_link", 2.0), tf("base_link", "laser", 0.1)]
    junk = [tf("map", f"junk{i}", float(i)) for i in range(50)]
    junk += [tf("junk3", "junk_child", 5.0)]
    buffer = Buffer(cache_time=Duration(seconds=10))
    for t in kept + junk:
        t.header.stamp.sec = 1
        assert buffer.set_transform(t, "test")
    buffer.set_transform_static(tf("base_link", "camera", 0.3), "test")
    reference = Buffer(cache_time=Duration(seconds=10))
    for t in kept:
        reference.set_transform(t, "test")
    reference.set_transform_static(tf("base_link", "camera", 0.3), "test")

    dropped = buffer.forget_frames([f"junk{i}" for i in range(50)] + ["junk_child"])
    assert dropped == 51
    assert sorted(buffer.get_all_frame_names()) == sorted(reference.get_all_frame_names())
    for target, source in [("map", "laser"), ("camera", "map"), ("laser", "camera")]:
        got = buffer.lookup_transform(target, source, Time())
        want = reference.lookup_transform(target, source, Time())
        assert got.transform == want.transform
        assert got.header.stamp == want.header.stamp
    with pytest.raises(TransformException):
        buffer.lookup_transform("map", "junk3", Time())
    # A frame that is still a parent keeps its name (base_link hangs off odom); only its own
    # link goes, and "map", now without data or children, goes with it.
    assert buffer.forget_frames(["odom"]) == 1
    assert "odom" in buffer.get_all_frame_names()
    assert "map" not in buffer.get_all_frame_names()
    with pytest.raises(TransformException):
        buffer.lookup_transform("map", "base_link", Time())
    laser = buffer.lookup_transform("odom", "laser", Time()).transform.translation.x
    assert laser == pytest.approx(2.1)
