"""``posekit launch ... --viewer`` serves the run's viewer with the same access checks as
``posekit view``: its own names by default, ``--allow-host``/``--allow-origin`` widen them.

Oracles: the HTTP status the server gives for each Host header (the rule written in
docs/security.md), and the TF frames of the simulated ROSbot in its state (the robot
description's static frames, e.g. ``imu_link`` and ``cover_link``).
"""

from __future__ import annotations

import json
import os
import sys
import urllib.error
import urllib.request
from pathlib import Path

import pytest

from _support.ports import free_port
from _support.procs import Proc

pytest.importorskip("aiohttp")

pytestmark = pytest.mark.slow


def _get(url: str, host: str) -> tuple[int, bytes]:
    request = urllib.request.Request(url, headers={"Host": host})
    try:
        with urllib.request.urlopen(request, timeout=10) as resp:
            return resp.status, resp.read()
    except urllib.error.HTTPError as exc:
        return exc.code, b""


def test_launch_viewer_takes_the_allow_lists(tmp_path: Path) -> None:
    port = free_port()
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    proc = Proc([sys.executable, "-m", "posekit.cli.main", "launch", "empty_world",
                 "--isolated", "--realtime", "--viewer", "--port", str(port),
                 "--allow-host", "viewer.lan"], env, cwd=tmp_path)
    try:
        proc.wait_line(lambda line: line.startswith("viewer: http://"), 60, "the viewer")
        url = f"http://127.0.0.1:{port}/api/state"
        status, body = _get(url, f"viewer.lan:{port}")
        assert status == 200
        frames = {f["name"] for f in json.loads(body)["tree"]}
        assert {"imu_link", "cover_link"} <= frames, frames
        assert _get(url, f"127.0.0.1:{port}")[0] == 200  # its own names still work
        assert _get(url, "other.lan")[0] == 403  # and nothing else
    finally:
        proc.kill()
