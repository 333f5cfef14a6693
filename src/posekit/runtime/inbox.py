"""The hand-off between a node's entities and the executor that runs their callbacks.

* :class:`Inbox` (one per executor): subscriptions, service servers and clients put an entry
  ``(seq, entity)`` in it when a message, request or response is queued (``seq``: the
  context-wide arrival number, which orders messages across all entities); the executor
  takes the entries in that order. ``put`` wakes the executor when it is waiting for work;
  ``wake`` wakes it for any other reason (a task, shutdown). Entities and nodes also report
  changes through it: :meth:`Inbox.timers_changed` (a timer was cancelled, reset or
  re-periodised) and :meth:`Inbox.entities_changed` (a timer, subscription, server or client
  was created or destroyed, or ``use_sim_time`` switched).
* :class:`Handoff` (one per node, shared by its entities): which executor and inbox the node
  is in (None and None when in none), and what an executor may use of the node: its
  queued entities and its time source.

* Pulled sources: a network subscription may let the executor take its samples itself
  (:meth:`Inbox.add_source`), as rclpy's executor takes from the middleware's wait set: the
  executor calls each source's ``pull(budget)`` on its own thread. The source's transport
  supplies the :class:`Waiter` the executor then blocks on, which the middleware's receive
  thread wakes directly (one thread wake-up per message instead of two): a Cyclone wait set
  for DDS, the channel of one subscription for Zenoh (``posekit.transport.zenoh_wait``).
  Either way no second Python thread contends for the GIL while samples flow.

The payload itself stays in the entity's own queue (bounded by its QoS depth): an inbox
entry is only a pointer, and it is stale once the entity's first queued entry has a later
``seq`` (KEEP_LAST dropped it, or it was delivered), the entity was destroyed, or its node
moved to another executor. The executor skips stale entries when it takes them.
"""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING, Any, Protocol

if TYPE_CHECKING:
    from posekit.runtime.node import Node
    from posekit.runtime.time_source import TimeSource

__all__ = ["Handoff", "Inbox", "PulledSource", "Waiter", "WakeSignal"]


class Waiter(Protocol):
    """What an inbox waits on: :class:`WakeSignal`'s set / clear / is_set / wait."""

    def set(self) -> None:
        """Signal (idempotent, any thread)."""

    def clear(self) -> None:
        """Unsignal."""

    def is_set(self) -> bool:
        """Whether signalled."""

    def wait(self, timeout: float | None = None) -> bool:
        """Until signalled (or woken by a source's data) or ``timeout`` seconds passed."""


class PulledSource(Protocol):
    """A subscription endpoint whose samples the executor takes on its own thread."""

    def pull(self, budget: int) -> int:
        """Hand up to ``budget`` waiting samples to the subscription's sink; how many."""

    def pending(self) -> bool:
        """Whether samples wait that the inbox's waiter would not wake the executor for.

        A source whose data wakes the waiter for as long as samples wait (a DDS read
        condition) says False; one that woke the executor once per hand-over (Zenoh) says
        whether that hand-over is still untaken, which the executor checks before sleeping.
        """


class WakeSignal:
    """``threading.Event``'s set / clear / wait on one raw lock (held = not signalled).

    A waiter woken by ``Event.set`` must then re-take the event's condition lock, which
    the setter may still hold: a second sleep and wake-up for every hand-off. A raw lock
    wakes the waiter once and allocates nothing per wait.
    """

    __slots__ = ("_lock",)

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._lock.acquire()

    def set(self) -> None:
        """Signal (idempotent)."""
        try:  # noqa: SIM105 - suppress() costs a context manager on the hot path
            self._lock.release()
        except RuntimeError:  # already signalled
            pass

    def clear(self) -> None:
        """Unsignal."""
        self._lock.acquire(False)

    def is_set(self) -> bool:
        """Whether signalled."""
        return not self._lock.locked()

    def wait(self, timeout: float | None = None) -> bool:
        """Until signalled or ``timeout`` seconds passed (None: no limit); True if signalled."""
        lock = self._lock
        if lock.acquire(True, -1 if timeout is None else max(0.0, timeout)):
            self.set()  # stay signalled, like an Event, until clear()
            return True
        return False


