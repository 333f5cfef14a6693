"""FoxgloveBridge over a real socket, spoken to by a plain aiohttp WebSocket client: the
``foxglove.sdk.v1`` and ``foxglove.websocket.v1`` handshakes, the ``time`` capability
following /clock, ``clientPublish`` of a PoseStamped serialized by rosbags and received by a
posekit subscriber, advertised channels with ros2msg schemas, CDR payloads decoded
by rosbags' own typestore (independent of posekit's serializer), /tf_static re-sent to late
subscribers, the missing-package error, a busy port, and a clean stop."""

from __future__ import annotations

import asyncio
import contextlib
import json
import socket
import struct
import sys
from collections.abc import AsyncIterator, Iterator
from typing import Any

import pytest

aiohttp = pytest.importorskip("aiohttp")
pytest.importorskip("foxglove", reason="foxglove-sdk is not installed (pip install foxglove-sdk)")

from rosbags.typesys import Stores, get_typestore  # noqa: E402

from _support.websocket import receive_until  # noqa: E402
from posekit.msgs.geometry_msgs import TransformStamped  # noqa: E402
from posekit.msgs.nav_msgs import Odometry  # noqa: E402
from posekit.runtime.context import Context  # noqa: E402
from posekit.runtime.executors import SingleThreadedExecutor  # noqa: E402
from posekit.runtime.node import Node  # noqa: E402
from posekit.tf2_ros import (  # noqa: E402
    StaticTransformBroadcaster,
    TransformBroadcaster,
)
from posekit.viewer import ViewerError, foxglove_bridge  # noqa: E402
from posekit.viewer.foxglove_bridge import FOXGLOVE_SUBPROTOCOL, FoxgloveBridge  # noqa: E402

pytestmark = pytest.mark.timeout(30)

ROS = get_typestore(Stores.ROS2_JAZZY)  # rosbags' stock classes, not posekit's
WANTED = {"/tf", "/tf_static", "/odometry/filtered"}
# First line of each ROS 2 (Jazzy) .msg definition.
FIRST_LINES = {
    "tf2_msgs/msg/TFMessage": "geometry_msgs/TransformStamped[] transforms",
    "nav_msgs/msg/Odometry": "std_msgs/Header header",
}


def _transform(parent: str, child: str, x: float, sec: int) -> TransformStamped:
    t = TransformStamped()
    t.header.frame_id = parent
    t.header.stamp.sec = sec
    t.child_frame_id = child
    t.transform.translation.x = x
    return t


class System:
    """A context publishing /tf_static (before the bridge exists), /tf and odometry."""

    def __init__(self) -> None:
        self.ctx = Context()
        self.ctx.init()
        self.node = Node("foxglove_test_pub", context=self.ctx)
        self.static = StaticTransformBroadcaster(self.node)
        self.static.sendTransform(_transform("base_link", "camera_link", 0.12, 0))
        self.tf = TransformBroadcaster(self.node)
        self.odom_pub = self.node.create_publisher(Odometry, "/odometry/filtered", 10)
        self.bridge = FoxgloveBridge(self.ctx.transport(), port=0, refresh_period=0.1)
        self.bridge.start()
        self.url = f"ws://127.0.0.1:{self.bridge.port}"

    def publish(self, x: float) -> None:
        self.tf.sendTransform(_transform("odom", "base_link", x, 5))
        odom = Odometry()
        odom.header.frame_id = "odom"
        odom.child_frame_id = "base_link"
        odom.pose.pose.position.x = x
        odom.twist.twist.linear.x = 0.25
        self.odom_pub.publish(odom)

    def close(self) -> None:
        self.bridge.stop()
        self.ctx.try_shutdown()


@pytest.fixture
def system() -> Iterator[System]:
    s = System()
    try:
        yield s
    finally:
        s.close()


