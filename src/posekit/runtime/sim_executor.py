"""The stepped executor: :class:`SimulatedTimeExecutor` owns simulated ROS time.

It runs every callback that is ready at the current sim time (tasks, then due timers, then
messages in arrival order, as :mod:`posekit.runtime.executors`), then jumps straight to the
next timer due time (no sleeping) and sets every node's clock. Messages are delivered at the
sim time they were published (zero latency). With the same inputs the sequence of callbacks
and messages is identical run after run. ``real_time_factor=1.0`` paces it to the wall clock
instead.

The simulation owns ``/clock`` (the one clock story):

* its own nodes are *driven*: the executor sets their time; they neither follow nor receive
  ``/clock``, so a foreign ``/clock`` publisher can never disturb them;
* it publishes ``/clock`` at every step exactly when its nodes are visible to other processes
  (one of them is on a transport with ``crosses_processes``, e.g. Zenoh), so nodes and tools
  elsewhere can follow it (``publish_clock`` True/False forces it either way);
* :meth:`SimulatedTimeExecutor.claim_clock` (called by ``posekit.launch`` before a run
  starts) refuses to start a second simulation clock: if another publisher of ``/clock`` is
  already on the graph it raises :class:`ClockConflictError` with one line naming it;
* a ``/clock`` publisher that appears later is reported once (WARN, naming its node) and
  changes nothing: the simulation keeps its time and followers keep following it (they
  ignore a second source, see :mod:`posekit.runtime.time_source`).

Its timers on the driven node clocks sit in the heap of its
:class:`~posekit.runtime.timer_schedule.TimerSchedule`.
"""

from __future__ import annotations

import math
import threading
import time
from typing import Any

from posekit.msgs.rosgraph_msgs import Clock as ClockMsg
from posekit.runtime.clock import ROSClock
from posekit.runtime.context import Context
from posekit.runtime.entities import Timer
from posekit.runtime.executors import Executor, runs_callbacks
from posekit.runtime.logging import get_logger
from posekit.runtime.node import Node
from posekit.runtime.parameters import Parameter
from posekit.runtime.qos import QoSProfile
from posekit.runtime.task import Future
from posekit.runtime.time_source import TimeSource
from posekit.runtime.timer_schedule import TimerSchedule
from posekit.runtime.transport import Transport
from posekit.time import ClockType, Duration, Time

__all__ = [
    "BEHIND_LAG_S",
    "BEHIND_LOG_PERIOD_S",
    "RTF_WINDOW_S",
    "ClockConflictError",
    "SimulatedTimeExecutor",
    "graph_clock_publishers",
]


class ClockConflictError(RuntimeError):
    """Another ``/clock`` publisher is on the graph: a second simulation clock is refused."""


def _clock_publisher_names(transport: Transport) -> list[str]:
    return sorted(i.node_fqn for i in transport.get_publishers_info_by_topic("/clock"))


def graph_clock_publishers(transport: Transport, *, settle_s: float = 0.3) -> list[str]:
    """The publishers of ``/clock`` on ``transport``'s graph; empty when there is none.

    Node names where the graph says, else ``"N publisher(s)"``.

    A network graph is completed with its ``sync_graph`` query, repeated for up to
    ``settle_s`` wall seconds until a publisher shows up: one query right after a session
    opened can come back before the network answered.
    """
    deadline = time.monotonic() + settle_s
    networked = transport.crosses_processes  # its graph completes over time
    while True:
        if networked:
            transport.sync_graph(max(0.05, deadline - time.monotonic()))
        count = int(transport.count_publishers("/clock"))
        if count > 0 or not networked or time.monotonic() >= deadline:
            break
        time.sleep(0.05)
    if count <= 0:
        return []
    return sorted(set(_clock_publisher_names(transport))) or [f"{count} publisher(s)"]


