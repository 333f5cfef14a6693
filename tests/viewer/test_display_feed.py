"""The display feed: messages of any topic as JSON for the page's displays.

Oracles: the messages as published (fields read back from the Python objects), numpy's own
decoding of the packed bytes (``np.frombuffer`` of the base64 payload), the JSON text parsed
by the standard library, and the WebSocket protocol spoken with aiohttp's plain client.
"""

from __future__ import annotations

import asyncio
import base64
import json
import math
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

aiohttp = pytest.importorskip("aiohttp")

from _support.websocket import receive_until as receive_text_until  # noqa: E402
from posekit.msgs.nav_msgs import Odometry  # noqa: E402
from posekit.msgs.sensor_msgs import LaserScan  # noqa: E402
from posekit.runtime.context import Context  # noqa: E402
from posekit.runtime.node import Node  # noqa: E402
from posekit.viewer.display_feed import PACK_MIN, MessageQueue, message_to_json  # noqa: E402
from posekit.viewer.errors import ViewerOptionError  # noqa: E402
from posekit.viewer.server import ViewerServer, load_view_config  # noqa: E402
from posekit.viewer.taps import ViewerTap  # noqa: E402

ODOM_TYPE = "nav_msgs/msg/Odometry"


def unpack(value: dict[str, Any]) -> np.ndarray:
    raw = base64.b64decode(value["$bin"])
    return np.frombuffer(raw, np.dtype(value["dtype"]).newbyteorder("<")).reshape(value["shape"])


def test_message_to_json_packs_large_arrays_and_keeps_small_ones() -> None:
    scan = LaserScan()
    scan.header.frame_id = "laser"
    scan.angle_increment = 0.01
    scan.ranges = np.linspace(0.5, 4.0, 360, dtype=np.float32)
    scan.intensities = np.arange(5, dtype=np.float32)
    out = json.loads(json.dumps(message_to_json(scan)))
    assert out["header"]["frame_id"] == "laser"
    assert math.isclose(out["angle_increment"], 0.01, rel_tol=1e-6)
    assert set(out["ranges"]) == {"$bin", "dtype", "shape"}
    assert out["ranges"]["dtype"] == "float32"
    assert np.array_equal(unpack(out["ranges"]), scan.ranges)
    assert out["intensities"] == [0.0, 1.0, 2.0, 3.0, 4.0]  # short: a plain list
    odom = Odometry()
    odom.pose.covariance = np.arange(36, dtype=np.float64)
    assert PACK_MIN >= 36
    assert message_to_json(odom)["pose"]["covariance"] == list(range(36))


def test_message_queue_numbers_and_bounds() -> None:
    q = MessageQueue(3)
    for i in range(5):
        q.append(i)
    assert q.after(0) == [(3, 2), (4, 3), (5, 4)]
    assert q.after(4) == [(5, 4)]
    q.resize(1)
    assert q.after(0) == [(5, 4)]


class System:
    """A context with one publishing node and a viewer on a free port."""

    def __init__(self, **options: Any) -> None:
        self.ctx = Context()
        self.ctx.init()
        self.node = Node("display_feed_test", context=self.ctx)
        self.pub = self.node.create_publisher(Odometry, "/test/odom", 10)
        self.tap = ViewerTap(self.ctx.transport())
        self.server = ViewerServer(self.tap, port=0, close_tap=True, **options)
        self.server.start()
        self.ws_url = self.server.url.replace("http://", "ws://") + "ws"

    def odom(self, x: float) -> Odometry:
        msg = Odometry()
        msg.header.frame_id = "odom"
        msg.child_frame_id = "base_link"
        msg.pose.pose.position.x = x
        msg.pose.pose.orientation.w = 1.0
        msg.pose.covariance = np.diag([0.04, 0.01, 0, 0, 0, 0.1]).ravel()
        return msg

    def close(self) -> None:
        self.server.stop()
        self.ctx.try_shutdown()


@pytest.fixture
def system() -> Iterator[System]:
    s = System(tf_rate=50.0)
    s.tap.refresh()
    yield s
    s.close()


async def receive_until(ws: Any, predicate: Any, timeout: float = 5.0) -> Any:
    """The first text frame (parsed JSON) for which ``predicate`` holds."""
    return await receive_text_until(ws, predicate, timeout, binary=False)


def is_display(topic: str) -> Any:
    return lambda d: d.get("type") == "display" and d.get("topic") == topic


