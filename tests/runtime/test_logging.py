"""Logger line format, severities, throttling, once, skip_first (sim-time stamped)."""

from __future__ import annotations

import pytest

from posekit.runtime.logging import (
    LoggingSeverity,
    RcutilsLogger,
    format_line,
    get_logger,
    set_logger_level,
)
from posekit.runtime.node import Node
from posekit.runtime.sim_executor import SimulatedTimeExecutor


def test_line_format() -> None:
    line = format_line(LoggingSeverity.INFO, 1_700_000_000_000_000_123, "talker", "hi")
    assert line == "[INFO] [1700000000.000000123] [talker]: hi"
    assert format_line(LoggingSeverity.WARN, 5, "a.b", "m") == "[WARN] [0.000000005] [a.b]: m"


def test_node_logger_uses_node_name_and_sim_time(ctx, logs, capsys) -> None:
    node = Node("talker", namespace="/robot1", context=ctx)
    ex = SimulatedTimeExecutor(context=ctx, start_time=12.5)
    ex.add_node(node)
    node.get_logger().info("hello")
    assert logs[-1].line == "[INFO] [12.500000000] [robot1.talker]: hello"
    assert "[INFO] [12.500000000] [robot1.talker]: hello" in capsys.readouterr().err


def test_severities_and_levels(logs) -> None:
    logger = get_logger("sev_test")
    assert not logger.debug("hidden")  # default threshold INFO
    logger.info("i")
    logger.warn("w")
    logger.warning("w2")
    logger.error("e")
    logger.fatal("f")
    assert [r.severity.name for r in logs] == ["INFO", "WARN", "WARN", "ERROR", "FATAL"]
    logger.set_level(LoggingSeverity.DEBUG)
    assert logger.debug("shown")
    assert logs[-1].line.startswith("[DEBUG] ")
    set_logger_level("sev_test", LoggingSeverity.ERROR)
    assert not logger.warning("no")
    assert get_logger("sev_test").get_child("sub").get_effective_level() == LoggingSeverity.ERROR


def test_throttle_once_skip_first_with_controlled_clock(logs) -> None:
    now = [0]
    logger = RcutilsLogger("throttled", lambda: now[0])
    emitted = []
    for step in range(11):  # t = 0.0, 0.1, ..., 1.0 s
        now[0] = step * 100_000_000
        if logger.info("tick", throttle_duration_sec=0.3):
            emitted.append(now[0])
    # Independent rule: emit when at least 0.3 s passed since the last emitted line.
    expected, last = [], None
    for step in range(11):
        t = step * 100_000_000
        if last is None or t - last >= 300_000_000:
            expected.append(t)
            last = t
    assert emitted == expected == [0, 300_000_000, 600_000_000, 900_000_000]

    once = [logger.info("one", once=True) for _ in range(3)]
    assert once == [True, False, False]
    skip = [logger.info("skip", skip_first=True) for _ in range(3)]
    assert skip == [False, True, True]


def test_different_call_sites_throttle_independently(logs) -> None:
    logger = RcutilsLogger("sites", lambda: 0)
    a = logger.info("a", throttle_duration_sec=10.0)
    b = logger.info("b", throttle_duration_sec=10.0)
    again = [logger.info("c", throttle_duration_sec=10.0) for _ in range(2)]
    assert (a, b, again) == (True, True, [True, False])


def test_unknown_keyword_is_an_error() -> None:
    with pytest.raises(TypeError):
        get_logger("x").info("m", bogus=1)
