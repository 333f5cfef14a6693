"""Fixtures for the vision node tests: an isolated context, a stepped executor, log capture."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from posekit.runtime.context import Context
from posekit.runtime.executors import SimulatedTimeExecutor
from posekit.runtime.logging import LogRecord, add_sink, remove_sink


@pytest.fixture
def ctx() -> Iterator[Context]:
    context = Context()
    context.init()
    yield context
    context.try_shutdown()


@pytest.fixture
def executor(ctx: Context) -> Iterator[SimulatedTimeExecutor]:
    ex = SimulatedTimeExecutor(context=ctx, publish_clock=False)
    yield ex
    ex.shutdown()


@pytest.fixture
def logs() -> Iterator[list[LogRecord]]:
    records: list[LogRecord] = []
    add_sink(records.append)
    yield records
    remove_sink(records.append)
