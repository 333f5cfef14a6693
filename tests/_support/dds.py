"""posekit on the DDS transport in tests: one ROS domain per test, discovery on loopback.

:func:`dds_domain` points this process (``ROS_DOMAIN_ID``, LOCALHOST discovery) at a domain
of the caller's choice, so tests running at the same time never meet; :func:`dds_context`
is a posekit context on the ``dds`` transport there; :func:`posekit_env` is the environment
for a posekit child process on the same domain.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable

import pytest

from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor


def dds_domain(monkeypatch: pytest.MonkeyPatch, domain_id: int) -> None:
    """Use ``domain_id`` with loopback-only discovery in this process."""
    monkeypatch.setenv("ROS_DOMAIN_ID", str(domain_id))
    monkeypatch.setenv("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    for var in ("ROS_STATIC_PEERS", "CYCLONEDDS_URI", "POSEKIT_TRANSPORT"):
        monkeypatch.delenv(var, raising=False)


def dds_context() -> Context:
    """An initialised context whose nodes use the dds transport (shut it down after use)."""
    context = Context()
    context.init(transport="dds")
    return context


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
