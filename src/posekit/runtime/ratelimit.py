"""Warnings that nobody outside the process can turn into a flood.

A :class:`RateLimitedLog` prints at most one line per ``period_s`` seconds for each *reason*
(a short string chosen by posekit's code, never by a peer: e.g. ``"bad attachment"``), and
the next line of that reason says how many were suppressed in between. The table of reasons
is bounded (``max_reasons``), so even a caller that passes sender-chosen text as the reason
cannot grow it without bound: past the bound, new reasons share one overflow slot.

Counters per reason (:attr:`RateLimitedLog.counts`) keep the full tally for statistics.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

__all__ = ["DEFAULT_PERIOD_S", "RateLimitedLog"]

#: One line per second per reason, the bound posekit promises for peer-triggered warnings.
DEFAULT_PERIOD_S = 1.0
_OVERFLOW = "(other reasons)"


class RateLimitedLog:
    """At most one line per ``period_s`` per reason, with the count suppressed in between.

    Args:
        emit: called with the finished line (e.g. ``logger.warning``).
        period_s: minimum seconds between two lines of one reason (monotonic clock).
        max_reasons: reasons tracked separately; more share one slot.
        clock: seconds (default monotonic wall time; a node's clock works too: a jump
            back in time ends the current window).
    """

    def __init__(
        self,
        emit: Callable[[str], object],
        *,
        period_s: float = DEFAULT_PERIOD_S,
        max_reasons: int = 64,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        if not period_s >= 0:
            raise ValueError(f"period_s must be >= 0, got {period_s}")
        if max_reasons < 1:
            raise ValueError(f"max_reasons must be >= 1, got {max_reasons}")
        self._emit = emit
        self._period_s = float(period_s)
        self._max_reasons = int(max_reasons)
        self._clock = clock
        self._lock = threading.Lock()
        # reason -> [last emitted (s) or None, suppressed since]
        self._state: dict[str, list[float | int | None]] = {}
        #: Every call per reason (emitted or not); bounded like the reason table.
        self.counts: dict[str, int] = {}
        #: Lines emitted so far.
        self.lines = 0

    def __call__(self, reason: str, detail: str = "") -> bool:
        """Log ``reason: detail`` unless this reason logged less than ``period_s`` ago.

        Returns whether a line was emitted.
        """
        now = self._clock()
        with self._lock:
            key = reason
            if key not in self._state and len(self._state) >= self._max_reasons:
                key = _OVERFLOW
            state = self._state.setdefault(key, [None, 0])
            self.counts[key] = self.counts.get(key, 0) + 1
            last = state[0]
            if last is not None and 0.0 <= now - float(last) < self._period_s:
                state[1] = int(state[1] or 0) + 1
                return False
            suppressed = int(state[1] or 0)
            state[0], state[1] = now, 0
            self.lines += 1
        line = f"{reason}: {detail}" if detail else reason
        if suppressed:
            line += f" ({suppressed} similar suppressed since the last report)"
        self._emit(line)
        return True
