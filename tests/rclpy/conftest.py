"""Fixtures for runtime tests: a fresh, isolated context per test and a log capture."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from posekit.runtime.context import Context
from posekit.runtime.logging import LogRecord, add_sink, remove_sink


@pytest.fixture
def ctx() -> Iterator[Context]:
    context = Context()
    context.init()
    yield context
    context.try_shutdown()


@pytest.fixture
def logs() -> Iterator[list[LogRecord]]:
    records: list[LogRecord] = []
    add_sink(records.append)
    yield records
    remove_sink(records.append)