def _ignore_change() -> None:
    pass


class Inbox:
    """One executor's ready work in arrival order, and its wake-up (see the module docstring).

    ``always_wake``: every ``put`` signals the wake-up (several threads may be waiting, as in
    a multi-threaded executor); otherwise only while a thread waits in :meth:`wait`.
    ``on_timers_changed`` / ``on_entities_changed``: the executor's reactions to the change
    reports (default: ignore them).
    """

    __slots__ = ("_entries", "_on_entities_changed", "_on_timers_changed", "_signal",
                 "_waiter_owner", "always_wake", "append", "sources", "take", "waiting")

    def __init__(
        self,
        *,
        always_wake: bool = False,
        on_timers_changed: Callable[[], None] = _ignore_change,
        on_entities_changed: Callable[[], None] = _ignore_change,
    ) -> None:
        self._entries: deque[tuple[int, Any]] = deque()
        #: ``append((seq, entity))``: :meth:`put` without the wake-up (the deque's own
        #: ``append``, no Python frame). A hot path may call it and then :meth:`wake` when
        #: :attr:`waiting` is true, which is exactly what :meth:`put` does.
        self.append: Callable[[tuple[int, Any]], None] = self._entries.append
        self._signal: Waiter = WakeSignal()
        #: Who supplied the waiter (see :meth:`adopt_waiter`); None for the plain WakeSignal.
        self._waiter_owner: object | None = None
        #: Pulled sources (see :meth:`add_source`), replaced whole so readers need no lock.
        self.sources: tuple[PulledSource, ...] = ()
        self.always_wake = always_wake
        #: True only while a thread may block in :meth:`wait`: a new entry must then wake it.
        self.waiting = always_wake
        self._on_timers_changed = on_timers_changed
        self._on_entities_changed = on_entities_changed
        #: ``take() -> (seq, entity)``: the oldest entry, removed; raises IndexError when
        #: empty (the deque's own ``popleft``, so taking costs no extra call).
        self.take: Callable[[], tuple[int, Any]] = self._entries.popleft

    # -- entities' side -------------------------------------------------------------------
    def put(self, seq: int, entity: Any) -> None:
        """``entity`` queued an item with arrival number ``seq``: hand it to the executor."""
        self.append((seq, entity))
        if self.waiting:
            self._signal.set()

    def wake(self) -> None:
        """Interrupt a :meth:`wait` (new work that is not an entry, shutdown)."""
        self._signal.set()

    def timers_changed(self) -> None:
        """A timer of a node in this executor moved (cancel, reset, new period)."""
        self._on_timers_changed()

    def entities_changed(self) -> None:
        """A node in this executor gained or lost entities, or switched ``use_sim_time``."""
        self._on_entities_changed()

    # -- executor's side ------------------------------------------------------------------
    def put_back(self, entries: list[tuple[int, Any]]) -> None:
        """Return taken ``entries`` (oldest first) to the front, in their order."""
        self._entries.extendleft(reversed(entries))

    def extend(self, entries: Iterable[tuple[int, Any]]) -> None:
        """Append ``entries`` (in arrival order) at the back without waking anyone."""
        self._entries.extend(entries)

    def __len__(self) -> int:
        return len(self._entries)

    def __bool__(self) -> bool:
        return bool(self._entries)

    def prepare_wait(self) -> None:
        """Announce a waiter and clear the wake-up, *before* the caller's last look for work.

        An entry put after that look then finds ``waiting`` set and signals, so no wake-up is
        lost between the look and :meth:`wait`.
        """
        self.waiting = True
        self._signal.clear()

    def wait(self, timeout: float | None) -> bool:
        """Block until :meth:`put` / :meth:`wake` signal or ``timeout`` seconds passed."""
        return self._signal.wait(timeout)

    # -- pulled sources (executors that take samples themselves) ---------------------
    @property
    def waiter(self) -> Waiter:
        """What :meth:`wait` blocks on: a plain WakeSignal, or a transport's waiter."""
        return self._signal

    def adopt_waiter(self, owner: object, make: Callable[[], Waiter]) -> Waiter | None:
        """The waiter of ``owner`` (a transport) for this inbox, made with ``make()`` if needed.

        None when the inbox already waits on another owner's waiter: its sources stay on
        their own threads. A new waiter replaces the plain wake-up; it starts signalled and
        the old one is signalled, so a thread waiting across the swap loses no wake-up.
        """
        if self._waiter_owner is owner:
            return self._signal
        if self._waiter_owner is not None:
            return None
        waiter = make()
        waiter.set()
        old, self._signal, self._waiter_owner = self._signal, waiter, owner
        old.set()
        return waiter

    def add_source(self, source: PulledSource) -> None:
        """From now on the executor calls ``source.pull`` (the source's thread stopped)."""
        if source not in self.sources:
            self.sources = (*self.sources, source)
        self.wake()

    def remove_source(self, source: PulledSource) -> None:
        """``source`` delivers on its own again (or is gone).

        The last one to leave restores the plain wake-up.
        """
        self.sources = tuple(s for s in self.sources if s is not source)
        if not self.sources and self._waiter_owner is not None:
            old, self._signal, self._waiter_owner = self._signal, WakeSignal(), None
            self._signal.set()
            old.set()

    def pull_sources(self, budget: int) -> int:
        """Let every pulled source hand up to ``budget`` samples over; how many in all."""
        sources = self.sources
        if len(sources) == 1:  # the common case, without a generator per wake-up
            return sources[0].pull(budget)
        return sum(source.pull(budget) for source in sources)

    def sources_pending(self) -> bool:
        """Whether a pulled source still holds samples for :meth:`pull_sources`."""
        return any(source.pending() for source in self.sources)

    def end_wait(self) -> None:
        """The waiter left: ``put`` stops signalling (unless ``always_wake``)."""
        self.waiting = self.always_wake


