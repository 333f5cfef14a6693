"""Bounded, seeded fuzzer: HTTP requests and WebSocket frames a browser page or a script can
send the viewer.

A real ViewerServer on a free loopback port, real aiohttp client. Oracle: HTTP semantics (no
request may produce a 5xx; every answer is one of the statuses the routes define), the
protocol in posekit.viewer.server (a malformed WebSocket request gets an ``error`` message
and the connection stays usable), and a final valid request answered normally.
"""

from __future__ import annotations

import asyncio
import json
import random
import string
from typing import Any

import pytest

aiohttp = pytest.importorskip("aiohttp")
pytest.importorskip("cv2")

from posekit.runtime.context import Context  # noqa: E402
from posekit.viewer.server import ViewerServer  # noqa: E402
from posekit.viewer.taps import ViewerTap  # noqa: E402

PATHS = ["/", "/api/state", "/ws", "/app/", "/app/main.js", "/vendor/three/", "/favicon.ico",
         "/app/../../etc/passwd", "/%2e%2e/%2e%2e/", "/api/state/../../"]
CHARS = string.printable + "é\u202e\U0001f916"
HEADER_CHARS = string.ascii_letters + string.digits + string.punctuation + " "


def _junk(rng: random.Random, n: int) -> str:
    return "".join(rng.choice(CHARS) for _ in range(rng.randint(0, n)))


def _ws_frame(rng: random.Random) -> str:
    kind = rng.randrange(6)
    if kind == 0:
        return _junk(rng, 200)
    if kind == 1:
        return json.dumps(rng.choice([[], 1, None, "x", {"op": None}]))
    if kind == 2:
        return json.dumps({"op": "fixed_frame", "frame": rng.choice(
            ["", "x" * 300, None, 5, ["a"], "/odom", _junk(rng, 30)])})
    if kind == 3:
        return json.dumps({"op": "watch", "topics": rng.choice(
            [None, "x", [1], [""], ["/t"] * 40, [_junk(rng, 20)]])})
    if kind == 4:
        return json.dumps({"op": "pause", "paused": rng.choice([True, 0, "no", None, {}])})
    return json.dumps({"op": _junk(rng, 10), "extra": [1] * rng.randint(0, 5)})


def test_random_requests_never_break_the_viewer() -> None:
    ctx = Context()
    ctx.init()
    server = ViewerServer(ViewerTap(ctx.transport()), port=0, close_tap=True)
    server.start()
    base = server.url.rstrip("/")
    rng = random.Random(21)
    statuses: dict[int, int] = {}

    async def scenario() -> None:
        async with aiohttp.ClientSession() as session:
            for _ in range(150):
                path = rng.choice(PATHS)
                if rng.random() < 0.5:
                    path += "?" + "&".join(
                        f"{_junk(rng, 8)}={_junk(rng, 40)}" for _ in range(rng.randint(0, 4)))
                headers = {}
                if rng.random() < 0.3:
                    headers["Host"] = rng.choice([f"127.0.0.1:{server.port}", "evil.example",
                                                  "".join(rng.choice(HEADER_CHARS)
                                                          for _ in range(12)).strip() or "x"])
                if rng.random() < 0.3:
                    headers["Origin"] = rng.choice(["null", "http://evil.example",
                                                    f"http://localhost:{server.port}"])
                method = rng.choice(["GET", "GET", "POST", "PUT", "HEAD"])
                async with session.request(method, base + path, headers=headers,
                                           data=_junk(rng, 100).encode()) as resp:
                    await resp.read()
                    statuses[resp.status] = statuses.get(resp.status, 0) + 1
            async with session.ws_connect(base + "/ws") as ws:
                errors = 0
                for _ in range(300):
                    if rng.random() < 0.1:
                        await ws.send_bytes(rng.randbytes(rng.randint(0, 64)))
                    else:
                        await ws.send_str(_ws_frame(rng))
                await ws.send_json({"op": "fixed_frame", "frame": "fuzz_done"})
                while True:
                    msg = await ws.receive(timeout=10.0)
                    assert msg.type == aiohttp.WSMsgType.TEXT, msg
                    data: dict[str, Any] = json.loads(msg.data)
                    if data.get("type") == "error":
                        errors += 1
                    if data.get("type") == "tf" and data.get("fixed") == "fuzz_done":
                        break
                assert errors > 0  # malformed requests were answered, not ignored
            async with session.get(base + "/api/state") as resp:
                assert resp.status == 200
                assert "frames" in await resp.json()

    try:
        asyncio.run(scenario())
    finally:
        server.stop()
        ctx.try_shutdown()
    assert sum(statuses.values()) == 150
    assert not any(status >= 500 for status in statuses), statuses
    assert set(statuses) <= {200, 204, 304, 400, 403, 404, 405}, statuses
