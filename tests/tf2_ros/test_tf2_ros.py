"""tf2_ros layer: broadcasters + listener in one process, QoS, static latching, clock jumps."""

from __future__ import annotations

import math

import numpy as np
import pytest

from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.tf2_msgs import TFMessage
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.qos import DurabilityPolicy, HistoryPolicy, ReliabilityPolicy
from posekit.runtime.sim_executor import SimulatedTimeExecutor
from posekit.tf2 import Buffer, TransformException
from posekit.tf2_ros import (
    StaticTransformBroadcaster,
    TransformBroadcaster,
    TransformListener,
)
from posekit.time import Duration, Time


def make_tf(parent: str, child: str, x: float, y: float = 0.0, z: float = 0.0,
            yaw: float = 0.0, stamp_ns: int = 0) -> TransformStamped:
    t = TransformStamped()
    t.header.frame_id = parent
    t.child_frame_id = child
    t.header.stamp.sec, t.header.stamp.nanosec = divmod(stamp_ns, 10**9)
    t.transform.translation.x, t.transform.translation.y = x, y
    t.transform.translation.z = z
    t.transform.rotation.z, t.transform.rotation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return t


def test_qos_of_broadcasters_and_listener(ctx) -> None:
    node = Node("n", context=ctx)
    dyn = TransformBroadcaster(node).pub_tf.qos_profile
    sta = StaticTransformBroadcaster(node).pub_tf.qos_profile
    listener = TransformListener(Buffer(), node)
    # docs/specs/tf2.md §9
    assert (dyn.depth, dyn.durability, dyn.reliability) == (
        100, DurabilityPolicy.VOLATILE, ReliabilityPolicy.RELIABLE)
    assert (sta.depth, sta.durability, sta.history) == (
        1, DurabilityPolicy.TRANSIENT_LOCAL, HistoryPolicy.KEEP_LAST)
    lq, sq = listener.tf_sub.qos_profile, listener.tf_static_sub.qos_profile
    assert (lq.depth, lq.durability) == (100, DurabilityPolicy.VOLATILE)
    assert (sq.depth, sq.durability, sq.reliability) == (
        100, DurabilityPolicy.TRANSIENT_LOCAL, ReliabilityPolicy.RELIABLE)
    assert listener.tf_sub.topic_name == "/tf"
    assert listener.tf_static_sub.topic_name == "/tf_static"


class Broadcaster(Node):
    """odom->base_link moving along x at 0.5 m/s (10 Hz), static base_link->camera."""

    def __init__(self, **kwargs) -> None:
        super().__init__("tf_broadcaster", **kwargs)
        self.br = TransformBroadcaster(self)
        self.static_br = StaticTransformBroadcaster(self)
        self.static_br.sendTransform(make_tf("base_link", "camera", 0.1, z=0.2, yaw=math.pi / 2))
        self.create_timer(0.1, self.tick)

    def tick(self) -> None:
        now = self.get_clock().now().nanoseconds
        self.br.sendTransform(make_tf("odom", "base_link", 0.5 * now / 1e9, stamp_ns=now))


class Listener(Node):
    def __init__(self, **kwargs) -> None:
        super().__init__("tf_listener", **kwargs)
        self.buffer = Buffer()
        self.listener = TransformListener(self.buffer, self)


def test_broadcaster_and_listener_nodes_in_one_process(ctx) -> None:
    br, ls = Broadcaster(context=ctx), Listener(context=ctx)
    ex = SimulatedTimeExecutor(context=ctx)
    ex.add_node(br)
    ex.add_node(ls)
    ex.run_until(2.0)
    # Latest common time: stamp 2.0 s, base at x = 1.0; camera = base + (0.1, 0, 0.2).
    t = ls.buffer.lookup_transform("odom", "camera", Time())
    assert t.header.stamp.sec == 2
    assert t.header.stamp.nanosec == 0
    p = t.transform.translation
    assert (p.x, p.y, p.z) == pytest.approx((1.1, 0.0, 0.2), abs=1e-12)
    q = t.transform.rotation
    assert (q.z, q.w) == pytest.approx((math.sqrt(0.5), math.sqrt(0.5)), abs=1e-12)
    # Interpolated dynamic + static at an intermediate time (x = 0.5 * 1.25).
    t_mid = ls.buffer.lookup_transform("odom", "camera", Time(seconds=1.25))
    assert t_mid.transform.translation.x == pytest.approx(0.625 + 0.1, abs=1e-12)
    # Inverse direction: odom origin seen from the camera.
    inv = ls.buffer.lookup_transform("camera", "odom", Time(seconds=2))
    R_odom_camera = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    expected = -R_odom_camera.T @ np.array([1.1, 0.0, 0.2])
    got = inv.transform.translation
    assert np.allclose([got.x, got.y, got.z], expected, atol=1e-12)