async def _advertised(
    ws: Any, wanted: set[str], *, first: bool = True, timeout: float = 5.0
) -> dict[str, dict[str, Any]]:
    """Read text frames until every topic of ``wanted`` is advertised; topic -> channel.
    ``first``: these are a new connection's first frames, which start with serverInfo.
    Every reader here has one deadline for the whole wait (``receive_until``): the bridge
    sends a ``time`` frame every 50 ms, so a per-frame timeout would never expire."""
    channels: dict[str, dict[str, Any]] = {}
    server_info = False

    def note(data: Any) -> bool:
        nonlocal server_info
        if data["op"] == "serverInfo":
            server_info = True
        elif data["op"] == "advertise":
            channels.update({c["topic"]: c for c in data["channels"]})
        return wanted <= channels.keys()

    await receive_until(ws, note, timeout, binary=False)  # time (opcode 2) may come any time
    assert server_info == first
    return channels


def _message_of(sub_id: int) -> Any:
    """Predicate: a messageData frame (opcode 1) of subscription ``sub_id``."""
    return lambda data: (isinstance(data, bytes) and data[0] == 1
                         and struct.unpack_from("<I", data, 1)[0] == sub_id)


async def _message(ws: Any, sub_id: int, timeout: float = 5.0) -> tuple[int, bytes]:
    """The next messageData frame of subscription ``sub_id``: (log_time ns, payload)."""
    data = await receive_until(ws, _message_of(sub_id), timeout)
    (log_time,) = struct.unpack_from("<Q", data, 5)
    return log_time, bytes(data[13:])


async def _publish_until_message(ws: Any, sub_id: int, publish: Any) -> bytes:
    """Call ``publish()`` until subscription ``sub_id`` delivers a message (the server
    registers a subscription asynchronously); its payload. Bounded: 40 tries, 0.5 s each."""
    for _attempt in range(40):
        publish()
        with contextlib.suppress(AssertionError):  # receive_until's timeout
            _, payload = await _message(ws, sub_id, 0.5)
            return payload
    raise AssertionError(f"subscription {sub_id} received nothing within 20 s")


async def _subscribe(ws: Any, channel_id: int, sub_id: int) -> None:
    await ws.send_str(json.dumps(
        {"op": "subscribe", "subscriptions": [{"id": sub_id, "channelId": channel_id}]}
    ))


@pytest.mark.parametrize("subprotocol", ["foxglove.sdk.v1", "foxglove.websocket.v1"])
def test_plain_client_gets_channels_and_cdr_messages(system: System, subprotocol: str) -> None:
    async def go() -> None:
        async with aiohttp.ClientSession() as session, _connect(session,
            system.url, protocols=(subprotocol,)
        ) as ws:
            assert ws.protocol == subprotocol
            system.publish(1.0)  # /tf and /odometry/filtered get publishers' first message
            channels = await _advertised(ws, WANTED)
            for topic in WANTED:
                ch = channels[topic]
                assert ch["encoding"] == "cdr"
                assert ch["schemaEncoding"] == "ros2msg"
                assert ch["schema"].splitlines()[0] == FIRST_LINES[ch["schemaName"]]
            assert channels["/tf"]["schemaName"] == "tf2_msgs/msg/TFMessage"
            assert channels["/odometry/filtered"]["schemaName"] == "nav_msgs/msg/Odometry"
            # Dependencies are appended as "MSG: pkg/Type" sections (ROS 2 MCAP format).
            assert "MSG: geometry_msgs/TransformStamped" in channels["/tf"]["schema"]

            # /tf_static was published before the bridge existed: re-sent on subscribe.
            await _subscribe(ws, channels["/tf_static"]["id"], 1)
            _, payload = await _message(ws, 1)
            static = ROS.deserialize_cdr(payload, "tf2_msgs/msg/TFMessage")
            assert [t.child_frame_id for t in static.transforms] == ["camera_link"]
            assert static.transforms[0].header.frame_id == "base_link"
            assert static.transforms[0].transform.translation.x == pytest.approx(0.12)

            await _subscribe(ws, channels["/odometry/filtered"]["id"], 2)
            payload = await _publish_until_message(ws, 2, lambda: system.publish(2.5))
            odom = ROS.deserialize_cdr(payload, "nav_msgs/msg/Odometry")
            assert odom.child_frame_id == "base_link"
            assert odom.pose.pose.position.x == pytest.approx(2.5)
            assert odom.twist.twist.linear.x == pytest.approx(0.25)

            # A second, later client also gets the latched static transform.
            async with _connect(session, system.url, protocols=(subprotocol,)) as ws2:
                channels2 = await _advertised(ws2, WANTED)
                await _subscribe(ws2, channels2["/tf_static"]["id"], 7)
                _, payload = await _message(ws2, 7)
                static2 = ROS.deserialize_cdr(payload, "tf2_msgs/msg/TFMessage")
                assert static2.transforms[0].child_frame_id == "camera_link"

    asyncio.run(go())
    assert set(system.bridge.topics()) >= WANTED


