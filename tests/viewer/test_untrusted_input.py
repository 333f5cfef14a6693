"""The viewer against what other peers and other web pages can send it.

Real ViewerServer over loopback sockets with aiohttp's client, fed by a real in-process
graph. Oracles: RFC 8259 (JSON has no inf/NaN, so every answer must parse with a strict
parser), the HTTP semantics local development servers use against DNS rebinding and
cross-site WebSockets (a Host or Origin that is not this server gets 403), and
``sys.modules`` / a marker file for "nothing was imported by a name from the graph".
"""

from __future__ import annotations

import asyncio
import json
import math
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any, ClassVar

import pytest

aiohttp = pytest.importorskip("aiohttp")
pytest.importorskip("cv2")

from posekit.msgs.geometry_msgs import TransformStamped  # noqa: E402
from posekit.runtime.context import Context  # noqa: E402
from posekit.runtime.logging import LogRecord, add_sink, remove_sink  # noqa: E402
from posekit.runtime.node import Node  # noqa: E402
from posekit.tf2_ros import (  # noqa: E402
    StaticTransformBroadcaster,
    TransformBroadcaster,
)
from posekit.viewer.server import ViewerServer  # noqa: E402
from posekit.viewer.taps import ViewerTap  # noqa: E402


def _strict(text: str) -> Any:
    """json.loads that refuses the non-standard Infinity/NaN tokens."""
    def refuse(token: str) -> Any:
        raise ValueError(f"non-standard JSON number {token}")

    return json.loads(text, parse_constant=refuse)


def _tf(parent: str, child: str, x: float, stamp_s: int = 1) -> TransformStamped:
    t = TransformStamped()
    t.header.frame_id = parent
    t.child_frame_id = child
    t.header.stamp.sec = stamp_s
    t.transform.translation.x = x
    t.transform.rotation.w = 1.0
    return t


class Graph:
    """A context with a publishing node and a viewer on a free loopback port."""

    def __init__(self, **options: Any) -> None:
        self.ctx = Context()
        self.ctx.init()
        self.node = Node("untrusted_pub", context=self.ctx)
        self.static = StaticTransformBroadcaster(self.node)
        self.dynamic = TransformBroadcaster(self.node)
        self.tap = ViewerTap(self.ctx.transport())
        self.server = ViewerServer(self.tap, port=0, close_tap=True, tf_rate=50.0, **options)
        self.server.start()
        self.http = self.server.url.rstrip("/")
        self.ws_url = self.http.replace("http://", "ws://") + "/ws"

    def close(self) -> None:
        self.server.stop()
        self.ctx.try_shutdown()


@pytest.fixture
def graph() -> Iterator[Graph]:
    g = Graph()
    yield g
    g.close()


@pytest.fixture
def warnings() -> Iterator[list[LogRecord]]:
    records: list[LogRecord] = []

    def sink(record: LogRecord) -> None:
        if record.name == "posekit_viewer":
            records.append(record)

    add_sink(sink)
    yield records
    remove_sink(sink)


async def _tf_until(ws: Any, predicate: Any, timeout: float = 10.0) -> dict[str, Any]:
    end = time.monotonic() + timeout
    while True:
        remaining = end - time.monotonic()
        assert remaining > 0, "timed out waiting for a tf message"
        msg = await ws.receive(timeout=remaining)
        assert msg.type == aiohttp.WSMsgType.TEXT, f"connection ended: {msg.type}"
        data = _strict(msg.data)
        if data.get("type") == "tf" and predicate(data):
            return dict(data)


def test_non_finite_transforms_never_stop_the_viewer(graph: Graph,
                                                     warnings: list[LogRecord]) -> None:
    # An infinite static, and two finite statics whose composition overflows to inf.
    graph.static.sendTransform([
        _tf("odom", "inf_frame", math.inf),
        _tf("odom", "big_a", 1e308),
        _tf("big_a", "big_b", 1e308),
        _tf("odom", "good_static", 2.0),
    ])
    graph.tap.refresh()

    async def scenario() -> None:
        async with aiohttp.ClientSession() as session:
            for _ in range(3):  # repeatedly: the answer does not depend on luck
                async with session.get(graph.http + "/api/state") as resp:
                    assert resp.status == 200
                    state = _strict(await resp.text())
                rows = {r[0]: r for r in state["frames"]}
                assert rows["inf_frame"][11] is False  # not available, not a crash
                assert rows["big_b"][11] is False
                assert rows["big_a"][2] == 1e308
                assert rows["big_a"][11] is True
                assert rows["good_static"][2:5] == [2.0, 0, 0]
            async with session.ws_connect(graph.ws_url) as ws:
                await _tf_until(ws, lambda d: any(r[0] == "good_static" for r in d["frames"]))
                # The feed is alive: a new dynamic frame arrives after the bad ones.
                await asyncio.get_running_loop().run_in_executor(None, graph.tap.refresh)
                graph.dynamic.sendTransform(_tf("odom", "late_frame", 0.5))
                await asyncio.get_running_loop().run_in_executor(None, graph.tap.refresh)
                graph.dynamic.sendTransform(_tf("odom", "late_frame", 0.5, stamp_s=2))
                tf = await _tf_until(ws, lambda d: any(r[0] == "late_frame" for r in d["frames"]))
                assert {r[0]: r for r in tf["frames"]}["late_frame"][2] == 0.5
            # A new WebSocket still opens and gets its hello.
            async with session.ws_connect(graph.ws_url) as ws:
                msg = await ws.receive(timeout=10.0)
                assert _strict(msg.data)["type"] == "hello"

    asyncio.run(scenario())
    assert graph.server.stats["producer_restarts"] == 0
    noted = [r for r in warnings if "non-finite pose" in r.message]
    assert 1 <= len(noted) <= 3  # rate-limited: one line per second, not one per update


