"""Bounded polling of a condition (never a fixed sleep standing in for it)."""

from __future__ import annotations

import time
from collections.abc import Callable


def wait_for(cond: Callable[[], bool], timeout: float = 5.0, interval: float = 0.01) -> bool:
    """Poll ``cond`` until it holds (True) or ``timeout`` seconds passed (its last value)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if cond():
            return True
        time.sleep(interval)
    return cond()
