"""A minimal awaitable Future in the shape of ``rclpy.task.Future``.

``await future`` yields (``None``) until a result or exception is set, so a coroutine that
awaits it can be driven by any loop, or by hand with ``coro.send(None)`` as tf2_ros's tests do.
Thread-safe: results may be set from another thread.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Generator
from typing import Any, Generic, TypeVar

__all__ = ["Future"]

T = TypeVar("T")


class Future(Generic[T]):
    """A result that will exist later (set once); ``done()``, ``result()``, callbacks, await."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._done = False
        self._cancelled = False
        self._result: T | None = None
        self._exception: BaseException | None = None
        self._callbacks: list[Callable[[Future[T]], None]] = []

    def done(self) -> bool:
        """True once a result or exception was set, or the future was cancelled."""
        return self._done

    def cancelled(self) -> bool:
        """True if :meth:`cancel` was called before completion."""
        return self._cancelled

    def cancel(self) -> None:
        """Mark as cancelled (no result); runs the done callbacks."""
        self._finish(cancelled=True)

    def result(self) -> T | None:
        """The result (None while pending); raises the stored exception if one was set."""
        if self._exception is not None:
            raise self._exception
        return self._result

    def exception(self) -> BaseException | None:
        """The stored exception, if any."""
        return self._exception

    def set_result(self, result: T) -> None:
        """Complete with a value (ignored if already done)."""
        self._finish(result=result)

    def set_exception(self, exception: BaseException) -> None:
        """Complete with an exception (ignored if already done)."""
        self._finish(exception=exception)

    def _finish(
        self,
        result: Any = None,
        exception: BaseException | None = None,
        cancelled: bool = False,
    ) -> None:
        with self._lock:
            if self._done:
                return
            self._result = result
            self._exception = exception
            self._cancelled = cancelled
            self._done = True
            callbacks, self._callbacks = self._callbacks, []
        for cb in callbacks:
            cb(self)

    def add_done_callback(self, callback: Callable[[Future[T]], None]) -> None:
        """Call ``callback(future)`` on completion (immediately if already done)."""
        with self._lock:
            if not self._done:
                self._callbacks.append(callback)
                return
        callback(self)

    def __await__(self) -> Generator[None, None, T | None]:
        while not self._done:
            yield
        return self.result()