def test_a_failing_producer_round_is_logged_and_the_feed_goes_on(
    graph: Graph, warnings: list[LogRecord]
) -> None:
    real_trails = graph.tap.trails_version
    failures = {"left": 5}

    def flaky() -> int:
        if failures["left"] > 0:
            failures["left"] -= 1
            raise RuntimeError("injected failure")
        return real_trails()

    graph.tap.trails_version = flaky  # type: ignore[method-assign]
    graph.static.sendTransform([_tf("odom", "after_failure", 1.0)])
    graph.tap.refresh()

    async def scenario() -> None:
        async with aiohttp.ClientSession() as session, session.ws_connect(graph.ws_url) as ws:
            await _tf_until(ws, lambda d: any(r[0] == "after_failure" for r in d["frames"]))
            end = time.monotonic() + 10.0
            while failures["left"] and time.monotonic() < end:
                await asyncio.sleep(0.02)
            graph.static.sendTransform([_tf("odom", "after_failure", 1.0),
                                        _tf("odom", "later", 3.0)])
            await _tf_until(ws, lambda d: any(r[0] == "later" for r in d["frames"]))

    asyncio.run(scenario())
    assert failures["left"] == 0
    assert graph.server.stats["producer_errors"] == 5
    lines = [r for r in warnings if "update failed" in r.message]
    assert 1 <= len(lines) <= 2
    assert "injected failure" in lines[0].message


class _ProbeType:
    """A class whose ROS type name points at an importable module (a peer could say so)."""

    __msgtype__: ClassVar[str] = ""