def test_new_topics_are_advertised_after_start(system: System) -> None:
    async def go() -> None:
        async with aiohttp.ClientSession() as session, _connect(session,
            system.url, protocols=(FOXGLOVE_SUBPROTOCOL,)
        ) as ws:
            await _advertised(ws, WANTED)
            system.node.create_publisher(Odometry, "/odometry/wheels", 10)
            later = await _advertised(ws, {"/odometry/wheels"}, first=False)  # background refresh
            assert later["/odometry/wheels"]["schemaName"] == "nav_msgs/msg/Odometry"

    asyncio.run(go())


def test_stop_closes_the_port(system: System) -> None:
    port = system.bridge.port
    system.bridge.stop()
    system.bridge.stop()  # idempotent
    with pytest.raises(ConnectionRefusedError), socket.create_connection(
        ("127.0.0.1", port), timeout=1.0
    ):
        pass


def test_busy_port_is_a_named_error() -> None:
    ctx = Context()
    ctx.init()
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        sock.listen()
        bridge = FoxgloveBridge(ctx.transport(), port=sock.getsockname()[1])
        with pytest.raises(ViewerError, match="cannot serve Foxglove"):
            bridge.start()
        bridge.stop()
    ctx.try_shutdown()


def test_missing_package_is_a_clear_error(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "foxglove", None)  # import foxglove -> ImportError
    ctx = Context()
    ctx.init()
    bridge = FoxgloveBridge(ctx.transport(), port=0)
    with pytest.raises(ViewerError, match="foxglove-sdk"):
        bridge.start()
    ctx.try_shutdown()


def test_bad_arguments() -> None:
    ctx = Context()
    ctx.init()
    with pytest.raises(ValueError, match="port"):
        FoxgloveBridge(ctx.transport(), port=70000)
    with pytest.raises(ValueError, match="refresh_period"):
        FoxgloveBridge(ctx.transport(), refresh_period=-1.0)
    ctx.try_shutdown()


def test_cli_bridge_serves_the_p_controller_scenario_on_sim_time() -> None:
    import posekit.robot.scenarios  # noqa: F401 - registers the robot's scenarios
    from posekit.cli.view_cmd import _parser, _sim_clock, _start_foxglove, main
    from posekit.launch.scenarios import start_scenario

    assert main(["--foxglove", "--foxglove-port", "70000"]) == 2
    ns = _parser().parse_args(["--foxglove", "--foxglove-port", "0"])
    assert _parser().parse_args([]).foxglove_port == 8766  # the documented default
    run = start_scenario("p_controller")
    bridge = None
    try:
        run.executor.run_for(1.0)
        bridge = _start_foxglove(ns, run.context.transport(), _sim_clock(run))
        assert bridge is not None
        assert bridge.host == "127.0.0.1"  # loopback unless --host says otherwise
        # Every topic with a publisher (an independent graph query) becomes a channel, but
        # the P controller's action feedback (a pkg/action/ type has no ros2msg schema text).
        transport = run.context.transport()
        graph = {
            t for t, types in transport.get_topic_names_and_types()
            if transport.count_publishers(t) > 0 and "/action/" not in types[0]
        }
        assert "/navigate_to_pose/_action/status" in graph
        assert {"/tf", "/tf_static", "/odometry/filtered", "/odometry/wheels"} <= graph
        url = f"ws://127.0.0.1:{bridge.port}"

        async def go() -> None:
            async with aiohttp.ClientSession() as session, _connect(session,
                url, protocols=(FOXGLOVE_SUBPROTOCOL,)
            ) as ws:
                channels = await _advertised(ws, graph)
                assert channels.keys() == graph
                await _subscribe(ws, channels["/tf_static"]["id"], 3)
                log_time, payload = await _message(ws, 3)
                # Logged at the run's simulated time, not the wall clock.
                assert log_time == run.executor.now_ns == 1_000_000_000
                static = ROS.deserialize_cdr(payload, "tf2_msgs/msg/TFMessage")
                assert static.transforms
                assert all(t.header.frame_id and t.child_frame_id for t in static.transforms)

        asyncio.run(go())
    finally:
        if bridge is not None:
            bridge.stop()
        run.shutdown()


