"""ViewerServer over real sockets with aiohttp's client: protocol, images only when watched,
newest-only delivery to slow clients, bad requests, bind errors."""

from __future__ import annotations

import asyncio
import json
import socket
import struct
import time
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

aiohttp = pytest.importorskip("aiohttp")
cv2 = pytest.importorskip("cv2")

from _support.waiting import wait_for  # noqa: E402
from _support.websocket import receive_until  # noqa: E402
from posekit.msgs.geometry_msgs import TransformStamped  # noqa: E402
from posekit.msgs.image import numpy_to_image  # noqa: E402
from posekit.msgs.sensor_msgs import Image  # noqa: E402
from posekit.runtime.context import Context  # noqa: E402
from posekit.runtime.node import Node  # noqa: E402
from posekit.tf2_ros import TransformBroadcaster  # noqa: E402
from posekit.viewer import ViewerError  # noqa: E402
from posekit.viewer.server import ViewerServer, _Client  # noqa: E402
from posekit.viewer.taps import ViewerTap  # noqa: E402


class System:
    """A context with one publishing node and a viewer on a free port."""

    def __init__(self, **options: Any) -> None:
        self.ctx = Context()
        self.ctx.init()
        self.node = Node("server_test_pub", context=self.ctx)
        self.tf = TransformBroadcaster(self.node)
        self.image_pub = self.node.create_publisher(Image, "/camera/image", 5)
        self.tap = ViewerTap(self.ctx.transport())
        self.server = ViewerServer(self.tap, port=0, close_tap=True, **options)
        self.server.start()
        self.ws_url = self.server.url.replace("http://", "ws://") + "ws"

    def send_tf(self, x: float, stamp_s: float = 1.0) -> None:
        t = TransformStamped()
        t.header.frame_id = "odom"
        t.child_frame_id = "base_link"
        t.header.stamp.sec, t.header.stamp.nanosec = divmod(int(stamp_s * 1e9), 1_000_000_000)
        t.transform.translation.x = x
        self.tf.sendTransform(t)

    def close(self) -> None:
        self.server.stop()
        self.ctx.try_shutdown()


@pytest.fixture
def system() -> Iterator[System]:
    s = System(tf_rate=50.0, image_rate=30.0)
    yield s
    s.close()


def is_type(kind: str) -> Any:
    return lambda d: isinstance(d, dict) and d.get("type") == kind


def test_hello_tf_and_fixed_frame_over_websocket(system: System) -> None:
    async def scenario() -> None:
        async with aiohttp.ClientSession() as session, session.ws_connect(system.ws_url) as ws:
            hello = await receive_until(ws, is_type("hello"))
            assert hello["fixed_frame"] == "odom"
            assert hello["world"] is None
            await asyncio.get_running_loop().run_in_executor(None, system.tap.refresh)
            system.send_tf(1.5)
            tf = await receive_until(ws, lambda d: is_type("tf")(d) and d["frames"])
            rows = {r[0]: r for r in tf["frames"]}
            assert tf["fixed"] == "odom"
            assert tf["error"] is None
            assert rows["base_link"][2:9] == [1.5, 0, 0, 0, 0, 0, 1]
            await ws.send_json({"op": "fixed_frame", "frame": "base_link"})
            tf = await receive_until(ws, lambda d: is_type("tf")(d) and d["fixed"] == "base_link")
            assert {r[0]: r for r in tf["frames"]}["odom"][2:5] == [-1.5, 0, 0]
            await ws.send_json({"op": "fixed_frame", "frame": "map"})
            tf = await receive_until(ws, lambda d: is_type("tf")(d) and d["fixed"] == "map")
            assert tf["error"] == "Fixed Frame [map] does not exist"

    system.tap.refresh()
    asyncio.run(scenario())