def test_late_listener_receives_static_transform(ctx) -> None:
    talker = Node("static_talker", context=ctx)
    StaticTransformBroadcaster(talker).sendTransform(make_tf("world", "map", 1.0))
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(talker)
    ex.spin_some()
    late = Listener(context=ctx)  # created after the static transform was sent
    ex.add_node(late)
    ex.spin_some()
    t = late.buffer.lookup_transform("world", "map", Time())
    assert t.transform.translation.x == 1.0


def test_static_broadcaster_accumulates_and_replaces_by_child(ctx) -> None:
    node = Node("n", context=ctx)
    static = StaticTransformBroadcaster(node)
    a = make_tf("base", "a", 1.0)
    static.sendTransform(a)
    static.sendTransform([make_tf("base", "b", 2.0), make_tf("base", "c", 3.0)])
    a.transform.translation.x = 99.0  # editing after sending changes nothing
    static.sendTransform(make_tf("other_parent", "a", 4.0))
    assert [(t.header.frame_id, t.child_frame_id, t.transform.translation.x)
            for t in static.transforms] == [
        ("other_parent", "a", 4.0), ("base", "b", 2.0), ("base", "c", 3.0)]
    latched: list[TFMessage] = []
    from posekit.tf2_ros import StaticListenerQoS

    late = Node("late", context=ctx)
    late.create_subscription(TFMessage, "/tf_static", latched.append, StaticListenerQoS())
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(late)
    ex.spin_some()
    assert len(latched) == 1  # depth 1: only the cumulative message
    assert [t.child_frame_id for t in latched[0].transforms] == ["a", "b", "c"]
    assert latched[0].transforms[0].transform.translation.x == 4.0


def test_backward_clock_jump_clears_buffer_with_warning(ctx, logs) -> None:
    br, ls = Broadcaster(context=ctx), Listener(context=ctx)
    ex = SimulatedTimeExecutor(context=ctx, start_time=10.0)
    ex.add_node(br)
    ex.add_node(ls)
    ex.run_until(11.0)
    assert ls.buffer.can_transform("odom", "base_link", Time(seconds=11))
    ex.set_time(3.0)  # e.g. a bag loop
    warnings = [r for r in logs if r.name == "tf_listener" and r.severity.name == "WARN"]
    assert [r.message for r in warnings] == ["Detected jump back in time. Clearing tf buffer."]
    with pytest.raises(TransformException):
        ls.buffer.lookup_transform("odom", "base_link", Time(seconds=11))
    # The static edge survives clear(); new dynamic data after the jump is accepted.
    assert ls.buffer.lookup_transform("base_link", "camera", Time()).transform.translation.z \
        == pytest.approx(0.2)
    ex.run_until(3.5)
    t = ls.buffer.lookup_transform("odom", "base_link", Time())
    assert t.transform.translation.x == pytest.approx(0.5 * 3.5)


def test_forward_jump_does_not_clear(ctx, logs) -> None:
    br, ls = Broadcaster(context=ctx), Listener(context=ctx)
    ex = SimulatedTimeExecutor(context=ctx, start_time=1.0)
    ex.add_node(br)
    ex.add_node(ls)
    ex.run_until(1.5)
    ex.set_time(100.0)
    assert ls.buffer.can_transform("odom", "base_link", Time(seconds=1.5))
    assert not [r for r in logs if "Clearing" in r.message]


def test_spin_thread_listener_receives_while_caller_blocks(ctx) -> None:
    talker = Node("talker", context=ctx)
    holder = Node("holder", context=ctx)
    buffer = Buffer()
    listener = TransformListener(buffer, holder, spin_thread=True)
    try:
        TransformBroadcaster(talker).sendTransform(make_tf("map", "robot", 2.0, stamp_ns=5))
        # No executor spins 'holder' or 'talker': the helper thread delivers /tf.
        t = buffer.lookup_transform("map", "robot", Time(), timeout=Duration(seconds=5))
        assert t.transform.translation.x == 2.0
    finally:
        listener.unregister()
