"""RateLimitedLog: one line per period per reason, suppressed counts, bounded reasons.

Oracle: a hand-driven clock and counting (what was called vs. what was emitted).
"""

from __future__ import annotations

import pytest

from posekit.runtime.ratelimit import RateLimitedLog


class FakeClock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def test_one_line_per_period_per_reason_with_suppressed_count() -> None:
    lines: list[str] = []
    clock = FakeClock()
    log = RateLimitedLog(lines.append, period_s=1.0, clock=clock)
    for i in range(1000):
        log("bad cdr", f"sample {i}")
        log("bad attachment", f"sample {i}")
        clock.now += 0.004  # 1000 calls in 4 s
    assert len(lines) == 8  # two reasons, one line per second each
    assert lines[0] == "bad cdr: sample 0"
    assert lines[1] == "bad attachment: sample 0"
    assert "(249 similar suppressed since the last report)" in lines[2]
    assert log.counts == {"bad cdr": 1000, "bad attachment": 1000}
    assert log.lines == 8


def test_reasons_table_is_bounded() -> None:
    lines: list[str] = []
    clock = FakeClock()
    log = RateLimitedLog(lines.append, period_s=1.0, max_reasons=4, clock=clock)
    for i in range(10_000):
        log(f"reason chosen by a sender {i}")
    assert len(log.counts) == 5  # four reasons and the shared overflow slot
    assert len(lines) == 5


def test_bad_arguments() -> None:
    with pytest.raises(ValueError, match="period_s"):
        RateLimitedLog(print, period_s=float("nan"))
    with pytest.raises(ValueError, match="max_reasons"):
        RateLimitedLog(print, max_reasons=0)
