"""The package's one ``Future``, in the shape of ``rclpy.task.Future``.

It lives here, in tf2 (numpy alone), because tf2's ``Buffer.wait_for_transform_async`` returns
one and tf2 sits below the runtime; the runtime's :class:`~posekit.runtime.task.Task` is a
subclass and ``posekit.runtime.task`` / ``posekit.rclpy.task`` re-export this class, so a tf2
future can be awaited in an executor's coroutine or passed to ``spin_until_future_complete``
(as tf2_ros's futures are rclpy's).

Semantics (the same wherever a future comes from):

* set once: the first ``set_result`` / ``set_exception`` / ``cancel`` wins, later ones are
  ignored (rclpy overwrites the result and runs the done callbacks again);
* a cancelled future is ``done()`` and its ``result()`` raises :class:`CancelledError`
  (rclpy: not done, result None);
* ``result()`` is None while pending, as in rclpy;
* thread-safe: a result may be set from any thread; done callbacks run in the thread that
  completes the future (at once in ``add_done_callback`` if it is already done), or, for a
  future made with ``Future(executor=...)`` (rclpy's keyword), as tasks of that executor;
* ``await future`` yields the future itself until it is done, so an executor running the
  awaiting coroutine can resume it from a done callback instead of polling; a coroutine can
  also be driven by hand with ``coro.send(None)``.
"""

from __future__ import annotations

import threading
import weakref
from collections.abc import Callable, Generator
from typing import Any, Generic, TypeVar

__all__ = ["CancelledError", "Future"]

T = TypeVar("T")

_PENDING = 0
_FINISHED = 1
_CANCELLED = 2


class CancelledError(Exception):
    """``result()`` of a cancelled future."""


class Future(Generic[T]):
    """A result that will exist later (set once); ``done()``, ``result()``, callbacks, await."""

    def __init__(self, *, executor: Any = None) -> None:
        """A pending future; with ``executor`` (rclpy's keyword) its done callbacks run there.

        ``executor`` is anything with rclpy's ``create_task(callback, *args)`` (held weakly,
        as rclpy holds it); without one they run in the thread that completes the future.
        """
        self._executor: weakref.ref[Any] | None = (
            None if executor is None else weakref.ref(executor))
        self._lock = threading.Lock()
        self._state = _PENDING
        self._result: T | None = None
        self._exception: BaseException | None = None
        self._callbacks: list[Callable[[Future[T]], Any]] = []
        self._event: threading.Event | None = None  # made by the first wait()

    def done(self) -> bool:
        """True once a result or exception was set, or the future was cancelled."""
        return self._state != _PENDING

    def cancelled(self) -> bool:
        """True if :meth:`cancel` was called before completion."""
        return self._state == _CANCELLED

    def result(self) -> T | None:
        """The result (None while pending).

        Raises the stored exception, or :class:`CancelledError` if the future was cancelled.
        """
        if self._state == _CANCELLED:
            raise CancelledError("the future was cancelled")
        if self._exception is not None:
            raise self._exception
        return self._result

    def exception(self) -> BaseException | None:
        """The stored exception, if any."""
        return self._exception

    def set_result(self, result: T) -> None:
        """Complete with a value (ignored if already done)."""
        self._finish(_FINISHED, result, None)

    def set_exception(self, exception: BaseException) -> None:
        """Complete with an exception (ignored if already done)."""
        self._finish(_FINISHED, None, exception)

    def cancel(self) -> None:
        """Cancel if still pending (no result); runs the done callbacks."""
        self._finish(_CANCELLED, None, None)

    def _finish(self, state: int, result: T | None, exception: BaseException | None) -> None:
        with self._lock:
            if self._state != _PENDING:
                return
            self._result = result
            self._exception = exception
            self._state = state
            callbacks, self._callbacks = self._callbacks, []
            event = self._event
        if event is not None:
            event.set()
        for cb in callbacks:
            self._invoke(cb)

    def _invoke(self, callback: Callable[[Future[T]], Any]) -> None:
        executor = self._executor() if self._executor is not None else None
        if executor is not None:
            executor.create_task(callback, self)
        else:
            callback(self)

    def add_done_callback(self, callback: Callable[[Future[T]], Any]) -> None:
        """Call ``callback(future)`` on completion (at once if already done).

        With an executor (see ``__init__``) the call is a task of that executor.
        """
        with self._lock:
            if self._state == _PENDING:
                self._callbacks.append(callback)
                return
        self._invoke(callback)

    def remove_done_callback(self, callback: Callable[[Future[T]], Any]) -> bool:
        """Forget a done callback; False if it was not registered (or already called)."""
        with self._lock:
            try:
                self._callbacks.remove(callback)
            except ValueError:
                return False
            return True

    def wait(self, timeout: float | None = None) -> bool:
        """Block the calling thread until done or ``timeout`` seconds passed; True if done.

        ``timeout`` None means no limit. Only useful while another thread completes the future.
        """
        with self._lock:
            if self._state != _PENDING:
                return True
            if self._event is None:
                self._event = threading.Event()
            event = self._event
        return event.wait(timeout)

    def __await__(self) -> Generator[Future[T], None, T | None]:
        while self._state == _PENDING:
            yield self
        return self.result()
