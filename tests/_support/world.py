"""Processes sharing one Zenoh router endpoint, all killed at the end (see World)."""

from __future__ import annotations

import os
import sys
import textwrap
from pathlib import Path

from _support.procs import Proc


class World:
    """Starts processes that share one router endpoint and kills them all at the end."""

    def __init__(self, endpoint: str, tmp: Path) -> None:
        self.endpoint = endpoint
        self.tmp = tmp
        self.procs: list[Proc] = []
        self.env = {k: v for k, v in os.environ.items()
                    if not k.startswith(("ZENOH_", "ROS_DOMAIN", "POSEKIT_"))}
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
        for proc in reversed(self.procs):
            proc.kill()
        for proc in self.procs:
            for stream in (proc.popen.stdout, proc.popen.stderr):
                if stream is not None:
                    stream.close()