@contextlib.asynccontextmanager
async def _connect(session: aiohttp.ClientSession, url: str,
                   **kwargs: Any) -> AsyncIterator[aiohttp.ClientWebSocketResponse]:
    """``session.ws_connect(url, **kwargs)``, closed within 2 s at the end: aiohttp's close
    reads frames until the server's close frame, and the bridge keeps sending ``time``
    frames, so an unanswered close would otherwise never end."""
    ws = await session.ws_connect(url, **kwargs)
    try:
        yield ws
    finally:
        with contextlib.suppress(TimeoutError):
            await asyncio.wait_for(ws.close(), 2.0)


async def _server_info(ws: Any) -> dict[str, Any]:
    info = await receive_until(ws, lambda data: data["op"] == "serverInfo", binary=False)
    return dict(info)


def _time_is(ns: int) -> Any:
    """Predicate: a ``time`` frame (opcode 2, u64 ns) saying ``ns``."""
    return lambda data: (isinstance(data, bytes) and data[0] == 2
                         and struct.unpack_from("<Q", data, 1)[0] == ns)


@pytest.mark.parametrize("subprotocol", ["foxglove.sdk.v1", "foxglove.websocket.v1"])
def test_time_follows_clock_and_a_client_publishes_a_goal(system: System,
                                                           subprotocol: str) -> None:
    from posekit.msgs.geometry_msgs import PoseStamped
    from posekit.msgs.rosgraph_msgs import Clock

    clock_pub = system.node.create_publisher(Clock, "/clock", 10)
    goals: list[Any] = []
    system.node.create_subscription(PoseStamped, "goal_pose", goals.append, 10)
    executor = SingleThreadedExecutor(context=system.ctx)
    executor.add_node(system.node)
    sim_ns = 42 * 1_000_000_000 + 5  # far from the wall clock: only /clock can say it

    async def go() -> None:
        async with aiohttp.ClientSession() as session, _connect(session,
            system.url, protocols=(subprotocol,)
        ) as ws:
            info = await _server_info(ws)
            assert {"time", "clientPublish"} <= set(info["capabilities"])
            assert "cdr" in info["supportedEncodings"]
            clock = Clock()
            clock.clock.sec, clock.clock.nanosec = divmod(sim_ns, 1_000_000_000)
            for _attempt in range(20):  # bounded: 20 tries, 0.3 s each
                clock_pub.publish(clock)  # the bridge subscribes to /clock on its next refresh
                with contextlib.suppress(AssertionError):  # receive_until's timeout
                    await receive_until(ws, _time_is(sim_ns), 0.3)
                    break
            else:
                raise AssertionError("no time frame said the published /clock within 6 s")

            # clientPublish: advertise goal_pose, send a PoseStamped serialized by rosbags.
            await ws.send_str(json.dumps({"op": "advertise", "channels": [{
                "id": 3, "topic": "goal_pose", "encoding": "cdr",
                "schemaName": "geometry_msgs/msg/PoseStamped"}]}))
            Pose, Header = ROS.types["geometry_msgs/msg/PoseStamped"], ROS.types[
                "std_msgs/msg/Header"]
            R = ROS.types
            ros_goal = Pose(
                header=Header(stamp=R["builtin_interfaces/msg/Time"](sec=42, nanosec=0),
                              frame_id="odom"),
                pose=R["geometry_msgs/msg/Pose"](
                    position=R["geometry_msgs/msg/Point"](x=1.5, y=-0.5, z=0.0),
                    orientation=R["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0)),
            )
            payload = bytes(ROS.serialize_cdr(ros_goal, "geometry_msgs/msg/PoseStamped"))
            loop = asyncio.get_running_loop()
            deadline = loop.time() + 5.0
            while not goals and loop.time() < deadline:
                await ws.send_bytes(struct.pack("<BI", 1, 3) + payload)  # opcode 1: data
                await asyncio.sleep(0.05)
                executor.spin_once(timeout_sec=0.0)

    asyncio.run(go())
    assert goals, "the published goal never reached a posekit subscriber"
    goal = goals[0]
    assert goal.header.frame_id == "odom"
    assert (goal.pose.position.x, goal.pose.position.y) == pytest.approx((1.5, -0.5))
    assert goal.pose.orientation.w == pytest.approx(1.0)


@pytest.mark.parametrize("subprotocol", ["foxglove.sdk.v1", "foxglove.websocket.v1"])
def test_a_client_publishes_in_json(system: System, subprotocol: str) -> None:
    """clientPublish with message encoding json: a PoseWithCovarianceStamped written as a
    JSON object (what Foxglove's Publish panel sends) reaches a posekit subscriber with the
    values given and defaults elsewhere; a field the type lacks is dropped with one logged
    line and the channel keeps working."""
    from posekit.msgs.geometry_msgs import PoseWithCovarianceStamped

    poses: list[Any] = []
    system.node.create_subscription(PoseWithCovarianceStamped, "initialpose", poses.append, 10)
    executor = SingleThreadedExecutor(context=system.ctx)
    executor.add_node(system.node)
    covariance = [0.0] * 36
    covariance[0], covariance[7], covariance[35] = 0.25, 0.25, 0.0685
    good = {"header": {"stamp": {"sec": 7, "nanosec": 500}, "frame_id": "odom"},
            "pose": {"pose": {"position": {"x": 2.5, "y": -1.0},
                              "orientation": {"z": 0.6, "w": 0.8}},
                     "covariance": covariance}}
    bad = {"pose": {"pose": {"position": {"x": 1.0, "q": 3}}}}

    async def go() -> None:
        async with aiohttp.ClientSession() as session, _connect(session,
            system.url, protocols=(subprotocol,)
        ) as ws:
            info = await _server_info(ws)
            assert "json" in info["supportedEncodings"]
            await ws.send_str(json.dumps({"op": "advertise", "channels": [{
                "id": 4, "topic": "initialpose", "encoding": "json",
                "schemaName": "geometry_msgs/msg/PoseWithCovarianceStamped"}]}))
            loop = asyncio.get_running_loop()
            deadline = loop.time() + 5.0
            while not poses and loop.time() < deadline:
                await ws.send_bytes(struct.pack("<BI", 1, 4) + json.dumps(bad).encode())
                await ws.send_bytes(struct.pack("<BI", 1, 4) + json.dumps(good).encode())
                await asyncio.sleep(0.05)
                executor.spin_once(timeout_sec=0.0)

    asyncio.run(go())
    assert poses, "the published pose never reached a posekit subscriber"
    assert all(p.pose.pose.position.x == 2.5 for p in poses)  # the bad ones were dropped
    msg = poses[0]
    assert msg.header.frame_id == "odom"
    assert (msg.header.stamp.sec, msg.header.stamp.nanosec) == (7, 500)
    p = msg.pose.pose
    assert (p.position.x, p.position.y, p.position.z) == (2.5, -1.0, 0.0)
    assert (p.orientation.x, p.orientation.z, p.orientation.w) == (0.0, 0.6, 0.8)
    assert list(msg.pose.covariance) == covariance


def test_other_subprotocols_and_foreign_hosts_are_refused(system: System) -> None:
    async def go() -> None:
        async with aiohttp.ClientSession() as session:
            with pytest.raises(aiohttp.WSServerHandshakeError) as no_proto:
                await session.ws_connect(system.url)
            assert no_proto.value.status == 400
            with pytest.raises(aiohttp.WSServerHandshakeError) as other:
                await session.ws_connect(system.url, protocols=("chat.v2",))
            assert other.value.status == 400
            with pytest.raises(aiohttp.WSServerHandshakeError) as rebound:
                await session.ws_connect(system.url, protocols=(FOXGLOVE_SUBPROTOCOL,),
                                         headers={"Host": f"evil.example:{system.bridge.port}"})
            assert rebound.value.status == 403
            # a web page of another site open in the user's browser (it could publish)
            with pytest.raises(aiohttp.WSServerHandshakeError) as foreign:
                await session.ws_connect(system.url, protocols=(FOXGLOVE_SUBPROTOCOL,),
                                         headers={"Origin": "https://evil.example"})
            assert foreign.value.status == 403
            own = f"http://127.0.0.1:{system.bridge.port}"  # a page of this server: accepted
            async with _connect(session, system.url, protocols=(FOXGLOVE_SUBPROTOCOL,),
                                          headers={"Origin": own}) as ws:
                assert ws.protocol == FOXGLOVE_SUBPROTOCOL

    asyncio.run(go())


def test_laser_scan_and_point_cloud_decode_from_the_advertised_schema(system: System) -> None:
    """LaserScan and PointCloud2 (a best-effort publisher, as sensor drivers use) reach a
    client on channels whose ros2msg schema decodes them: mcap-ros2-support builds its
    decoder from the advertised schema text alone, as Foxglove does."""
    import numpy as np
    from mcap_ros2._dynamic import generate_dynamic

    from posekit.msgs.point_cloud2 import create_cloud
    from posekit.msgs.sensor_msgs import LaserScan, PointCloud2
    from posekit.msgs.std_msgs import Header
    from posekit.runtime.qos import qos_profile_sensor_data

    scan_pub = system.node.create_publisher(LaserScan, "/scan", 10)
    cloud_pub = system.node.create_publisher(PointCloud2, "/points", qos_profile_sensor_data)
    scan = LaserScan()
    scan.header.frame_id = "laser"
    scan.angle_min, scan.angle_max, scan.angle_increment = -1.5, 1.5, 0.75
    scan.range_min, scan.range_max = 0.05, 30.0
    scan.ranges = np.array([1.25, np.inf, 2.5, -np.inf, 0.5], dtype=np.float32)
    scan.intensities = np.array([10, 0, 20, 0, 30], dtype=np.float32)
    xyz = np.array([[1.0, 2.0, 3.0], [-0.5, 0.25, 4.0]], dtype=np.float32)
    cloud = create_cloud(Header(frame_id="oak_rgb_camera_optical_frame"), xyz)

    async def go() -> None:
        async with aiohttp.ClientSession() as session, _connect(session,
            system.url, protocols=(FOXGLOVE_SUBPROTOCOL,)
        ) as ws:
            channels = await _advertised(ws, {"/scan", "/points"})
            decoded: dict[str, Any] = {}
            for sub_id, (topic, msg, pub) in enumerate(
                    [("/scan", scan, scan_pub), ("/points", cloud, cloud_pub)], start=10):
                ch = channels[topic]
                assert (ch["encoding"], ch["schemaEncoding"]) == ("cdr", "ros2msg")
                await _subscribe(ws, ch["id"], sub_id)
                payload = await _publish_until_message(
                    ws, sub_id, lambda pub=pub, msg=msg: pub.publish(msg))
                decoder = generate_dynamic(ch["schemaName"], ch["schema"])[ch["schemaName"]]
                decoded[topic] = decoder(payload)
            got_scan, got_cloud = decoded["/scan"], decoded["/points"]
            assert channels["/scan"]["schemaName"] == "sensor_msgs/msg/LaserScan"
            assert channels["/points"]["schemaName"] == "sensor_msgs/msg/PointCloud2"
            assert got_scan.header.frame_id == "laser"
            np.testing.assert_array_equal(np.asarray(got_scan.ranges, np.float32), scan.ranges)
            np.testing.assert_array_equal(np.asarray(got_scan.intensities, np.float32),
                                          scan.intensities)
            assert got_scan.angle_increment == 0.75
            assert [(f.name, f.offset, f.datatype, f.count) for f in got_cloud.fields] == [
                ("x", 0, 7, 1), ("y", 4, 7, 1), ("z", 8, 7, 1)]
            assert (got_cloud.width, got_cloud.height, got_cloud.point_step) == (2, 1, 12)
            points = np.frombuffer(bytes(got_cloud.data), np.float32).reshape(2, 3)
            np.testing.assert_array_equal(points, xyz)

    asyncio.run(go())


def test_a_topic_whose_publishers_leave_is_unadvertised(system: System) -> None:
    async def go() -> None:
        async with aiohttp.ClientSession() as session, _connect(session,
            system.url, protocols=(FOXGLOVE_SUBPROTOCOL,)
        ) as ws:
            pub = system.node.create_publisher(Odometry, "/odometry/wheels", 10)
            channels = await _advertised(ws, {"/odometry/wheels"})
            system.node.destroy_publisher(pub)
            channel_id = channels["/odometry/wheels"]["id"]
            # The background refresh notices within a few periods.
            await receive_until(ws, lambda data: (data["op"] == "unadvertise"
                                                  and channel_id in data["channelIds"]),
                                binary=False)
            assert "/odometry/wheels" not in system.bridge.topics()

    asyncio.run(go())


def test_a_latched_topic_reaches_clients_that_subscribe_later(system: System) -> None:
    """/robot_description is published once, transient local, before any client connects
    (as robot_state_publisher does); each client that subscribes later still receives it."""
    from posekit.msgs.std_msgs import String
    from posekit.runtime.qos import DurabilityPolicy, QoSProfile

    latched = system.node.create_publisher(
        String, "/robot_description",
        QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    latched.publish(String(data="<robot name='rosbot'/>"))
    system.bridge.refresh()  # observed (and the latched sample taken) with no client yet

    async def go() -> None:
        async with aiohttp.ClientSession() as session:
            for sub_id in (21, 22):  # two clients, one after the other
                async with _connect(session, system.url,
                                              protocols=(FOXGLOVE_SUBPROTOCOL,)) as ws:
                    channels = await _advertised(ws, {"/robot_description"})
                    await _subscribe(ws, channels["/robot_description"]["id"], sub_id)
                    _, payload = await _message(ws, sub_id)
                    msg = ROS.deserialize_cdr(payload, "std_msgs/msg/String")
                    assert msg.data == "<robot name='rosbot'/>"

    asyncio.run(go())


def test_topics_and_static_frames_are_bounded(monkeypatch: pytest.MonkeyPatch) -> None:
    # Topic and frame names are the peers' choice: the bridge serves at most MAX_TOPICS
    # topics (the rest are listed as skipped, with the reason) and keeps at most
    # MAX_STATIC_FRAMES static frames for late clients (a frame it keeps is still updated).
    monkeypatch.setattr(foxglove_bridge, "MAX_TOPICS", 3)
    monkeypatch.setattr(foxglove_bridge, "MAX_STATIC_FRAMES", 2)
    system = System()  # /tf_static: base_link -> camera_link before the bridge exists
    try:
        for i in range(6):
            system.node.create_publisher(Odometry, f"/flood_{i}", 10)
        system.static.sendTransform([_transform("base_link", f"extra_{i}", 0.1, 0)
                                     for i in range(4)])
        system.static.sendTransform(_transform("base_link", "camera_link", 0.5, 0))
        system.bridge.refresh()
        assert len(system.bridge.topics()) == 3
        assert any("at most 3 topics" in reason for reason in system.bridge.skipped().values())
        kept = dict(system.bridge._static)  # what a late client would be sent
        assert len(kept) == 2
        assert "camera_link" in kept
        assert kept["camera_link"].transform.translation.x == 0.5
    finally:
        system.close()
