"""Reading a viewer WebSocket in tests (aiohttp's client)."""

from __future__ import annotations

import json
import time
from typing import Any

import aiohttp


async def receive_until(ws: Any, predicate: Any, timeout: float = 5.0, *,
                        binary: bool = True) -> Any:
    """The first frame for which ``predicate`` holds: text frames as parsed JSON, binary
    frames as bytes (skipped unless ``binary``). Raises AssertionError after ``timeout``
    seconds or when the connection ends."""
    end = time.monotonic() + timeout
    while True:
        remaining = end - time.monotonic()
        if remaining <= 0:
            raise AssertionError("timed out waiting for a message")
        try:
            msg = await ws.receive(timeout=remaining)
        except TimeoutError:
            raise AssertionError("timed out waiting for a message") from None
        if msg.type == aiohttp.WSMsgType.TEXT:
            data = json.loads(msg.data)
        elif msg.type == aiohttp.WSMsgType.BINARY:
            if not binary:
                continue
            data = msg.data
        else:
            raise AssertionError(f"connection ended: {msg.type}")
        if predicate(data):
            return data
