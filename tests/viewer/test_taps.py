"""ViewerTap on the in-process bus: TF poses in a fixed frame (vs scipy), trails with RViz2's
tolerances, rates, latched /tf_static, bad input, and graph hygiene."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as R

from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.rosgraph_msgs import Clock
from posekit.msgs.sensor_msgs import Image
from posekit.runtime.context import Context
from posekit.runtime.logging import LogRecord, add_sink, remove_sink
from posekit.runtime.node import Node
from posekit.tf2_ros import StaticTransformBroadcaster, TransformBroadcaster
from posekit.viewer.taps import TRAIL_POSITION_TOLERANCE_M, ViewerTap

NS = 1_000_000_000


@pytest.fixture
def node(ctx: Context) -> Node:
    return Node("viewer_test_pub", context=ctx)


def transform(parent: str, child: str, xyz: Any, quat_xyzw: Any, stamp_ns: int) -> TransformStamped:
    t = TransformStamped()
    t.header.frame_id = parent
    t.child_frame_id = child
    t.header.stamp.sec, t.header.stamp.nanosec = divmod(stamp_ns, NS)
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = map(
        float, xyz)
    q = t.transform.rotation
    q.x, q.y, q.z, q.w = map(float, quat_xyzw)
    return t


def odometry(x: float, y: float, yaw: float, speed: float = 0.0, frame: str = "odom") -> Odometry:
    msg = Odometry()
    msg.header.frame_id = frame
    msg.child_frame_id = "base_link"
    msg.pose.pose.position.x, msg.pose.pose.position.y = x, y
    msg.pose.pose.orientation.z, msg.pose.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    msg.twist.twist.linear.x = speed
    return msg


def test_frames_in_fixed_frame_match_scipy_composition(ctx: Context, node: Node) -> None:
    rng = np.random.default_rng(3)
    chain = [("odom", "base_link"), ("base_link", "body_link"), ("body_link", "camera")]
    poses = {child: (rng.normal(size=3), R.random(random_state=rng)) for _, child in chain}
    dynamic = TransformBroadcaster(node)
    static = StaticTransformBroadcaster(node)
    tap = ViewerTap(ctx.transport())
    tap.refresh()
    for parent, child in chain:
        xyz, rot = poses[child]
        t = transform(parent, child, xyz, rot.as_quat(), 5 * NS)
        (static if child == "body_link" else dynamic).sendTransform(t)
    tap.refresh()
    for parent, child in chain:  # subscribed after the first publish: send the dynamic again
        if child != "body_link":
            xyz, rot = poses[child]
            dynamic.sendTransform(transform(parent, child, xyz, rot.as_quat(), 5 * NS))

    def T(child: str) -> np.ndarray:
        m = np.eye(4)
        m[:3, :3] = poses[child][1].as_matrix()
        m[:3, 3] = poses[child][0]
        return m

    T_odom = {"odom": np.eye(4), "base_link": T("base_link")}
    T_odom["body_link"] = T_odom["base_link"] @ T("body_link")
    T_odom["camera"] = T_odom["body_link"] @ T("camera")
    for fixed in ("odom", "body_link"):
        error, rows = tap.frames_in(fixed)
        assert error is None
        by_name = {r[0]: r for r in rows}
        assert set(by_name) == {"odom", "base_link", "body_link", "camera"}
        for name, row in by_name.items():
            expected = np.linalg.inv(T_odom[fixed]) @ T_odom[name]
            assert row[11] is True
            np.testing.assert_allclose(row[2:5], expected[:3, 3], atol=2e-5)
            got = R.from_quat(row[5:9])
            angle = (got.inv() * R.from_matrix(expected[:3, :3])).magnitude()
            assert angle < 1e-4
        assert by_name["body_link"][10] is True
        assert by_name["camera"][10] is False
        assert by_name["camera"][1] == "body_link"


def test_missing_fixed_frame_is_reported(ctx: Context, node: Node) -> None:
    tap = ViewerTap(ctx.transport())
    error, rows = tap.frames_in("odom")
    assert error is not None
    assert "Fixed Frame [odom] does not exist" in error
    assert rows == []
    TransformBroadcaster(node)
    tap.refresh()
    TransformBroadcaster(node).sendTransform(
        transform("map", "base_link", (1, 0, 0), (0, 0, 0, 1), NS))
    error, rows = tap.frames_in("odom")
    assert error == "Fixed Frame [odom] does not exist"
    assert {r[0] for r in rows} == {"map", "base_link"}
    assert not any(r[11] for r in rows)


def test_static_transforms_sent_before_the_tap_arrive(ctx: Context, node: Node) -> None:
    StaticTransformBroadcaster(node).sendTransform(
        transform("base_link", "imu_link", (0, 0.1, 0), (0, 0, 0, 1), 0))
    tap = ViewerTap(ctx.transport())
    tap.refresh()
    error, rows = tap.frames_in("base_link")
    assert error is None
    imu = {r[0]: r for r in rows}["imu_link"]
    assert imu[2:5] == [0.0, 0.1, 0.0]
    assert imu[10] is True
    assert [f["name"] for f in tap.tree()] == ["imu_link"]


def test_frame_rate_and_age_come_from_stamps(ctx: Context, node: Node) -> None:
    clock_ns = [0]
    tap = ViewerTap(ctx.transport(), clock_ns=lambda: clock_ns[0])
    pub = TransformBroadcaster(node)
    tap.refresh()
    for i in range(21):  # 20 Hz for one second of stamps
        pub.sendTransform(transform("odom", "base_link", (i, 0, 0), (0, 0, 0, 1), i * NS // 20))
    clock_ns[0] = 3 * NS
    (row,) = tap.tree()
    assert row["rate"] == pytest.approx(20.0)
    assert row["age"] == pytest.approx(2.0)
    assert row["parent"] == "odom"
    assert row["static"] is False


def test_sim_time_without_clock_uses_the_newest_stamp(ctx: Context, node: Node) -> None:
    tap = ViewerTap(ctx.transport())
    pub = TransformBroadcaster(node)
    tap.refresh()
    pub.sendTransform(transform("odom", "base_link", (0, 0, 0), (0, 0, 0, 1), 7 * NS))
    assert abs(tap.now_ns() - 7 * NS) < NS // 2  # not the wall clock (~1.7e18 ns)


def test_clock_drives_ages_and_a_backward_jump_clears(ctx: Context, node: Node) -> None:
    clock_pub = node.create_publisher(Clock, "/clock", 1)
    tf = TransformBroadcaster(node)
    tap = ViewerTap(ctx.transport())
    tap.refresh()
    tf.sendTransform(transform("odom", "base_link", (1, 0, 0), (0, 0, 0, 1), 10 * NS))
    msg = Clock()
    msg.clock.sec = 12
    clock_pub.publish(msg)
    assert tap.now_ns() == 12 * NS
    assert tap.tree()[0]["age"] == pytest.approx(2.0)
    msg.clock.sec = 1  # the run restarted
    clock_pub.publish(msg)
    error, rows = tap.frames_in("odom")
    assert error is None
    assert {r[0]: r for r in rows}["base_link"][11] is False  # buffer cleared


def test_trail_keeps_poses_past_rviz_tolerances(ctx: Context, node: Node) -> None:
    pub = node.create_publisher(Odometry, "/odometry/filtered", 10)
    tap = ViewerTap(ctx.transport(), trail_length=5)
    tap.refresh()
    step = 0.04
    xs = [i * step for i in range(30)]
    for x in xs:
        pub.publish(odometry(x, 0.0, 0.0, speed=0.4))
    # Independent replay of the rule: keep when >= 0.1 m from the last kept pose.
    kept = [xs[0]]
    for x in xs[1:]:
        if x - kept[-1] >= TRAIL_POSITION_TOLERANCE_M:
            kept.append(x)
    trail = tap.trails()["/odometry/filtered"]
    assert trail["received"] == 30
    assert trail["frame"] == "odom"
    assert [p[0] for p in trail["trail"]] == pytest.approx(kept[-5:])
    assert trail["trail"][-1][7] == pytest.approx(0.4)
    # Turning in place past 0.1 rad adds an arrow; 0.05 rad does not.
    before = len(tap.trails()["/odometry/filtered"]["trail"])
    pub.publish(odometry(xs[-1], 0.0, 0.05))
    pub.publish(odometry(kept[-1], 0.0, 0.15))
    after = tap.trails()["/odometry/filtered"]["trail"]
    assert len(after) == min(5, before + 1)
    assert after[-1][5] == pytest.approx(math.sin(0.075), abs=1e-4)


def test_bad_odometry_is_logged_and_the_tap_keeps_working(ctx: Context, node: Node) -> None:
    pub = node.create_publisher(Odometry, "/odometry/wheels", 10)
    tap = ViewerTap(ctx.transport())
    tap.refresh()
    records: list[LogRecord] = []
    add_sink(records.append)
    try:
        pub.publish(odometry(float("nan"), 0.0, 0.0))
    finally:
        remove_sink(records.append)
    assert any("bad message on /odometry/wheels" in r.message for r in records)
    pub.publish(odometry(1.0, 2.0, 0.0))
    assert tap.trails()["/odometry/wheels"]["trail"][0][:2] == [1.0, 2.0]


def test_images_newest_only_and_rates(ctx: Context, node: Node) -> None:
    pub = node.create_publisher(Image, "camera/image", 5)
    tap = ViewerTap(ctx.transport())
    tap.refresh()
    tap.set_image_watches(["/camera/image"])
    images = []
    for i in range(11):
        msg = Image(height=1, width=1, encoding="mono8", step=1, data=np.array([i], np.uint8))
        images.append(msg)
        pub.publish(msg)
        time.sleep(0.01)
    seq, newest = tap.latest_image("/camera/image")
    assert seq == 11
    assert int(newest.data[0]) == 10
    assert tap.image_topics() == ["/camera/image"]
    row = {t["name"]: t for t in tap.topics()}["/camera/image"]
    assert row["count"] == 11
    assert row["publishers"] == 1
    # 10 intervals of >= 10 ms: at most 100 Hz, and a loaded machine still gives > 10 Hz.
    assert 10.0 < row["rate"] <= 101.0


def test_image_topics_are_subscribed_only_while_watched(ctx: Context, node: Node) -> None:
    """An Image topic is listed but not subscribed (its publisher counts no subscriber, so a
    lazy camera renders nothing) until a page watches it or a display follows it; let go,
    it keeps no image, so a new watch waits for a new message."""
    from posekit.viewer.taps import ON_DEMAND_NOTE

    pub = node.create_publisher(Image, "/depth", 5)
    tap = ViewerTap(ctx.transport())
    tap.refresh()
    tap.refresh()
    assert pub.get_subscription_count() == 0
    assert tap.image_topics() == ["/depth"]
    assert any(t["name"] == "/depth" and t["error"] == ON_DEMAND_NOTE for t in tap.topics())
    pub.publish(Image(height=1, width=1, encoding="mono8", step=1, data=np.array([7], np.uint8)))
    assert tap.latest_image("/depth") is None
    tap.set_image_watches(["/depth", "/not_there"])
    assert pub.get_subscription_count() == 1
    pub.publish(Image(height=1, width=1, encoding="mono8", step=1, data=np.array([8], np.uint8)))
    seq, newest = tap.latest_image("/depth")  # type: ignore[misc]
    assert (seq, int(newest.data[0])) == (1, 8)
    tap.set_message_watches({"/depth": 1})  # a display follows it too: still one subscription
    tap.set_image_watches([])
    assert pub.get_subscription_count() == 1
    tap.set_message_watches({})
    assert pub.get_subscription_count() == 0
    assert tap.latest_image("/depth") is None
    tap.refresh()
    assert pub.get_subscription_count() == 0  # not observed again without a watch
    tap.set_image_watches(["/depth"])
    assert pub.get_subscription_count() == 1
    assert tap.latest_image("/depth") is None
    pub.publish(Image(height=1, width=1, encoding="mono8", step=1, data=np.array([9], np.uint8)))
    seq, newest = tap.latest_image("/depth")  # type: ignore[misc]
    assert seq > 1
    assert int(newest.data[0]) == 9
    tap.close()


def test_tap_creates_no_topics_and_skips_unknown_types(ctx: Context, node: Node) -> None:
    transport = ctx.transport()
    # only the /parameter_events and /rosout publishers every node has (as in ROS 2),
    # before and after
    own = [
        ("/parameter_events", ["rcl_interfaces/msg/ParameterEvent"]),
        ("/rosout", ["rcl_interfaces/msg/Log"]),
    ]
    assert transport.get_topic_names_and_types() == own
    tap = ViewerTap(transport)
    tap.refresh()
    assert transport.get_topic_names_and_types() == own

    @dataclass
    class Custom:  # a type the registry does not know, defined in a function
        value: int = 0
        __msgtype__: ClassVar[str] = "my_pkg/msg/Custom"

    pub = node.create_publisher(Custom, "custom", 1)
    tap.refresh()
    pub.publish(Custom(1))
    row = {t["name"]: t for t in tap.topics()}["/custom"]
    assert "unknown message type" in row["error"]
    assert row["count"] == 0
    assert transport.count_subscribers("/custom") == 0


def test_close_stops_listening(ctx: Context, node: Node) -> None:
    pub = node.create_publisher(Odometry, "/odometry/filtered", 10)
    tap = ViewerTap(ctx.transport())
    tap.refresh()
    assert ctx.transport().count_subscribers("/odometry/filtered") == 1
    tap.close()
    assert ctx.transport().count_subscribers("/odometry/filtered") == 0
    pub.publish(odometry(1.0, 0.0, 0.0))
    assert tap.trails() == {}


def test_trail_length_must_be_positive(ctx: Context) -> None:
    with pytest.raises(ValueError, match="trail_length"):
        ViewerTap(ctx.transport(), trail_length=0)


def test_rates_are_measured_on_the_sim_clock(ctx: Context, node: Node) -> None:
    """A 10 Hz-of-sim-time publisher reads 10 Hz however fast the wall clock goes (here it
    publishes as fast as possible); the oracle is the closed-form 1 / 0.1 s."""
    sim = {"ns": 100 * NS}
    pub = node.create_publisher(Image, "camera/image", 5)
    tap = ViewerTap(ctx.transport(), clock_ns=lambda: sim["ns"])
    tap.refresh()
    tap.set_image_watches(["/camera/image"])  # image topics are followed while watched
    for i in range(15):
        pub.publish(Image(height=1, width=1, encoding="mono8", step=1,
                          data=np.array([i], np.uint8)))
        sim["ns"] += NS // 10
    row = {t["name"]: t for t in tap.topics()}["/camera/image"]
    # receipts at 100.0 .. 101.4 s, now 101.5 s: 2 s window holds all 15, 14 intervals / 1.4 s
    assert row["rate"] == pytest.approx(10.0)
    state = tap.time_state()
    assert state["source"] == "executor"
    assert state["rate_clock"] == "sim"
    assert state["sim"] == pytest.approx(101.5)
    assert abs(state["wall"] - time.time()) < 5.0


def test_real_time_factor_is_sim_seconds_per_wall_second(ctx: Context) -> None:
    """A clock running at half the wall clock's speed measures RTF 0.5 (closed form)."""
    t0 = time.monotonic()
    tap = ViewerTap(ctx.transport(), clock_ns=lambda: int((time.monotonic() - t0) * 0.5 * NS))
    assert tap.time_state()["rtf"] is None  # one sample: not measured yet
    deadline = time.monotonic() + 5.0
    rtf = None
    while rtf is None and time.monotonic() < deadline:
        time.sleep(0.05)
        rtf = tap.time_state()["rtf"]
    assert rtf == pytest.approx(0.5, abs=0.02)