def _to_ns(t: float | int | Time | Duration) -> int:
    if isinstance(t, Time | Duration):
        return t.nanoseconds
    return round(float(t) * 1e9)


#: Wall seconds over which a paced run's real-time factor is measured.
RTF_WINDOW_S = 1.0
#: A paced run this far behind its schedule at the end of a window is "falling behind".
BEHIND_LAG_S = 0.25
#: At most one "falling behind" warning per this many wall seconds.
BEHIND_LOG_PERIOD_S = 10.0


def _sim_log() -> Any:
    return get_logger("posekit.simulation")


class SimulatedTimeExecutor(Executor):
    """A stepped executor that owns simulated ROS time (see the module docstring).

    Nodes added get ``use_sim_time=True``. Timers on other clocks (an explicit system or
    steady clock) are still checked, against the wall clock, which makes them the only
    non-deterministic part of a stepped run.
    """

    def __init__(
        self,
        *,
        context: Context | None = None,
        start_time: float | Time = 0.0,
        real_time_factor: float | None = None,
        publish_clock: bool | None = None,
    ) -> None:
        super().__init__(context=context)
        self._now_ns = _to_ns(start_time)
        if self._now_ns < 0:
            raise ValueError("start_time must be >= 0")
        if real_time_factor is not None and real_time_factor <= 0:
            raise ValueError("real_time_factor must be > 0 (or None for as fast as possible)")
        self.real_time_factor = real_time_factor
        self._publish_clock_choice = publish_clock
        self._publish_clock = bool(publish_clock)  # effective value, see _rebuild_timers
        self._foreign_check_at = 0.0
        self._foreign_reported: set[str] = set()
        self._claimed: Any = None  # the transport claim_clock checked, if any
        self._clock_node: Node | None = None
        self._clock_pub: Any = None
        self._anchor: tuple[float, int] | None = None
        self._pace_stop = threading.Event()  # set by shutdown(): ends a pacing wait at once
        self._rtf_window: tuple[float, int] | None = None
        self._behind_logged = -math.inf
        #: Simulated seconds per wall second over the last :data:`RTF_WINDOW_S` of a paced
        #: run (None before the first window, and when not paced).
        self.measured_real_time_factor: float | None = None
        #: Callbacks executed so far.
        self.callbacks_run = 0
        self._time_sources: list[TimeSource] = []

    # -- time -------------------------------------------------------------------------
    @property
    def now_ns(self) -> int:
        """Current simulated time in nanoseconds."""
        return self._now_ns

    def now(self) -> Time:
        """Current simulated time."""
        return Time(nanoseconds=self._now_ns, clock_type=ClockType.ROS_TIME)

    def add_node(self, node: Node) -> bool:
        """Add ``node`` with its clock driven by this executor (``use_sim_time`` set true)."""
        time_source = node.handoff.time_source
        # Driven first: the node never subscribes to /clock while the executor owns its time.
        time_source.set_driven(True)
        if not node.get_parameter("use_sim_time").value:
            node.set_parameters([Parameter("use_sim_time", value=True)])
        time_source.set_time_ns(self._now_ns)
        return super().add_node(node)

    def remove_node(self, node: Node) -> None:
        """Remove ``node``; a live node's clock follows ``/clock`` again."""
        super().remove_node(node)
        handoff = node.handoff
        if not self._is_shutdown and handoff.executor is None and not handoff.destroyed:
            handoff.time_source.set_driven(False)  # on its own again: follow /clock

    @property
    def publish_clock(self) -> bool:
        """Whether ``/clock`` is published at every step.

        Default (``publish_clock=None``): exactly when a node of the executor is visible to
        other processes; setting True or False forces it.
        """
        return self._publish_clock

    @publish_clock.setter
    def publish_clock(self, enabled: bool | None) -> None:
        self._publish_clock_choice = enabled
        self._update_publish_clock()

    def _update_publish_clock(self) -> None:
        choice = self._publish_clock_choice
        claimed = self._claimed is not None and self._claimed.crosses_processes
        self._publish_clock = bool(choice) if choice is not None else claimed or any(
            n.transport.crosses_processes for n in self._nodes
        )

    def _clock_transport(self) -> Any:
        if self._claimed is not None:
            return self._claimed
        for node in self._nodes:
            if node.transport.crosses_processes:
                return node.transport
        return self._context.transport()

    def claim_clock(self, transport: Any = None, *, timeout_sec: float = 0.3) -> None:
        """Refuse a second simulation clock.

        ``transport``: where the simulation's nodes are (or will be: ``posekit.launch`` claims
        before it creates any node, so a refused run never shows a node to others); default: the
        nodes' transport.

        When ``/clock`` is to be published there (``publish_clock`` True, or None and the
        transport crosses processes) and another publisher of ``/clock`` is already on its
        graph (see :func:`graph_clock_publishers`), raise :class:`ClockConflictError`;
        otherwise start publishing ``/clock`` there.
        """
        if self._clock_pub is not None:
            return
        transport = transport if transport is not None else self._clock_transport()
        choice = self._publish_clock_choice
        if choice is False or (choice is None and not transport.crosses_processes
                               and not self._publish_clock):
            return
        others = graph_clock_publishers(transport, settle_s=timeout_sec)
        if others:
            raise ClockConflictError(
                f"another clock source already publishes /clock ({', '.join(others)}): a "
                "second simulation would fight over sim time. Stop it first, or run your "
                "nodes against it (use_sim_time:=true) instead of starting another simulation"
            )
        self._claimed = transport
        self._update_publish_clock()
        self._ensure_clock_publisher()

    def _foreign_clock_publishers(self, transport: Any) -> list[str]:
        """Who else publishes /clock on ``transport`` now (the live graph, no query)."""
        count = transport.count_publishers("/clock") - (self._clock_pub is not None)
        if count <= 0:
            return []
        names = _clock_publisher_names(transport)
        if self._clock_node is not None and self._clock_pub is not None:
            own = self._clock_node.get_fully_qualified_name()
            if own in names:
                names.remove(own)  # ours, once
        return sorted(set(names)) or [f"{count} publisher(s)"]

    def _ensure_clock_publisher(self) -> None:
        if self._clock_pub is None:
            # No executor spins this node: it serves nothing, so it advertises no parameter
            # or type description services (which nobody would answer: `param list` would
            # wait on them).
            self._clock_node = Node(
                "posekit_sim_clock", context=self._context, transport=self._clock_transport(),
                start_parameter_services=False,
                parameter_overrides=[Parameter("start_type_description_service", value=False)],
            )
            self._clock_pub = self._clock_node.create_publisher(
                ClockMsg, "/clock", QoSProfile(depth=1)
            )

    def _publish_clock_msg(self) -> None:
        if not self._publish_clock:
            return
        if self._clock_pub is None:
            self._ensure_clock_publisher()
        msg = ClockMsg()
        msg.clock.sec, msg.clock.nanosec = divmod(self._now_ns, 1_000_000_000)
        self._clock_pub.publish(msg)
        transport = self._clock_node.transport if self._clock_node else None
        if transport is not None and transport.crosses_processes:
            wall = time.monotonic()
            if wall >= self._foreign_check_at:  # a graph lookup, once a wall second
                self._foreign_check_at = wall + 1.0
                self._report_foreign_clocks(transport)

    def _report_foreign_clocks(self, transport: Any) -> None:
        new = [n for n in self._foreign_clock_publishers(transport)
               if n not in self._foreign_reported]
        if new and self._clock_node is not None:
            self._foreign_reported.update(new)
            self._clock_node.get_logger().warning(
                f"Ignoring a second /clock publisher ({', '.join(new)}): this simulation owns "
                "/clock; its nodes keep its time and followers elsewhere keep following it"
            )

    def set_time(self, t: float | Time) -> None:
        """Jump to ``t`` (seconds or Time), forwards or backwards; jump callbacks fire."""
        ns = _to_ns(t)
        if ns < 0:
            raise ValueError("simulated time cannot be negative")
        self._now_ns = ns
        self._anchor = None
        for node in list(self._nodes):
            node.handoff.time_source.set_time_ns(ns)
        self._schedule.invalidate()  # a backward jump restarts timer periods
        self._publish_clock_msg()

    def _advance(self, ns: int) -> None:
        if ns == self._now_ns:
            return
        if self.real_time_factor is not None:
            if self._anchor is None:
                self._anchor = (time.monotonic(), self._now_ns)
            wall0, sim0 = self._anchor
            due = wall0 + (ns - sim0) / 1e9 / self.real_time_factor
            delay = due - time.monotonic()
            if delay > 0 and self._pace_stop.wait(delay):
                return  # shut down while waiting: time stays where it is
            self._watch_pace(ns, -delay)
        self._now_ns = ns
        for source in self._time_sources:
            source.set_time_ns(ns)
        if self._publish_clock:
            self._publish_clock_msg()

    def _watch_pace(self, ns: int, lag_s: float) -> None:
        """The watchdog of a paced run, ``lag_s`` seconds behind its schedule (< 0: ahead).

        Measures the real-time factor over windows of :data:`RTF_WINDOW_S` wall seconds
        (:attr:`measured_real_time_factor`); once a window ends more than
        :data:`BEHIND_LAG_S` behind, logs one warning with the factor (at most every
        :data:`BEHIND_LOG_PERIOD_S`) and re-anchors the pace there, so a run that cannot
        keep up goes on at the speed it can (as Gazebo does) instead of racing to catch up.
        """
        now = time.monotonic()
        window = self._rtf_window
        if window is None or window[1] > ns:
            self._rtf_window = (now, ns)
            return
        wall0, sim0 = window
        if now - wall0 < RTF_WINDOW_S:
            return
        rtf = (ns - sim0) / 1e9 / (now - wall0)
        self.measured_real_time_factor = rtf
        self._rtf_window = (now, ns)
        if lag_s <= BEHIND_LAG_S:
            return
        self._anchor = (now, ns)
        if now - self._behind_logged >= BEHIND_LOG_PERIOD_S:
            self._behind_logged = now
            _sim_log().warning(
                f"simulation is falling behind real time: real-time factor {rtf:.2f} "
                f"(target {self.real_time_factor:g}) at t = {ns / 1e9:.1f} s sim, "
                f"{lag_s:.1f} s behind"
            )

    # -- timer schedule ---------------------------------------------------------------
    def _make_schedule(self) -> TimerSchedule:
        return TimerSchedule(self._drives)

    def _drives(self, timer: Timer) -> bool:
        """Whether ``timer`` is on a clock this executor sets.

        Its own node's clock, that node in this executor, on sim time (then the clock shows this
        executor's time).
        """
        handoff = timer.handoff
        clock = timer.clock
        return (
            isinstance(clock, ROSClock)
            and clock is handoff.node.get_clock()
            and handoff.executor is self
            and clock.ros_time_is_active
        )

    def _rebuild_timers(self) -> None:
        super()._rebuild_timers()
        self._time_sources = [node.handoff.time_source for node in self._nodes]
        self._update_publish_clock()

    def _take_ready(self) -> tuple[int, Any, Any] | None:
        # Only the stepping thread claims timers, so the schedule needs no lock here (node
        # and timer changes from other threads only invalidate it).
        work = self._take_task_or_timer()
        if work is not None or not len(self.inbox):
            return work
        with self._lock:
            return self._take_message()

    def _next_timer_ns(self) -> int | None:
        """Sim time (ns) of the next timer call that moves time (None: no such timer)."""
        return self._schedule.next_due_ns(self._now_ns)

    # -- running ----------------------------------------------------------------------
    def _run_ready(self) -> int:
        """Run every callback ready at the current sim time.

        In the order of the module docstring: tasks, due timers, then messages in arrival order.
        """
        count = 0
        context = self._context
        tasks = self._tasks
        claim_timer = self._schedule.claim_due
        call = self._call
        inbox = self.inbox
        # context._ok: Context.ok() without a call per callback (the stepped hot path).
        while context._ok and not self._is_shutdown:
            if tasks:
                tasks.popleft().step()
                count += 1
                continue
            timer = claim_timer()
            if timer is not None:
                call(timer)
                count += 1
                continue
            if not len(inbox):
                break
            with self._lock:
                work = self._take_message()
            if work is None:
                break
            self._execute(work)
            # Sim time is frozen during a step, so no timer can become due while the queued
            # messages are delivered: drain them in arrival order.
            count += 1 + self._drain_messages(1 << 62)
        self.callbacks_run += count
        return count

    @runs_callbacks
    def run_until(self, t: float | Time) -> int:
        """Advance simulated time to ``t`` (seconds or Time); returns the number of callbacks run.

        Every callback due on the way runs, in time order.
        """
        target = _to_ns(t)
        if target < self._now_ns:
            raise ValueError(
                f"run_until({target / 1e9} s) is before the current sim time "
                f"{self._now_ns / 1e9} s; use set_time() to jump back"
            )
        start = self.callbacks_run
        while self._context.ok() and not self._is_shutdown:
            self._run_ready()
            nxt = self._next_timer_ns()
            if nxt is None or nxt > target:
                self._advance(target)
                self._run_ready()
                break
            self._advance(nxt)
        return self.callbacks_run - start

    def run_for(self, seconds: float | Duration) -> int:
        """run_until(now + seconds)."""
        return self.run_until(Time(nanoseconds=self._now_ns + _to_ns(seconds)))

    @runs_callbacks
    def spin_once(self, timeout_sec: float | None = None) -> None:
        """Run one ready callback; if none, jump to the next timer and run one there.

        With no timers at all, wait up to ``timeout_sec`` wall seconds for an outside message.
        """
        work = self._take_ready()
        if work is None:
            nxt = self._next_timer_ns()
            if nxt is not None:
                self._advance(nxt)
                work = self._take_ready()
            else:
                work = self._wait_for_work(timeout_sec)
        if work is not None:
            self._execute(work)
            self.callbacks_run += 1

    @runs_callbacks
    def spin_until_future_complete(
        self, future: Future[Any], timeout_sec: float | None = None
    ) -> None:
        """Step until ``future`` is done; ``timeout_sec`` counts *simulated* seconds."""
        future.add_done_callback(lambda _f: self.wake())
        end = None if timeout_sec is None or timeout_sec < 0 else self._now_ns + _to_ns(timeout_sec)
        schedule = self._schedule
        while self._context.ok() and not self._is_shutdown and not future.done():
            if not self._run_ready():
                nxt = self._next_timer_ns()
                if nxt is None:
                    # Nothing moves sim time: wait for outside work, the future itself, or
                    # a new timer (a timer change marks the schedule dirty and wakes us).
                    work = self._wait_for_work(None, lambda: future.done() or schedule.changed)
                    if work is not None:
                        self._execute(work)
                        self.callbacks_run += 1
                    continue
                if end is not None and nxt > end:
                    self._advance(max(end, self._now_ns))
                    self._run_ready()
                    return
                self._advance(nxt)

    def shutdown(self, timeout_sec: float | None = None) -> bool:
        """Shut down as :meth:`Executor.shutdown`, and destroy the ``/clock`` publisher node.

        A paced run waiting for the wall clock stops waiting at once.
        """
        self._pace_stop.set()
        result = super().shutdown(timeout_sec)
        if self._clock_node is not None and self._context.ok():
            self._clock_node.destroy_node()
        return result
