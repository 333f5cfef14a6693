"""Which timer an executor calls next, and when: the due-time bookkeeping of the executors.

The order is rcl's: among the ready timers whose callback group is free, the one due first
(earliest next call time), ties in creation order.

Timers on a clock the executor drives (a stepped executor's node clocks, all showing the
same simulated time) sit in a heap keyed ``(next call ns, creation seq)``, so the next one is
found without scanning the others; :meth:`TimerSchedule.invalidate` (a timer was cancelled,
reset or re-periodised; nodes, ``use_sim_time`` or the time itself changed in a way the heap
cannot follow) makes the next look rebuild it. Zero-period timers (ready once whenever the
clock moves) and timers on any other clock (wall clocks, another node's clock) are scanned
at every look. A wall-clock executor has no driven clock: it scans all its timers.
"""

from __future__ import annotations

import heapq
from collections.abc import Callable

from posekit.runtime.clock import ROSClock
from posekit.runtime.entities import Timer

__all__ = ["TimerSchedule"]


def _never(_timer: Timer) -> bool:
    return False


def _scan(timers: list[Timer]) -> Timer | None:
    """The ready timer due first (creation order among equals) whose group is free."""
    best: Timer | None = None
    for timer in timers:
        if timer.ready_now() and timer.callback_group.can_execute() and (
            best is None or timer.next_call_ns < best.next_call_ns
        ):
            best = timer
    return best


class TimerSchedule:
    """The timers of one executor, in due order.

    ``driven(timer)``: whether ``timer``'s clock is one the executor sets itself (such
    timers go in the heap); default: none is.
    """

    def __init__(self, driven: Callable[[Timer], bool] = _never) -> None:
        self._driven = driven
        self._timers: list[Timer] = []
        self._heap: list[tuple[int, int, Timer]] = []
        self._scanned: list[Timer] = []  # zero-period driven timers, then all others
        #: Whether the schedule was invalidated (or given new timers) since the last look
        #: (a plain attribute: the executor's message loop reads it once per message).
        self.changed = True

    @property
    def timers(self) -> list[Timer]:
        """Every timer, in creation order."""
        return self._timers

    def set_timers(self, timers: list[Timer]) -> None:
        """Schedule ``timers`` (any order) instead of the current ones."""
        self._timers = sorted(timers, key=lambda t: t.seq)
        self.changed = True

    def invalidate(self) -> None:
        """A timer moved or the executor's clocks changed: re-sort at the next look.

        Safe to call from any thread.
        """
        self.changed = True

    def _rebuild(self) -> None:
        self.changed = False  # first: a change during the rebuild marks it again
        heap: list[tuple[int, int, Timer]] = []
        zero: list[Timer] = []
        other: list[Timer] = []
        driven = self._driven
        for timer in self._timers:
            if timer.stopped:
                continue  # cancel()/reset() invalidate the schedule again
            if driven(timer):
                if timer.period_ns == 0:
                    zero.append(timer)
                else:
                    timer.ready_now()  # applies backward-jump rescheduling first
                    heap.append((timer.next_call_ns, timer.seq, timer))
            else:
                other.append(timer)
        heapq.heapify(heap)
        self._heap, self._scanned = heap, zero + other

    def _heap_top(self) -> tuple[Timer, int] | None:
        """The heap's timer due first and its clock's time.

        Entries that moved are re-keyed or dropped first.
        """
        heap = self._heap
        while heap:
            due, seq, timer = heap[0]
            now = timer.clock.now_ns()
            if timer.next_call_ns == due and now >= timer.last_call_ns:
                return timer, now  # the common case: a valid entry, no backward jump
            if timer.stopped:
                heapq.heappop(heap)
            elif not self._driven(timer):  # e.g. use_sim_time switched off: reclassify
                self._rebuild()
                heap = self._heap
            else:
                timer.ready_now()  # applies backward-jump rescheduling
                heapq.heapreplace(heap, (timer.next_call_ns, seq, timer))
        return None

    def claim_due(self) -> Timer | None:
        """The timer to call now, or None.

        Its callback group is claimed and the call marked (its next call moved on). One thread
        at a time (the executor's lock, or the stepping thread).
        """
        if self.changed:
            self._rebuild()
        heap = self._heap
        found: tuple[Timer, int] | None = None
        if heap:  # _heap_top's common case inline (the stepped executor's hot path)
            due, _, timer = heap[0]
            now = timer.clock.now_ns()
            if timer.next_call_ns == due and now >= timer.last_call_ns:
                found = (timer, now)
            else:
                found = self._heap_top()
        top: Timer | None = None
        best: Timer | None = None
        if found is not None and found[0].next_call_ns <= found[1]:
            top = found[0]
            if top.callback_group.can_execute():
                best = top
            else:  # its group is busy (a re-entrant spin): scan every timer instead
                best = _scan(self._timers)
                # Whatever it picks may sit deeper in the heap: re-sort afterwards.
                self.changed = True
        if self._scanned:
            extra = _scan(self._scanned)
            if extra is not None and (best is None or (extra.next_call_ns, extra.seq)
                                      < (best.next_call_ns, best.seq)):
                best = extra
        if best is None or not best.callback_group.beginning_execution():
            return None
        best.mark_called(found[1] if best is top and found is not None else None)
        if best is top and not self.changed:
            heapq.heapreplace(self._heap, (best.next_call_ns, best.seq, best))
        return best

    def next_due_ns(self, now_ns: int) -> int | None:
        """Simulated time (ns, at least ``now_ns``) of the next call of a sim-clock timer.

        A timer on an active ROS clock with a period, i.e. the next time a stepped executor must
        stop at; None if there is no such timer.
        """
        if self.changed:
            self._rebuild()
        found = self._heap_top()
        best = None if found is None else max(found[0].next_call_ns, now_ns)
        for timer in self._scanned:
            if timer.stopped:
                continue
            clock = timer.clock
            if not (isinstance(clock, ROSClock) and clock.ros_time_is_active):
                continue
            if timer.period_ns == 0:
                continue  # runs once per step; it does not drive time
            timer.ready_now()  # applies backward-jump rescheduling
            due = max(timer.next_call_ns, now_ns)
            if best is None or due < best:
                best = due
        return best

    def wall_wait_s(self) -> float | None:
        """Wall seconds until the next timer not on an active ROS clock is due (None: none).

        Those on an active ROS clock wake up with the /clock messages that move them.
        """
        return self._wall_s_until_due(sim_time_due_now=False)

    def quiet_wall_s(self) -> float | None:
        """Wall seconds during which no timer comes due (None: no timer ever does).

        0.0 when one is due now or runs on an active ROS clock: a /clock message, which
        nothing here sees, may make it due at any moment.
        """
        return self._wall_s_until_due(sim_time_due_now=True)

    def _wall_s_until_due(self, *, sim_time_due_now: bool) -> float | None:
        best: int | None = None
        for timer in self._timers:
            clock = timer.clock
            if isinstance(clock, ROSClock) and clock.ros_time_is_active:
                if sim_time_due_now and not (timer.stopped):
                    return 0.0
                continue
            remaining = timer.ns_until_next_call()
            if remaining is not None and (best is None or remaining < best):
                best = remaining
        return None if best is None else max(0.0, best / 1e9)