def test_time_state_follows_clock_else_the_wall(ctx: Context, node: Node) -> None:
    tap = ViewerTap(ctx.transport())
    wall = tap.time_state()
    assert (wall["source"], wall["sim"], wall["rtf"], wall["rate_clock"]) == (
        "wall", None, 1.0, "wall")
    pub = node.create_publisher(Clock, "/clock", 1)
    tap.refresh()
    msg = Clock()
    msg.clock.sec, msg.clock.nanosec = 42, 500_000_000
    pub.publish(msg)
    state = tap.time_state()
    assert (state["source"], state["sim"], state["rate_clock"]) == ("/clock", 42.5, "sim")


def test_best_effort_topics_arrive_and_topics_that_leave_are_dropped(
    ctx: Context, node: Node
) -> None:
    """A best-effort odometry publisher (a request of reliable would not match it) reaches
    the trail; a topic whose publisher is destroyed is unsubscribed and leaves the panel."""
    from posekit.runtime.qos import qos_profile_sensor_data

    pub = node.create_publisher(Odometry, "/odometry/filtered", qos_profile_sensor_data)
    tap = ViewerTap(ctx.transport())
    tap.refresh()
    pub.publish(odometry(1.5, 0.0, 0.0))
    assert tap.trails()["/odometry/filtered"]["trail"][0][0] == 1.5
    assert [t["name"] for t in tap.topics()].count("/odometry/filtered") == 1
    node.destroy_publisher(pub)
    for _ in range(3):  # the observer lets go after its grace refreshes
        tap.refresh()
    assert ctx.transport().count_subscribers("/odometry/filtered") == 0
    assert "/odometry/filtered" not in [t["name"] for t in tap.topics()]
    tap.close()


