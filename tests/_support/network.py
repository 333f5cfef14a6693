"""Two posekit contexts on one network transport, as two processes would be.

:func:`network_contexts` opens them on ``"zenoh"`` (a private router endpoint) or ``"dds"``
(a private ROS domain on loopback), skipping when that transport's library is missing, and
shuts both down at the end.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

import pytest

from _support.dds import dds_domain
from _support.ports import free_port
from _support.world import use_zenoh_endpoint
from posekit.runtime.context import Context


@contextlib.contextmanager
def network_contexts(transport: str,
                     monkeypatch: pytest.MonkeyPatch) -> Iterator[tuple[Context, Context]]:
    """``(first, second)``: two initialized contexts on ``transport`` (zenoh or dds)."""
    if transport == "zenoh":
        pytest.importorskip("zenoh")
        use_zenoh_endpoint(monkeypatch, f"tcp/127.0.0.1:{free_port()}")
    else:
        pytest.importorskip("cyclonedds")
        dds_domain(monkeypatch)
    first, second = Context(), Context()
    first.init(transport=transport)
    second.init(transport=transport)
    try:
        yield first, second
    finally:
        second.shutdown()
        first.shutdown()