def test_images_are_encoded_only_for_watchers(system: System) -> None:
    rgb = np.zeros((48, 64, 3), np.uint8)
    rgb[:, :, 0] = 200  # red in RGB
    msg = numpy_to_image(rgb, "rgb8")
    msg.header.stamp.sec = 3

    async def scenario() -> None:
        async with aiohttp.ClientSession() as session, session.ws_connect(system.ws_url) as ws:
            await receive_until(ws, is_type("hello"))
            system.image_pub.publish(msg)
            await asyncio.sleep(0.3)
            assert system.server.stats["images_encoded"] == 0  # nobody watches
            await ws.send_json({"op": "watch", "topics": ["/camera/image"]})
            assert wait_for(lambda: system.image_pub.get_subscription_count() == 1)
            system.image_pub.publish(msg)
            frame = await receive_until(ws, lambda d: isinstance(d, bytes))
            (n,) = struct.unpack(">I", frame[:4])
            header = json.loads(frame[4 : 4 + n])
            assert header["topic"] == "/camera/image"
            assert header["seq"] == 1
            assert (header["width"], header["height"], header["stamp"]) == (64, 48, 3.0)
            image = cv2.imdecode(np.frombuffer(frame[4 + n :], np.uint8), cv2.IMREAD_COLOR)
            assert np.abs(image.astype(int) - (0, 0, 200)).max() < 10  # BGR
            # The same image is not sent twice; unwatching stops images.
            await ws.send_json({"op": "watch", "topics": []})
            system.image_pub.publish(msg)
            encoded = system.server.stats["images_encoded"]
            await asyncio.sleep(0.3)
            assert system.server.stats["images_encoded"] == encoded == 1

    system.tap.refresh()
    asyncio.run(scenario())


def test_an_image_topic_is_subscribed_only_while_a_client_watches_it(system: System) -> None:
    """The server lists /camera/image (graph messages) without subscribing to it: its
    publisher counts no subscriber, so a lazy camera renders nothing. A client's watch (what
    the page's Image and Camera displays send while enabled) subscribes it; the topic stays
    subscribed while any client watches it and is let go when the last one stops watching
    or disconnects."""
    count = system.image_pub.get_subscription_count
    msg = numpy_to_image(np.full((8, 8, 3), 90, np.uint8), "rgb8")

    async def scenario() -> None:
        async with aiohttp.ClientSession() as session:
            async with session.ws_connect(system.ws_url) as ws:
                await receive_until(ws, is_type("hello"))
                # Two graph rounds (each after a refresh of the tap) list the topic...
                for _ in range(2):
                    graph = await receive_until(
                        ws, lambda d: is_type("graph")(d) and "/camera/image" in d["images"])
                assert count() == 0  # ... and nobody subscribed to it
                row = {t["name"]: t for t in graph["topics"]}["/camera/image"]
                assert row["count"] == 0
                await ws.send_json({"op": "watch", "topics": ["/camera/image"]})
                assert wait_for(lambda: count() == 1)
                system.image_pub.publish(msg)
                await receive_until(ws, lambda d: isinstance(d, bytes))
                async with session.ws_connect(system.ws_url) as other:
                    await receive_until(other, is_type("hello"))
                    await other.send_json({"op": "watch", "topics": ["/camera/image"]})
                    # Its watch is handled once it gets the newest image.
                    await receive_until(other, lambda d: isinstance(d, bytes))
                    await ws.send_json({"op": "watch", "topics": []})
                    await ws.send_json({"op": "no_such_op"})
                    # Requests are handled in order: the error answer follows the unwatch.
                    await receive_until(ws, is_type("error"))
                    assert count() == 1  # the other client still watches
                assert wait_for(lambda: count() == 0)  # its connection closed
                await ws.send_json({"op": "watch", "topics": ["/camera/image"]})
                assert wait_for(lambda: count() == 1)
            assert wait_for(lambda: count() == 0)

    system.tap.refresh()
    asyncio.run(scenario())


def test_slow_client_gets_newest_only() -> None:
    client = _Client.__new__(_Client)
    client.slots, client.dropped = {}, 0
    client.wake = asyncio.Event()
    for i in range(100):
        client.put("tf", f"tf {i}")
        client.put("image:/a", f"a {i}".encode())
    assert client.slots == {"tf": "tf 99", "image:/a": b"a 99"}
    assert client.dropped == 198