@pytest.mark.parametrize("pattern", ["{mod}.x::msg::dds_::T_", "{mod}.x/msg/T", "{mod}.Cls"])
def test_type_names_from_the_graph_are_never_imported(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, pattern: str
) -> None:
    module = f"posekit_probe_{abs(hash(pattern)) % 10**8}"
    marker = tmp_path / "imported"
    (tmp_path / f"{module}.py").write_text(
        f"open({str(marker)!r}, 'w').write('imported')\nclass Cls:\n    pass\n"
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    type_name = pattern.format(mod=module)
    probe = type("Probe", (_ProbeType,), {"__msgtype__": type_name})
    ctx = Context()
    ctx.init()
    try:
        node = Node("type_name_peer", context=ctx)
        node.create_publisher(probe, "/peer_topic", 1)
        tap = ViewerTap(ctx.transport())
        tap.refresh()
        row = {t["name"]: t for t in tap.topics()}["/peer_topic"]
        assert row["type"] == type_name
        assert "unknown message type" in row["error"]
        assert not marker.exists()
        assert module not in sys.modules
        tap.close()
    finally:
        ctx.try_shutdown()


def test_rosbags_types_are_still_resolved(graph: Graph) -> None:
    from posekit.viewer.taps import _resolve_class

    cls = _resolve_class("std_msgs/msg/Int64MultiArray")  # not posekit's, in rosbags' store
    assert cls is not None
    assert cls.__msgtype__ == "std_msgs/msg/Int64MultiArray"  # type: ignore[attr-defined]


def test_host_header_must_name_this_server(graph: Graph) -> None:
    port = graph.server.port

    async def status(host: str, path: str = "/api/state") -> int:
        async with aiohttp.ClientSession() as session, session.get(
            graph.http + path, headers={"Host": host}
        ) as resp:
            return resp.status

    async def scenario() -> None:
        for ok in (f"localhost:{port}", f"127.0.0.1:{port}", f"[::1]:{port}",
                   f"LOCALHOST:{port}"):
            assert await status(ok) == 200, ok
        # DNS rebinding: a page of attacker.example whose name now resolves to 127.0.0.1.
        for bad in (f"attacker.example:{port}", "attacker.example", f"localhost:{port + 1}",
                    f"127.0.0.1.attacker.example:{port}", ""):
            assert await status(bad) == 403, bad
            assert await status(bad, "/") == 403, bad

    asyncio.run(scenario())
    assert graph.server.stats["forbidden"] == 10


def test_websocket_origin_must_be_this_server(graph: Graph) -> None:
    port = graph.server.port

    async def connects(origin: str | None) -> bool | int:
        """True if the hello arrives, else the handshake's HTTP status."""
        headers = {} if origin is None else {"Origin": origin}
        async with aiohttp.ClientSession() as session:
            try:
                async with session.ws_connect(graph.ws_url, headers=headers) as ws:
                    msg = await ws.receive(timeout=10.0)
                    return bool(_strict(msg.data)["type"] == "hello")
            except aiohttp.WSServerHandshakeError as exc:
                return exc.status

    async def scenario() -> None:
        assert await connects(None) is True  # a script, not a browser
        assert await connects(f"http://127.0.0.1:{port}") is True
        assert await connects(f"http://localhost:{port}") is True
        assert await connects("https://evil.example") == 403
        assert await connects(f"http://evil.example:{port}") == 403
        assert await connects("null") == 403  # sandboxed iframe, file:// page

    asyncio.run(scenario())


def test_allow_lists_widen_the_checks() -> None:
    g = Graph(allow_hosts=["viewer.lan"], allow_origins=["http://viewer.lan:9000"])
    try:
        async def scenario() -> None:
            async with aiohttp.ClientSession() as session:
                async with session.get(g.http + "/api/state",
                                       headers={"Host": "viewer.lan:9000"}) as resp:
                    assert resp.status == 200
                async with session.get(g.http + "/api/state",
                                       headers={"Host": "other.lan"}) as resp:
                    assert resp.status == 403
                async with session.ws_connect(
                    g.ws_url, headers={"Origin": "http://viewer.lan:9000"}
                ) as ws:
                    msg = await ws.receive(timeout=10.0)
                    assert _strict(msg.data)["type"] == "hello"

        asyncio.run(scenario())
    finally:
        g.close()


def test_far_future_stamps_and_endless_frames_in_the_tap(graph: Graph,
                                                         warnings: list[LogRecord]) -> None:
    """The tap applies TransformListener's guards: a /tf sample stamped a year ahead of its
    clock does not freeze the frame (tf2 alone would refuse every later sample as
    TF_OLD_DATA), and frames beyond MAX_FRAMES are forgotten least recently updated first.
    Oracle: what a plain Buffer does with the same samples, and counts."""
    from posekit.tf2 import Buffer
    from posekit.viewer.taps import MAX_FRAMES

    graph.dynamic.sendTransform(_tf("odom", "probe", 0.0))  # make /tf known to the tap
    graph.tap.refresh()
    now = time.time_ns()
    year = 365 * 24 * 3600 * 10**9

    def at(ns: int, child: str = "base_link", x: float = 0.0) -> TransformStamped:
        t = _tf("odom", child, x)
        t.header.stamp.sec, t.header.stamp.nanosec = divmod(ns, 10**9)
        return t

    graph.dynamic.sendTransform(at(now + year, x=9.0))
    for k in range(1, 4):
        graph.dynamic.sendTransform(at(now + k * 10**8, x=float(k)))
    rows = {r[0]: r for r in graph.tap.frames_in("odom")[1]}
    assert rows["base_link"][2] == 3.0
    assert any("far in the future" in r.message for r in warnings)
    plain = Buffer()
    assert plain.set_transform(at(now + year), "peer")
    assert not plain.set_transform(at(now + 10**8), "peer")  # what the guard prevents

    for batch in range(MAX_FRAMES // 100 * 3 // 2):
        graph.dynamic.sendTransform(
            [at(now + batch, f"junk_{batch}_{i}") for i in range(100)]
            + [at(now + batch, "base_link", 5.0)])
    assert len(graph.tap.tree()) <= MAX_FRAMES
    assert len(graph.tap.buffer.get_all_frame_names()) <= MAX_FRAMES + 1  # plus "odom"
    assert {r["name"] for r in graph.tap.tree()} >= {"base_link"}


def test_the_tap_follows_a_bounded_number_of_topics(graph: Graph) -> None:
    """A peer announcing hundreds of topics: the tap subscribes to at most
    MAX_SUBSCRIBED_TOPICS (each is a subscription and, over Zenoh, a thread), /tf first, and
    lists the rest with the reason. Oracle: the transport's own subscriber counts."""
    from posekit.msgs.std_msgs import String
    from posekit.viewer.taps import MAX_SUBSCRIBED_TOPICS

    pubs = [graph.node.create_publisher(String, f"/aa_flood_{i:03d}", 1)
            for i in range(MAX_SUBSCRIBED_TOPICS + 50)]
    graph.dynamic.sendTransform(_tf("odom", "base_link", 1.0))  # /tf sorts after /aa_...
    graph.tap.refresh()
    transport = graph.ctx.transport()
    followed = [p.topic_name for p in pubs if transport.count_subscribers(p.topic_name)]
    assert len(followed) <= MAX_SUBSCRIBED_TOPICS
    assert transport.count_subscribers("/tf") == 1
    rows = {t["name"]: t for t in graph.tap.topics()}
    refused = [n for n, t in rows.items() if "at most" in t["error"]]
    flood_refused = [n for n in refused if n.startswith("/aa_flood_")]  # not /rosout etc.
    assert len(followed) + len(flood_refused) == len(pubs)
    assert refused
