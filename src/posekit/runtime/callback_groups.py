"""Callback groups (rclpy.callback_groups): which callbacks may run concurrently.

Only the MultiThreadedExecutor runs callbacks concurrently. Callbacks of one
MutuallyExclusiveCallbackGroup (each node's default group) never overlap; callbacks of a
ReentrantCallbackGroup may.
"""

from __future__ import annotations

import functools
import threading

__all__ = ["CallbackGroup", "MutuallyExclusiveCallbackGroup", "ReentrantCallbackGroup"]


class CallbackGroup:
    """Base class; ``can_execute`` / ``beginning_execution`` / ``ending_execution``."""

    def __init__(self) -> None:
        self._lock = threading.Lock()

    def can_execute(self) -> bool:
        """Whether another callback of this group may start now."""
        return True

    def beginning_execution(self) -> bool:
        """Claim the group for one callback; False if not possible."""
        return True

    def ending_execution(self) -> None:
        """Release the claim."""


class ReentrantCallbackGroup(CallbackGroup):
    """Callbacks may run in parallel."""


class MutuallyExclusiveCallbackGroup(CallbackGroup):
    """At most one callback of the group runs at a time."""

    def __init__(self) -> None:
        super().__init__()
        # The lock itself is the claim: one non-blocking acquire per callback.
        self._claim = threading.Lock()
        self.beginning_execution = functools.partial(  # type: ignore[method-assign]
            self._claim.acquire, False
        )
        self.ending_execution = self._claim.release  # type: ignore[method-assign]

    def can_execute(self) -> bool:
        """Whether no callback of this group is running now."""
        return not self._claim.locked()