def test_a_client_that_never_reads_keeps_memory_bounded() -> None:
    system = System(image_rate=60.0, jpeg_quality=100)
    rng = np.random.default_rng(0)
    noise = [rng.integers(0, 255, (720, 1280, 3), np.uint8) for _ in range(3)]

    async def scenario() -> None:
        async with aiohttp.ClientSession() as session, session.ws_connect(system.ws_url) as ws:
            await ws.send_json({"op": "watch", "topics": ["/camera/image"]})
            assert wait_for(lambda: system.image_pub.get_subscription_count() == 1)
            for i in range(40):  # ~1 MB incompressible frames, never read by this client
                system.image_pub.publish(numpy_to_image(noise[i % 3], "rgb8"))
                await asyncio.sleep(0.03)
            clients = list(system.server._clients)
            assert len(clients) == 1
            assert len(clients[0].slots) <= 4  # hello/graph/tf/odom/image: one each at most
            assert system.server.stats["dropped"] > 0

    try:
        system.tap.refresh()
        asyncio.run(scenario())
    finally:
        system.close()


def test_bad_requests_get_an_error_and_the_connection_stays(system: System) -> None:
    async def scenario() -> None:
        async with aiohttp.ClientSession() as session, session.ws_connect(system.ws_url) as ws:
            await receive_until(ws, is_type("hello"))
            for bad in ("not json", "[1, 2]", json.dumps({"op": "explode"}),
                        json.dumps({"op": "fixed_frame", "frame": ""}),
                        json.dumps({"op": "watch", "topics": "x"})):
                await ws.send_str(bad)
                err = await receive_until(ws, is_type("error"))
                assert err["message"].startswith("bad request")
            await ws.send_json({"op": "fixed_frame", "frame": "odom"})
            assert (await receive_until(ws, is_type("tf")))["fixed"] == "odom"

    asyncio.run(scenario())


def test_http_routes(system: System) -> None:
    async def scenario() -> None:
        async with aiohttp.ClientSession() as session:
            async with session.get(system.server.url) as r:
                assert r.status == 200
                assert "posekit viewer" in await r.text()
            async with session.get(system.server.url + "app/main.js") as r:
                assert r.status == 200
            async with session.get(system.server.url + "api/state?fixed_frame=odom") as r:
                state = await r.json()
                assert {r[0] for r in state["frames"]} == {"odom", "base_link"}

    system.tap.refresh()
    system.send_tf(2.0)
    asyncio.run(scenario())


def test_address_in_use_raises_viewer_error() -> None:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        sock.listen()
        port = sock.getsockname()[1]
        ctx = Context()
        ctx.init()
        server = ViewerServer(ViewerTap(ctx.transport()), port=port)
        with pytest.raises(ViewerError, match=f"127.0.0.1:{port}"):
            server.start()
        ctx.shutdown()


def test_options_are_validated() -> None:
    ctx = Context()
    ctx.init()
    tap = ViewerTap(ctx.transport())
    for bad in ({"tf_rate": 0}, {"tf_rate": 101}, {"image_rate": 0}, {"jpeg_quality": 101},
                {"port": 70000}, {"fps": 0}):
        with pytest.raises(ValueError, match=next(iter(bad))):
            ViewerServer(tap, **bad)
    ctx.shutdown()


def _listen(system: System, msg_type: type, topic: str) -> tuple[list[Any], Any]:
    """A subscription of the system's node to ``topic``: the received messages, and a call
    that spins (at most 5 s) until one arrived."""
    from posekit.runtime.executors import SingleThreadedExecutor

    got: list[Any] = []
    system.node.create_subscription(msg_type, topic, got.append, 10)
    executor = SingleThreadedExecutor(context=system.ctx)
    executor.add_node(system.node)

    def received() -> None:
        deadline = time.monotonic() + 5.0
        while not got and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.05)

    return got, received


