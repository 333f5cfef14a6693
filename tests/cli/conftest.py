"""Fixtures for the CLI tests that start real processes over Zenoh on loopback.

Every test points its processes at a fresh free port through ``POSEKIT_ZENOH_ROUTER`` (the
variable the transport honours), so tests never meet each other or a user's router, and every
process is killed at the end.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from _support.ports import free_port
from _support.world import World, use_zenoh_endpoint


@pytest.fixture
def world(tmp_path: Path) -> Iterator[World]:
    w = World(f"tcp/127.0.0.1:{free_port()}", tmp_path)
    try:
        yield w
    finally:
        w.close()


@pytest.fixture
def routed(world: World) -> World:
    """A world with ``posekit router`` running on its endpoint."""
    router = world.cli("router", "--listen", world.endpoint)
    router.wait_line(lambda s: "listening on" in s, 15, "the router to listen")
    return world


@pytest.fixture
def joined(world: World, monkeypatch: pytest.MonkeyPatch) -> World:
    """A world whose endpoint this test process's own Zenoh sessions use too."""
    use_zenoh_endpoint(monkeypatch, world.endpoint)
    return world
