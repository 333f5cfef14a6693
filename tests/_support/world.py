"""Processes sharing one Zenoh router endpoint, all killed at the end (see World)."""

from __future__ import annotations

import sys
import textwrap

from _support.procs import Proc, ProcGroup


class World(ProcGroup):
    """A :class:`ProcGroup` with shorthands: ``cli("topic", "list")`` runs ``posekit topic
    list``; ``script(source)`` runs Python source with ``POSEKIT_TRANSPORT=zenoh``."""

    def cli(self, *args: str) -> Proc:
        return self.posekit(*args)

    def script(self, source: str, *args: str, transport_env: bool = True) -> Proc:
        env = {"POSEKIT_TRANSPORT": "zenoh"} if transport_env else {}
        return self.start([sys.executable, "-c", textwrap.dedent(source), *args], env)
