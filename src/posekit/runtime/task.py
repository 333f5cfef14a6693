"""Future and Task (rclpy.task): results produced later, awaitable inside async callbacks."""

from __future__ import annotations

import threading
from collections.abc import Callable, Coroutine, Generator
from typing import Any

__all__ = ["CancelledError", "Future", "Task"]


class CancelledError(Exception):
    """result() of a cancelled future."""


class Future:
    """A result that arrives later. ``await future`` works inside async callbacks/tasks."""

    def __init__(self) -> None:
        self._state = "pending"
        self._result: Any = None
        self._exception: BaseException | None = None
        self._callbacks: list[Callable[[Future], None]] = []
        self._lock = threading.Lock()
        self._event = threading.Event()

    def done(self) -> bool:
        """True once a result, exception or cancellation is set."""
        return self._state != "pending"

    def cancelled(self) -> bool:
        """True if cancel() was called before completion."""
        return self._state == "cancelled"

    def result(self) -> Any:
        """The result (None while pending, like rclpy); re-raises a stored exception."""
        if self._state == "cancelled":
            raise CancelledError("the future was cancelled")
        if self._exception is not None:
            raise self._exception
        return self._result

    def exception(self) -> BaseException | None:
        """The stored exception, if any."""
        return self._exception

    def _finish(self, state: str) -> None:
        with self._lock:
            self._state = state
            callbacks = list(self._callbacks)
            self._callbacks.clear()
        self._event.set()
        for cb in callbacks:
            cb(self)

    def set_result(self, result: Any) -> None:
        """Complete with ``result``."""
        with self._lock:
            if self._state != "pending":
                return
            self._result = result
        self._finish("finished")

    def set_exception(self, exception: BaseException) -> None:
        """Complete with an exception."""
        with self._lock:
            if self._state != "pending":
                return
            self._exception = exception
        self._finish("finished")

    def cancel(self) -> None:
        """Cancel if still pending."""
        with self._lock:
            if self._state != "pending":
                return
        self._finish("cancelled")

    def add_done_callback(self, callback: Callable[[Future], None]) -> None:
        """Call ``callback(self)`` on completion (at once if already done)."""
        with self._lock:
            if self._state == "pending":
                self._callbacks.append(callback)
                return
        callback(self)

    def remove_done_callback(self, callback: Callable[[Future], None]) -> bool:
        """Forget a done callback; False if it was not registered (or already called)."""
        with self._lock:
            try:
                self._callbacks.remove(callback)
            except ValueError:
                return False
            return True

    def wait(self, timeout: float | None = None) -> bool:
        """Block the calling thread until done (only useful with another thread spinning)."""
        return self._event.wait(timeout)

    def __await__(self) -> Generator[Future, None, Any]:
        while not self.done():
            yield self
        return self.result()


class Task(Future):
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
