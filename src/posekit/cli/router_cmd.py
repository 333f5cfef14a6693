"""``posekit router [--listen ENDPOINT]``: run a Zenoh router (what ``rmw_zenohd`` is) until Ctrl-C.

Listens on ``tcp/127.0.0.1:7447`` unless ``--listen`` or ``$POSEKIT_ZENOH_ROUTER`` says
otherwise; loopback only by default. posekit processes and rmw_zenoh nodes connect to it and
then link to each other directly (gossip), so data keeps flowing between already linked
peers if the router stops. Exits 1 with the reason when the endpoint is taken.
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
import threading
from collections.abc import Sequence
from typing import Any, TextIO

__all__ = ["main"]


def main(argv: Sequence[str], *, out: TextIO | None = None, err: TextIO | None = None,
         stop: threading.Event | None = None) -> int:
    """Run the router until SIGINT/SIGTERM (or ``stop`` is set, for tests)."""
    from posekit.transport.zenoh_session import (
        DEFAULT_ROUTER_ENDPOINT,
        ZenohSessionError,
        open_router,
    )
    from posekit.transport.zenoh_transport import ENV_ROUTER

    out = out or sys.stdout
    err = err or sys.stderr
    parser = argparse.ArgumentParser(prog="posekit router")
    parser.add_argument(
        "--listen", default=os.environ.get(ENV_ROUTER, "").strip() or DEFAULT_ROUTER_ENDPOINT,
        help=f"endpoint to listen on (default ${ENV_ROUTER} or {DEFAULT_ROUTER_ENDPOINT})",
    )
    ns = parser.parse_args(list(argv))
    try:
        router = open_router(ns.listen)
    except ZenohSessionError as exc:
        err.write(f"posekit router: {exc}\n")
        return 1
    stop = stop or threading.Event()
    previous: dict[signal.Signals, Any] = {}
    if threading.current_thread() is threading.main_thread():
        for sig in (signal.SIGINT, signal.SIGTERM):
            previous[sig] = signal.signal(sig, lambda *_: stop.set())
    try:
        out.write(f"posekit router {router.info.zid()} listening on {ns.listen} "
                  "(Ctrl-C to stop)\n")
        out.flush()
        while not stop.wait(0.5):
            pass
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        router.close()  # type: ignore[no-untyped-call]
    out.write("posekit router stopped\n")
    out.flush()
    return 0
