"""posekit on the DDS transport in tests: one ROS domain per test, discovery on loopback.

:func:`free_domain` picks a ROS domain nothing on this machine uses right now (another test,
another checkout's test run, a real ROS 2 system), :func:`dds_domain` points this process
(``ROS_DOMAIN_ID``, LOCALHOST discovery) at one, so tests running at the same time never
meet; :func:`dds_context`
is a posekit context on the ``dds`` transport there; :func:`posekit_env` is the environment
for a posekit child process on the same domain.
"""

from __future__ import annotations

import contextlib
import os
import random
import socket
import time
from collections.abc import Callable, Iterator

import pytest

from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor


def _port_free(port: int) -> bool:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        try:
            s.bind(("0.0.0.0", port))
        except OSError:
            return False
    return True


def free_domain(low: int = 100, high: int = 200) -> int:
    """A ROS domain id in ``[low, high)`` whose first DDS participants' unicast ports
    (RTPS: 7400 + 250 domain + 10 + 2 i, + 11 + 2 i) are free, tried in random order."""
    candidates = list(range(low, high))
    random.shuffle(candidates)
    for domain in candidates:
        base = 7400 + 250 * domain
        if all(_port_free(base + offset) for offset in (10, 11, 12, 13)):
            return domain
    raise RuntimeError(f"no free ROS domain in {low}..{high - 1}")


def dds_domain(monkeypatch: pytest.MonkeyPatch, domain_id: int | None = None) -> int:
    """Use ``domain_id`` (default: :func:`free_domain`) with loopback-only discovery in this
    process; returns it."""
    if domain_id is None:
        domain_id = free_domain()
    monkeypatch.setenv("ROS_DOMAIN_ID", str(domain_id))
    monkeypatch.setenv("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    for var in ("ROS_STATIC_PEERS", "CYCLONEDDS_URI", "POSEKIT_TRANSPORT"):
        monkeypatch.delenv(var, raising=False)
    return domain_id


def dds_context() -> Context:
    """An initialised context whose nodes use the dds transport (shut it down after use)."""
    context = Context()
    context.init(transport="dds")
    return context


@contextlib.contextmanager
def two_dds_contexts(monkeypatch: pytest.MonkeyPatch) -> Iterator[tuple[Context, Context]]:
    """Two contexts (two DDS participants) on a fresh domain, shut down afterwards."""
    dds_domain(monkeypatch)
    a, b = dds_context(), dds_context()
    try:
        yield a, b
    finally:
        b.try_shutdown()
        a.try_shutdown()


def posekit_env(domain_id: int, **extra: str) -> dict[str, str]:
    """Environment for a posekit child process on ``domain_id`` over DDS."""
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("ROS_", "RMW_", "POSEKIT_", "ZENOH_", "CYCLONEDDS_"))}
    env.update(ROS_DOMAIN_ID=str(domain_id), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
               POSEKIT_TRANSPORT="dds", PYTHONUNBUFFERED="1")
    env.update(extra)
    return env


def spin_until(executor: SingleThreadedExecutor, cond: Callable[[], bool],
               timeout: float, step: Callable[[], None] | None = None) -> bool:
    """Spin ``executor`` until ``cond()`` (True) or ``timeout`` s (False); ``step`` runs
    between spins (e.g. publish)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if cond():
            return True
        if step is not None:
            step()
        executor.spin_once(timeout_sec=0.05)
    return cond()
