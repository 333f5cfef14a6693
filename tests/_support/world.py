"""Processes sharing one Zenoh router endpoint, all killed at the end (see World)."""

from __future__ import annotations

import os
import sys
import textwrap
from pathlib import Path
from typing import Any

from _support.procs import Proc, stop_all

#: Environment variables that would point a test's Zenoh sessions somewhere else.
ZENOH_ENV_PREFIXES = ("ZENOH_", "ROS_DOMAIN", "POSEKIT_")


def use_zenoh_endpoint(monkeypatch: Any, endpoint: str) -> None:
    """Point this test process's own Zenoh sessions at ``endpoint`` only (pytest monkeypatch)."""
    for name in list(os.environ):
        if name.startswith(ZENOH_ENV_PREFIXES):
            monkeypatch.delenv(name)
    monkeypatch.setenv("POSEKIT_ZENOH_ROUTER", endpoint)


class World:
    """Starts processes that share one router endpoint and kills them all at the end."""

    def __init__(self, endpoint: str, tmp: Path) -> None:
        self.endpoint = endpoint
        self.tmp = tmp
        self.procs: list[Proc] = []
        self.env = {k: v for k, v in os.environ.items() if not k.startswith(ZENOH_ENV_PREFIXES)}
        self.env.update(POSEKIT_ZENOH_ROUTER=endpoint, PYTHONUNBUFFERED="1")

    def cli(self, *args: str) -> Proc:
        return self._start([sys.executable, "-m", "posekit.cli.main", *args])

    def script(self, source: str, *args: str, transport_env: bool = True) -> Proc:
        env = dict(self.env)
        if transport_env:
            env["POSEKIT_TRANSPORT"] = "zenoh"
        return self._start([sys.executable, "-c", textwrap.dedent(source), *args], env)

    def _start(self, args: list[str], env: dict[str, str] | None = None) -> Proc:
        proc = Proc(args, env or self.env, cwd=self.tmp)
        self.procs.append(proc)
        return proc

    def close(self) -> None:
        stop_all(self.procs)
