"""Future and Task (rclpy.task): results produced later, awaitable inside async callbacks.

:class:`Future` is the package's one future (:mod:`posekit.tf2.future`, re-exported here):
the futures of service clients, actions, tf2's ``Buffer`` and tasks are all of this class.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Coroutine
from typing import Any

from posekit.tf2.future import CancelledError, Future

__all__ = ["CancelledError", "Future", "Task"]


class Task(Future[Any]):
    """Runs a coroutine step by step on an executor; completes with its return value."""

    def __init__(
        self,
        coroutine: Coroutine[Any, Any, Any],
        schedule: Callable[[Task], None],
    ) -> None:
        super().__init__()
        self._coroutine = coroutine
        self._schedule = schedule
        self._running = threading.Lock()

    def step(self) -> None:
        """Run the coroutine until it awaits an unfinished future or returns."""
        if self.done():
            return
        with self._running:
            try:
                awaited = self._coroutine.send(None)
            except StopIteration as stop:
                self.set_result(stop.value)
                return
            except Exception as exc:
                self.set_exception(exc)
                return
        if isinstance(awaited, Future):
            awaited.add_done_callback(lambda _f: self._schedule(self))
        else:
            # A bare ``yield``/unknown awaitable: try again on the next executor turn.
            self._schedule(self)
