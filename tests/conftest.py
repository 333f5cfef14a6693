"""Suite-wide test settings and fixtures.

* A deterministic hypothesis profile sized for a 2-core CI machine.
* ``ctx``: a fresh, initialised runtime :class:`~posekit.runtime.context.Context` per test
  (transport from $POSEKIT_TRANSPORT, default in-process), shut down afterwards.
* ``executor``: a :class:`~posekit.runtime.sim_executor.SimulatedTimeExecutor` on ``ctx``
  without a /clock publisher (stepped sim time).
* every test: ``POSEKIT_ZENOH_ROUTER`` on a free loopback port of its own.
* ``logs``: every :class:`~posekit.runtime.logging.LogRecord` emitted during the test.

The runtime is imported inside the fixtures, so the geometry/msgs/tf2 tests do not load it.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

import pytest
from hypothesis import HealthCheck, settings

if TYPE_CHECKING:
    from posekit.runtime.context import Context
    from posekit.runtime.logging import LogRecord
    from posekit.runtime.sim_executor import SimulatedTimeExecutor

settings.register_profile(
    "posekit",
    max_examples=150,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile("posekit")


@pytest.fixture(autouse=True)
def _private_zenoh_router(monkeypatch: pytest.MonkeyPatch) -> None:
    """Each test's in-process Zenoh sessions (a ``posekit launch`` run by a test, a tool)
    use a free loopback port of their own, so tests never meet each other's graph or a
    user's router on the default port. Tests that start processes set their own endpoint."""
    from _support.ports import free_port

    monkeypatch.setenv("POSEKIT_ZENOH_ROUTER", f"tcp/127.0.0.1:{free_port()}")


@pytest.fixture
def ctx() -> Iterator[Context]:
    from posekit.runtime.context import Context

    context = Context()
    context.init()
    yield context
    context.try_shutdown()


@pytest.fixture
def executor(ctx: Context) -> Iterator[SimulatedTimeExecutor]:
    from posekit.runtime.sim_executor import SimulatedTimeExecutor

    ex = SimulatedTimeExecutor(context=ctx, publish_clock=False)
    yield ex
    ex.shutdown()


@pytest.fixture
def logs() -> Iterator[list[LogRecord]]:
    from posekit.runtime.logging import add_sink, remove_sink

    records: list[LogRecord] = []
    add_sink(records.append)
    yield records
    remove_sink(records.append)
