"""``Rate``: ``node.create_rate(hz)`` and ``rate.sleep()``, as rclpy has them.

A Rate wraps a timer of the node (period ``1 / frequency`` on the node clock, or the clock
given); ``sleep()`` blocks the calling thread until that timer's next call. The timer runs
in the executor like any other, so **someone must be spinning the node in another thread**
(``MultiThreadedExecutor`` or ``executor.spin()`` in a background thread) while a thread
sleeps. Calling ``sleep()`` from a callback of a ``SingleThreadedExecutor`` (or a stepped
``SimulatedTimeExecutor``) blocks forever, exactly as in rclpy: that executor cannot run the
timer while it is inside the sleeping callback. Prefer a timer callback in node code.

Shutting the context down wakes every sleeper with :class:`ROSInterruptException`.
"""

from __future__ import annotations

import threading
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from posekit.runtime.context import Context
    from posekit.runtime.entities import Timer

__all__ = ["ROSInterruptException", "Rate"]


class ROSInterruptException(Exception):  # noqa: N818 - rclpy name
    """An operation was ended by rclpy shutting down (rclpy.exceptions)."""

    def __init__(self) -> None:
        super().__init__("rclpy.shutdown() has been called")


class Rate:
    """Sleeps until the next tick of a timer (rclpy.timer.Rate)."""

    def __init__(self, timer: Timer, *, context: Context) -> None:
        self._timer = timer
        self._is_shutdown = False
        self._is_destroyed = False
        self._event = threading.Event()
        self._lock = threading.Lock()
        self._sleepers = 0
        timer.callback = self._event.set
        context.on_shutdown(self._on_shutdown)

    def _on_shutdown(self) -> None:
        self._is_shutdown = True
        self.destroy()

    def destroy(self) -> None:
        """Wake every sleeper; later ``sleep()`` calls raise."""
        self._is_destroyed = True
        self._event.set()

    def sleep(self) -> None:
        """Block until the timer's next call (see the module docstring about executors).

        Raises:
            ROSInterruptException: the context was shut down before or during the sleep.
            RuntimeError: the rate (or its timer) was destroyed.
        """
        if self._is_shutdown:
            raise ROSInterruptException()
        if self._is_destroyed:
            raise RuntimeError("Rate cannot sleep because it has been destroyed")
        if self._timer.destroyed:
            self.destroy()
            raise RuntimeError("Rate cannot sleep because the timer has been destroyed")
        with self._lock:
            self._sleepers += 1
        try:
            self._event.wait()
        finally:
            with self._lock:
                self._sleepers -= 1
                if self._sleepers == 0:
                    self._event.clear()
        if self._is_shutdown:
            self.destroy()
            raise ROSInterruptException()
