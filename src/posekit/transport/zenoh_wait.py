"""An executor's wait on a Zenoh subscription's channel: one thread wake-up per message.

A :class:`~posekit.runtime.executors.SingleThreadedExecutor` that reads its Zenoh
subscriptions itself (``pull_into``) waits in :class:`ChannelWaiter`. zenoh-python offers no
wait over several channels that releases the GIL, so the waiter blocks in the channel of one
pulled subscription, its *primary*: zenoh's network thread wakes the executor directly when
a sample arrives there, with the GIL released meanwhile, the one wake-up per message that
raw zenoh-python's callback thread costs (and rclpy's executor on a middleware wait set).

Whatever else must end the wait (another subscription's hand-over, a task, a future done on
another thread, shutdown, a timer's deadline) *pokes* the primary's channel: a DELETE sample
on the primary's key, routed to this session only (``Locality.SESSION_LOCAL``, never onto
the network); every posekit subscription ignores DELETE samples. A zenoh channel is bounded,
so a poke waits while it is full: pokes are therefore sent only by threads that hold no lock
the executor could need to empty it (the waiter's own helper thread, which also keeps the
timeout, subscriptions' receive threads, and zenoh's own thread in the handlers marked
:func:`on_receive_thread`: a service's queries, a client's replies), never by an arbitrary
caller of :meth:`set`.

Before the primary's receive thread has handed its channel over, and when there is no
primary, the waiter is a plain :class:`~posekit.runtime.inbox.WakeSignal`.

The first pulled subscription becomes the primary. When the samples come on a secondary
instead (:data:`PROMOTE_AFTER` of its hand-overs while the executor took nothing from the
primary's channel), that secondary becomes the primary before the executor next waits.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import Any, Protocol, TypeVar

from posekit.runtime.inbox import WakeSignal

__all__ = ["ChannelWaiter", "PrimaryChannel", "on_receive_thread"]

_T = TypeVar("_T")

#: The helper thread ends after this long with nothing to do (a waiter an inbox dropped
#: leaves no thread behind).
_HELPER_IDLE_S = 1.0

#: A secondary subscription that woke the executor this many times (each a second thread
#: wake-up) while the executor took nothing from the primary's channel becomes the primary.
PROMOTE_AFTER = 32


_receiving = threading.local()


def on_receive_thread(handler: Callable[[_T], None]) -> Callable[[_T], None]:
    """``handler`` marked as run by zenoh's own thread, holding no lock of posekit's.

    A :meth:`ChannelWaiter.set` made inside it (a request or a response queued for an
    executor that waits in a channel) pokes at once, as a subscription's receive thread
    does, instead of through the helper thread.
    """

    def marked(arg: _T) -> None:
        _receiving.active = True
        try:
            handler(arg)
        finally:
            _receiving.active = False

    return marked


class PrimaryChannel(Protocol):
    """What the waiter needs of its primary subscription (a ``WireSubscription``)."""

    def enter_wait(self, waiter: ChannelWaiter) -> bool:
        """Whether the executor may block in the channel now.

        If so, ``waiter.inside_of`` is set under the subscription's lock, so a release
        meanwhile leaves the turn to :meth:`took`.
        """

    def channel_recv(self) -> Any:
        """Block until the channel holds a sample (GIL released); raises once it is closed."""

    def took(self, waiter: ChannelWaiter, sample: Any, closed: bool = False) -> None:
        """The executor left ``waiter``'s wait in the channel.

        ``sample``: data for pull, a poke, or None (nothing taken); ``closed``: the channel
        closed. Clears ``waiter.inside_of`` under the subscription's lock (with :meth:`enter_wait`,
        the bracket a release looks at).
        """

    def poke(self) -> None:
        """Put a DELETE for this session only in the channel (wakes a blocked receive)."""

    def promote(self, replacing: PrimaryChannel) -> None:
        """Become the waiter's primary instead of ``replacing``.

        Called on the executor's thread outside any channel; does nothing if either is no
        longer a source of the waiter.
        """


class ChannelWaiter:
    """The :class:`~posekit.runtime.inbox.Waiter` of an executor pulling Zenoh subscriptions.

    One per executor inbox. ``primary`` is set and cleared by the subscription that serves as
    the primary (under its own lock). See the module docstring.
    """

    def __init__(self) -> None:
        self._plain = WakeSignal()
        self._signalled = False
        #: The subscription whose channel the executor waits in (None: plain wait).
        self.primary: PrimaryChannel | None = None
        #: The subscription whose channel the executor is blocked in right now, or None.
        self.inside_of: PrimaryChannel | None = None
        self._poked = False  # a poke was sent (or asked for) since the executor went in
        # The helper thread: sends the pokes asked for and keeps the deadline.
        self._cond = threading.Condition(threading.Lock())
        self._deadline: float | None = None
        self._helper_until = float("inf")  # what the helper sleeps until
        self._poke_asked = False
        self._helper: threading.Thread | None = None
        self._closed = False
        # Wake-ups by one secondary since the executor last took data from the primary
        # (counted without a lock: a heuristic, a lost count only delays a promotion).
        self._busiest: PrimaryChannel | None = None
        self._secondary_wakes = 0

    # -- the Waiter protocol ----------------------------------------------------------
    def set(self) -> None:
        """Signal; a blocked executor is poked by the helper thread (any caller, any lock).

        Inside a handler marked :func:`on_receive_thread` the poke is sent at once.
        """
        if getattr(_receiving, "active", False):
            self.set_from_receiver()
            return
        self._signalled = True
        self._plain.set()
        if self.inside_of is not None and not self._poked:
            self._poked = True
            with self._cond:
                self._poke_asked = True
                self._ensure_helper()
                self._cond.notify()

    def set_from_receiver(self) -> None:
        """:meth:`set` from a subscription's receive thread, which holds no lock: poke at once."""
        self._signalled = True
        self._plain.set()
        inside = self.inside_of
        if inside is not None and not self._poked:
            self._poked = True
            inside.poke()

    def clear(self) -> None:
        """Unsignal."""
        self._signalled = False
        self._plain.clear()

    def is_set(self) -> bool:
        """Whether signalled."""
        return self._signalled

    def wait(self, timeout: float | None = None) -> bool:
        """Until signalled, a sample in the primary's channel, or ``timeout`` seconds passed.

        False only when a plain wait timed out. In the channel a timeout is a poke like any
        other wake-up, and True; the executor looks at the clock itself.
        """
        primary = self.primary
        busiest = self._busiest
        if (self._secondary_wakes >= PROMOTE_AFTER and busiest is not None
                and primary is not None and busiest is not primary):
            # The traffic is on a secondary: it becomes the primary (one wake-up per
            # sample), the primary a secondary.
            self._busiest, self._secondary_wakes = None, 0
            busiest.promote(primary)
            primary = self.primary
        if primary is None or self._closed:
            return self._plain.wait(timeout)
        self._poked = False
        if not primary.enter_wait(self):  # the receive thread still holds the channel
            return self._plain.wait(timeout)
        sample, closed = None, False
        try:
            if not self._signalled:  # (set() before inside_of was did not poke)
                if timeout is not None:
                    self._arm(time.monotonic() + max(0.0, timeout))
                try:
                    sample = primary.channel_recv()
                except (KeyboardInterrupt, SystemExit):
                    raise
                except Exception:  # the channel closed (session closed): no more waiting in it
                    closed = True
        finally:
            if timeout is not None:
                self._deadline = None
            primary.took(self, sample, closed)  # clears inside_of
        return True

    # -- which subscription is the primary ----------------------------------------------
    def note_secondary(self, source: PrimaryChannel) -> None:
        """``source``, a secondary, handed a sample over (its receive thread woke first)."""
        if source is not self._busiest:
            self._busiest, self._secondary_wakes = source, 0
        self._secondary_wakes += 1

    def note_primary(self) -> None:
        """The executor took samples from the primary's channel."""
        self._secondary_wakes = 0

    def forget(self, source: PrimaryChannel) -> None:
        """``source`` is no longer a source of this waiter: never promote it."""
        if self._busiest is source:
            self._busiest, self._secondary_wakes = None, 0

    # -- the helper thread ------------------------------------------------------------
    def _arm(self, deadline: float) -> None:
        with self._cond:
            self._deadline = deadline
            if deadline < self._helper_until:  # it sleeps longer than that: wake it to re-arm
                self._ensure_helper()
                self._cond.notify()

    def _ensure_helper(self) -> None:
        """Start the helper thread if needed (the caller holds ``_cond``)."""
        if self._helper is None and not self._closed:
            self._helper = threading.Thread(target=self._run_helper, daemon=True,
                                            name="posekit-zenoh wait")
            self._helper.start()

    def _run_helper(self) -> None:
        cond = self._cond
        with cond:
            while not self._closed:
                now = time.monotonic()
                deadline = self._deadline
                due = deadline is not None and now >= deadline
                if self._poke_asked or due:
                    self._poke_asked = False
                    if due:
                        self._deadline = None
                    target = self.inside_of
                    if target is not None:
                        self._poked = True
                        cond.release()  # a full channel may hold the poke back: no lock held
                        try:
                            target.poke()
                        finally:
                            cond.acquire()
                    continue
                self._helper_until = float("inf") if deadline is None else deadline
                woken = cond.wait(_HELPER_IDLE_S if deadline is None else deadline - now)
                self._helper_until = float("-inf")  # awake: no notify needed to re-arm
                if not woken and self._deadline is None and not self._poke_asked:
                    break  # idle: the next deadline or poke starts a new helper
            self._helper = None

    def close(self, timeout: float = 2.0) -> None:
        """Stop the helper; wait (at most ``timeout`` s) for the executor to leave the channel.

        Called after the session closed, which ends every blocked receive.
        """
        with self._cond:
            self._closed = True
            self._cond.notify()
        end = time.monotonic() + timeout
        while self.inside_of is not None and time.monotonic() < end:
            time.sleep(0.001)
        self._plain.set()