class Handoff:
    """A node's side of the hand-off (one per node, shared by its entities).

    ``executor`` / ``inbox``: the executor the node is in and its inbox (both None while the
    node is in none); an entity with a queued item calls ``handoff.inbox.put(seq, entity)``.
    ``queued_entities()``: the node's subscriptions, servers and clients (what an executor
    adding the node scans for items queued before). ``time_source``: the node's
    :class:`~posekit.runtime.time_source.TimeSource` (a stepped executor drives it).
    """

    __slots__ = ("destroyed", "executor", "inbox", "node", "queued_entities", "time_source")

    def __init__(
        self,
        node: Node,
        queued_entities: Callable[[], list[Any]],
        time_source: TimeSource,
    ) -> None:
        self.node = node
        self.queued_entities = queued_entities
        self.time_source = time_source
        self.executor: Any = None
        self.inbox: Inbox | None = None
        #: True once the node was destroyed.
        self.destroyed = False

    def connect(self, executor: Any, inbox: Inbox) -> None:
        """The node joined ``executor``."""
        self.executor, self.inbox = executor, inbox

    def disconnect(self) -> None:
        """The node left its executor."""
        self.executor = self.inbox = None

    def timers_changed(self) -> None:
        """Report a moved timer to the executor, if any."""
        inbox = self.inbox
        if inbox is not None:
            inbox.timers_changed()

    def entities_changed(self) -> None:
        """Report created/destroyed entities (or a ``use_sim_time`` switch), if in an executor."""
        inbox = self.inbox
        if inbox is not None:
            inbox.entities_changed()
