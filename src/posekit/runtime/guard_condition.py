"""rclpy.guard_condition: a condition another thread triggers to run a callback.

``node.create_guard_condition(callback)`` returns a :class:`GuardCondition`; ``trigger()``
(from any thread) makes the executor the node is in run ``callback()`` once, in the callback
group given (default: the node's). Triggers that come before the executor gets to it run the
callback once, as rcl's guard conditions do. A GuardCondition made directly (not by a node)
belongs to no executor and its triggers run nothing.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from posekit.runtime.callback_groups import CallbackGroup
from posekit.runtime.context import Context, InvalidHandle, get_default_context

if TYPE_CHECKING:
    from posekit.runtime.services import _Queued

__all__ = ["GuardCondition"]


class GuardCondition:
    """rclpy's GuardCondition (``callback``, ``callback_group``, ``trigger()``, ``destroy()``)."""

    def __init__(self, callback: Callable[[], Any], callback_group: CallbackGroup | None,
                 context: Context | None = None) -> None:
        self._context = get_default_context() if context is None else context
        self.callback = callback
        self.callback_group = callback_group
        self._queued: _Queued | None = None  # set by the node that made it
        self._destroyed = False

    def trigger(self) -> None:
        """Make the node's executor run the callback (once for triggers not yet handled)."""
        if self._destroyed:
            raise InvalidHandle("cannot use Destroyable because destruction was requested")
        if self._queued is not None:
            self._queued.enqueue(None)

    def destroy(self) -> None:
        """Stop: a pending trigger is dropped and trigger() raises InvalidHandle."""
        self._destroyed = True
        if self._queued is not None:
            self._queued.destroyed = True
            self._queued.queue.clear()