def test_point_clouds_are_subscribed_only_while_a_display_follows_them(
    ctx: Context, node: Node
) -> None:
    """A PointCloud2 topic is listed but not subscribed (its publisher counts no subscriber,
    so a lazy sensor renders nothing) until a display follows it; then its messages reach the
    display queue; when the display goes, so does the subscription."""
    from posekit.msgs.point_cloud2 import create_cloud
    from posekit.msgs.sensor_msgs import PointCloud2
    from posekit.msgs.std_msgs import Header
    from posekit.viewer.taps import ON_DEMAND_NOTE

    pub = node.create_publisher(PointCloud2, "/points", 5)
    tap = ViewerTap(ctx.transport())
    tap.refresh()
    tap.refresh()
    assert pub.get_subscription_count() == 0
    assert tap.topic_type("/points") == "sensor_msgs/msg/PointCloud2"
    assert any(t["name"] == "/points" and t["error"] == ON_DEMAND_NOTE
               for t in tap.topics())
    tap.set_message_watches({"/points": 1})
    assert pub.get_subscription_count() == 1
    pub.publish(create_cloud(Header(frame_id="f"), np.ones((4, 3), np.float32)))
    got = tap.messages_after("/points", 0)
    assert len(got) == 1
    assert got[0][1].width == 4
    tap.set_message_watches({})
    assert pub.get_subscription_count() == 0
    tap.refresh()
    assert pub.get_subscription_count() == 0  # not observed again without a display
    tap.close()
