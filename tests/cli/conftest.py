"""Fixtures of the command-line tests."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from _support.ports import free_port
from _support.procs import ProcGroup, use_zenoh_endpoint


@pytest.fixture
def group(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[ProcGroup]:
    """Processes on a fresh loopback router endpoint, which this test process uses too;
    all killed at the end."""
    g = ProcGroup(f"tcp/127.0.0.1:{free_port()}", tmp_path)
    use_zenoh_endpoint(monkeypatch, g.endpoint)
    try:
        yield g
    finally:
        g.close()