def test_goal_requests_publish_a_pose_stamped_and_bad_ones_are_refused(system: System) -> None:
    """``op: goal`` publishes geometry_msgs/PoseStamped on /goal_pose (received by a plain
    subscriber; the quaternion checked against the closed form (0, 0, sin(yaw/2),
    cos(yaw/2))); non-finite, non-numeric, huge or frameless goals get one error each and
    publish nothing; the goal comes back in ``graph`` for drawing."""
    import math

    from posekit.msgs.geometry_msgs import PoseStamped
    got, received = _listen(system, PoseStamped, "goal_pose")

    async def scenario() -> None:
        async with aiohttp.ClientSession() as session, session.ws_connect(system.ws_url) as ws:
            await receive_until(ws, is_type("hello"))
            good = {"op": "goal", "frame": "odom", "x": 1.25, "y": -2.0, "yaw": 2.0}
            for bad in ('{"op": "goal", "frame": "odom", "x": NaN, "y": 0, "yaw": 0}',
                        '{"op": "goal", "frame": "odom", "x": 1e999, "y": 0, "yaw": 0}',
                        json.dumps({**good, "yaw": "north"}),
                        json.dumps({**good, "x": True}),
                        json.dumps({**good, "y": 1e9}),
                        json.dumps({**good, "frame": ""}),
                        json.dumps({**good, "frame": "f" * 300})):
                await ws.send_str(bad)
                err = await receive_until(ws, is_type("error"))
                assert err["message"].startswith("bad request"), err
            await ws.send_json(good)
            sent = await receive_until(ws, is_type("goal_sent"))
            assert (sent["frame"], sent["x"], sent["y"], sent["yaw"]) == ("odom", 1.25, -2.0, 2.0)
            graph = await receive_until(ws, lambda d: is_type("graph")(d) and d.get("goal"))
            assert graph["goal"]["frame"] == "odom"
            assert graph["goal"]["pose"][:3] == pytest.approx([1.25, -2.0, 0.0])

    asyncio.run(scenario())
    received()
    assert len(got) == 1, "exactly the one valid goal is published"
    msg = got[0]
    assert msg.header.frame_id == "odom"
    assert (msg.pose.position.x, msg.pose.position.y, msg.pose.position.z) == (1.25, -2.0, 0.0)
    q = msg.pose.orientation
    assert (q.x, q.y, q.z, q.w) == pytest.approx((0.0, 0.0, math.sin(1.0), math.cos(1.0)))
    assert system.server.stats["goals"] == 1


def test_initial_pose_requests_publish_rviz2s_pose_estimate(system: System) -> None:
    """``op: initial_pose`` publishes geometry_msgs/PoseWithCovarianceStamped on /initialpose
    with RViz2's covariance (0.25 m² on x and y, (pi/12)² rad² on yaw, zero elsewhere); a bad
    one gets an error and publishes nothing."""
    import math

    from posekit.msgs.geometry_msgs import PoseWithCovarianceStamped
    got, received = _listen(system, PoseWithCovarianceStamped, "initialpose")

    async def scenario() -> None:
        async with aiohttp.ClientSession() as session, session.ws_connect(system.ws_url) as ws:
            await receive_until(ws, is_type("hello"))
            good = {"op": "initial_pose", "frame": "odom", "x": -0.5, "y": 3.0, "yaw": -1.0}
            await ws.send_json({**good, "yaw": None})
            err = await receive_until(ws, is_type("error"))
            assert "yaw" in err["message"]
            await ws.send_json(good)
            sent = await receive_until(ws, is_type("initial_pose_sent"))
            assert (sent["frame"], sent["x"], sent["y"], sent["yaw"]) == ("odom", -0.5, 3.0, -1.0)

    asyncio.run(scenario())
    received()
    assert len(got) == 1, "exactly the one valid pose is published"
    msg = got[0]
    assert msg.header.frame_id == "odom"
    p, q = msg.pose.pose.position, msg.pose.pose.orientation
    assert (p.x, p.y, p.z) == (-0.5, 3.0, 0.0)
    assert (q.x, q.y, q.z, q.w) == pytest.approx((0.0, 0.0, math.sin(-0.5), math.cos(-0.5)))
    expected = np.zeros(36)
    expected[0] = expected[7] = 0.25
    expected[35] = (math.pi / 12) ** 2
    assert np.array_equal(msg.pose.covariance, expected)
    assert system.server.stats["initial_poses"] == 1
