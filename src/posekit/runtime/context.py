"""Context: the lifetime of a "ROS process" (``init`` / ``ok`` / ``shutdown``).

A context owns the transports its nodes use (one instance per transport name, so nodes of a
context share one in-process bus), the global ROS arguments given to ``init(args=...)`` (as
rclpy: ``args=None`` reads ``sys.argv``; ``--ros-args -p name:=value -r from:=to
--params-file FILE --log-level LEVEL``, see :mod:`posekit.runtime.arguments`) and a sequence
counter that orders every message and timer of the context (what makes simulated runs
deterministic).

Different contexts are isolated from each other, like separate processes; tests use a fresh
``Context()`` each to avoid leaking latched messages.
"""

from __future__ import annotations

import inspect
import itertools
import sys
import threading
import weakref
from collections.abc import Callable, Sequence

from posekit.runtime.arguments import RosArguments, parse_arguments
from posekit.runtime.transport import Transport, create_transport, selected_transport_name

__all__ = [
    "Context",
    "InvalidHandle",
    "NotInitializedException",
    "get_default_context",
    "init",
    "ok",
    "shutdown",
    "try_shutdown",
]


class NotInitializedException(RuntimeError):  # noqa: N818 - rclpy name
    """A node or executor was used with a context that is not initialized (call init())."""

    def __init__(self, what: str = "") -> None:
        super().__init__(
            f"{what + ': ' if what else ''}the context is not initialized; call "
            "rclpy.init() (posekit.runtime.context.init()) first"
        )


class InvalidHandle(RuntimeError):  # noqa: N818 - rclpy name
    """An entity (node, timer, guard condition) was used after it was destroyed (rclpy's)."""


class Context:
    """Lifetime, transports and global rules of a set of nodes."""

    def __init__(self) -> None:
        self._ok = False
        self._lock = threading.RLock()
        self._transport_name: str | None = None
        self._transports: dict[str, Transport] = {}
        # a bound method is held weakly (as rclpy's Context does), so an executor or node
        # that registers its own method does not live as long as the context
        self._on_shutdown: list[Callable[[], Callable[[], None] | None]] = []
        self.seq = itertools.count()
        #: The parsed global ROS arguments (parameters, remaps, log levels) of init().
        self.arguments = RosArguments()
        self.args: list[str] = []

    def init(self, args: Sequence[str] | None = None, *, transport: str | None = None) -> None:
        """Initialize with the ROS arguments in ``args`` (None: ``sys.argv``, as rclpy).

        Raises :class:`~posekit.runtime.arguments.RCLError` for a malformed argument and
        :class:`~posekit.runtime.arguments.UnknownROSArgsError` for an unknown one.
        """
        with self._lock:
            if self._ok:
                raise RuntimeError("Context.init() must only be called once")
            args = list(sys.argv if args is None else args)
            self.arguments = parse_arguments(args)
            self.arguments.apply_log_levels()
            self.args = args
            self._transport_name = transport
            self.seq = itertools.count()
            self._ok = True

    def ok(self) -> bool:
        """True between init() and shutdown()."""
        return self._ok

    def transport(self, name: str | None = None) -> Transport:
        """The context's transport called ``name`` (default: the selected one), created once."""
        if not self._ok:
            raise NotInitializedException("transport")
        chosen = selected_transport_name(name or self._transport_name)
        with self._lock:
            transport = self._transports.get(chosen)
            if transport is None:
                transport = create_transport(chosen)
                self._transports[chosen] = transport
            return transport

    def on_shutdown(self, callback: Callable[[], None]) -> None:
        """Run ``callback`` when the context shuts down (a bound method is held weakly)."""
        ref: Callable[[], Callable[[], None] | None] = (
            weakref.WeakMethod(callback) if inspect.ismethod(callback) else lambda: callback
        )
        with self._lock:
            self._on_shutdown.append(ref)

    def remove_on_shutdown(self, callback: Callable[[], None]) -> None:
        """Forget ``callback`` given to :meth:`on_shutdown` (posekit's; rclpy has none)."""
        with self._lock:
            self._on_shutdown = [ref for ref in self._on_shutdown if ref() != callback]

    def shutdown(self) -> None:
        """Stop: executors return from spin, transports close. Raises if not initialized."""
        with self._lock:
            if not self._ok:
                raise RuntimeError("Context must be initialized before it can be shutdown")
            self._ok = False
            callbacks = list(self._on_shutdown)
            self._on_shutdown.clear()
            transports = list(self._transports.values())
            self._transports.clear()
        for ref in callbacks:  # executors wake (they registered their wake) in this pass
            cb = ref()
            if cb is not None:
                cb()
        for transport in transports:
            transport.close()

    def try_shutdown(self) -> None:
        """shutdown() if initialized, else nothing."""
        if self._ok:
            self.shutdown()


_default_context = Context()


def get_default_context() -> Context:
    """The context used when none is given."""
    return _default_context


def init(
    args: Sequence[str] | None = None,
    *,
    context: Context | None = None,
    domain_id: int | None = None,
    transport: str | None = None,
    signal_handler_options: object = None,
) -> None:
    """rclpy.init: initialize ``context`` (default: the global one).

    ``domain_id`` and ``signal_handler_options`` are accepted for compatibility and ignored.
    """
    del domain_id, signal_handler_options
    (context or _default_context).init(args, transport=transport)


def shutdown(*, context: Context | None = None, uninstall_handlers: object = None) -> None:
    """rclpy.shutdown."""
    del uninstall_handlers
    (context or _default_context).shutdown()


def try_shutdown(*, context: Context | None = None) -> None:
    """rclpy.try_shutdown."""
    (context or _default_context).try_shutdown()


def ok(*, context: Context | None = None) -> bool:
    """rclpy.ok."""
    return (context or _default_context).ok()