def test_a_display_gets_the_newest_message_then_each_new_one_once(system: System) -> None:
    system.pub.publish(system.odom(0.5))  # before the display exists: sent on subscribe

    async def scenario() -> None:
        async with aiohttp.ClientSession() as session, session.ws_connect(system.ws_url) as ws:
            await ws.send_json({"op": "display_subscribe", "topic": "/test/odom",
                                "type": ODOM_TYPE})
            first = await receive_until(ws, is_display("/test/odom"))
            assert len(first["messages"]) == 1
            msg = first["messages"][0]
            assert msg["pose"]["pose"]["position"]["x"] == 0.5
            assert msg["header"]["frame_id"] == "odom"
            assert msg["pose"]["covariance"][0] == 0.04
            for x in (1.0, 2.0, 3.0):
                system.pub.publish(system.odom(x))
            # Newest only (queue 1): whatever arrives is newer than what came before.
            seen: list[float] = []
            while not seen or seen[-1] != 3.0:
                d = await receive_until(ws, is_display("/test/odom"))
                assert len(d["messages"]) == 1
                seen.append(d["messages"][0]["pose"]["pose"]["position"]["x"])
            assert seen == sorted(set(seen))
            await ws.send_json({"op": "display_unsubscribe", "topic": "/test/odom"})
            end = time.monotonic() + 5.0  # the server drops the topic's queue
            while system.tap.messages_after("/test/odom", 0):
                assert time.monotonic() < end, "the unsubscribed topic is still kept"
                await asyncio.sleep(0.02)

    asyncio.run(scenario())


def test_a_queued_display_gets_every_message_in_order(system: System) -> None:
    async def scenario() -> None:
        async with aiohttp.ClientSession() as session, session.ws_connect(system.ws_url) as ws:
            await ws.send_json({"op": "display_subscribe", "topic": "/test/odom",
                                "type": ODOM_TYPE, "queue": 50})
            ack = await receive_until(ws, lambda d: d.get("type") == "display_subscribed")
            assert (ack["topic"], ack["msg_type"], ack["queue"]) == ("/test/odom", ODOM_TYPE, 50)
            for i in range(20):
                system.pub.publish(system.odom(float(i)))
            xs: list[float] = []
            while len(xs) < 20:
                d = await receive_until(ws, is_display("/test/odom"))
                xs += [m["pose"]["pose"]["position"]["x"] for m in d["messages"]]
            assert xs == [float(i) for i in range(20)]

    asyncio.run(scenario())


@pytest.mark.parametrize(("request_", "reason"), [
    ({"topic": "/test/odom", "type": "geometry_msgs/msg/PoseStamped"}, "carries"),
    ({"topic": "/test/odom", "type": "not a type"}, "'type'"),
    ({"topic": "relative", "type": ODOM_TYPE}, "fully qualified"),
    ({"topic": "/test/odom", "type": ODOM_TYPE, "queue": 0}, "'queue'"),
    ({"topic": "/test/odom", "type": ODOM_TYPE, "queue": True}, "'queue'"),
])
def test_bad_display_requests_are_refused_with_the_reason(
    system: System, request_: dict[str, Any], reason: str
) -> None:
    async def scenario() -> None:
        async with aiohttp.ClientSession() as session, session.ws_connect(system.ws_url) as ws:
            await ws.send_json({"op": "display_subscribe", **request_})
            error = await receive_until(ws, lambda d: d.get("type") == "error")
            assert reason in error["message"]
            await ws.send_json({"op": "pause", "paused": False})  # still connected
            assert not ws.closed

    asyncio.run(scenario())
    assert system.tap.messages_after("/test/odom", 0) == []


def test_display_modules_are_listed(system: System) -> None:
    async def scenario() -> dict[str, Any]:
        async with aiohttp.ClientSession() as session, \
                session.get(system.server.url + "api/displays") as r:
            assert r.status == 200
            data: dict[str, Any] = await r.json()
            return data

    modules = asyncio.run(scenario())["modules"]
    names = {m.rsplit("/", 1)[1] for m in modules}
    assert {"odometry.js", "pose.js", "pose_array.js", "path.js", "marker.js", "image.js",
            "tf.js"} <= names
    assert not any(n.startswith("_") for n in names)  # helpers are not displays


def test_view_config_file_is_checked_and_sent_in_hello(tmp_path: Path) -> None:
    good = tmp_path / "view.json"
    config = {"posekit_view": 1, "fixed_frame": "base_link",
              "topic_displays": [{"display": "Odometry", "topic": "/test/odom",
                                  "type": ODOM_TYPE, "enabled": True, "options": {}}]}
    good.write_text(json.dumps(config))
    assert load_view_config(good) == config
    for name, text, reason in [("a.json", "{not json", "not JSON"),
                               ("b.json", '{"posekit_view": 2}', "not a posekit view"),
                               ("c.json", "[1, 2]", "not a posekit view")]:
        path = tmp_path / name
        path.write_text(text)
        with pytest.raises(ViewerOptionError, match=reason):
            load_view_config(path)
    with pytest.raises(ViewerOptionError, match="cannot read"):
        load_view_config(tmp_path / "missing.json")
    big = tmp_path / "big.json"
    big.write_text(" " * ((1 << 20) + 1))
    with pytest.raises(ViewerOptionError, match="1 MiB"):
        load_view_config(big)

    s = System(config=good)
    try:
        async def scenario() -> dict[str, Any]:
            async with aiohttp.ClientSession() as session, \
                    session.ws_connect(s.ws_url) as ws:
                hello: dict[str, Any] = await receive_until(ws, lambda d: d["type"] == "hello")
                return hello

        assert asyncio.run(scenario())["config"] == config
    finally:
        s.close()
