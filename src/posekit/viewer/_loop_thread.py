"""An asyncio event loop serving from a daemon thread.

The viewer's page server and the Foxglove bridge's front both run their aiohttp servers this
way.
"""

from __future__ import annotations

import asyncio
import contextlib
import threading
from collections.abc import Awaitable, Callable, Iterable
from typing import Any

__all__ = ["LoopThread"]


class LoopThread:
    """Runs ``startup()`` on a new event loop in a daemon thread, then the loop until :meth:`stop`.

    :meth:`stop` cancels the tasks ``pending()`` lists, awaits ``cleanup()`` and closes the
    loop. ``on_started(loop)`` runs on the loop's thread right after startup.
    """

    def __init__(
        self,
        name: str,
        startup: Callable[[], Awaitable[None]],
        cleanup: Callable[[], Awaitable[None]],
        *,
        pending: Callable[[], Iterable[asyncio.Future[Any]]] = tuple,
        on_started: Callable[[asyncio.AbstractEventLoop], None] | None = None,
    ) -> None:
        self.name = name
        self.loop: asyncio.AbstractEventLoop | None = None
        self.thread: threading.Thread | None = None
        self._startup, self._cleanup = startup, cleanup
        self._pending, self._on_started = pending, on_started
        self._ready = threading.Event()
        self._error: BaseException | None = None

    def start(self, timeout: float = 15.0) -> None:
        """Start and wait for ``startup()``.

        Raises what it raised (e.g. OSError: address in use), or TimeoutError when it did not
        finish within ``timeout`` s.
        """
        self.thread = threading.Thread(target=self._run, name=self.name, daemon=True)
        self.thread.start()
        if not self._ready.wait(timeout):
            raise TimeoutError(f"{self.name} did not start within {timeout:g} s")
        if self._error is not None:
            self.thread.join(timeout=5.0)
            self.thread = None
            raise self._error

    def is_alive(self) -> bool:
        return self.thread is not None and self.thread.is_alive()

    def stop(self, timeout: float = 10.0) -> None:
        """Stop the loop (from another thread) and join the thread (idempotent)."""
        loop, thread = self.loop, self.thread
        if loop is not None and thread is not None and thread.is_alive():
            loop.call_soon_threadsafe(loop.stop)
            thread.join(timeout=timeout)

    def _run(self) -> None:
        loop = asyncio.new_event_loop()
        self.loop = loop
        asyncio.set_event_loop(loop)
        try:
            loop.run_until_complete(self._startup())
        except BaseException as exc:  # reported by start()
            self._error = exc
            self._ready.set()
            loop.close()
            return
        self._ready.set()
        if self._on_started is not None:
            self._on_started(loop)
        try:
            loop.run_forever()
        finally:
            pending = list(self._pending())
            for task in pending:
                task.cancel()
            with contextlib.suppress(BaseException):
                loop.run_until_complete(asyncio.gather(*pending, return_exceptions=True))
            loop.run_until_complete(self._cleanup())
            loop.close()
