"""Executors: who calls the callbacks, in which order and at which (simulated) time.

* :class:`SingleThreadedExecutor`: one thread runs timers, subscription callbacks and tasks
  one at a time. Ready timers first (earliest due first, then creation order), then queued
  messages in arrival order across all subscriptions (context-wide sequence numbers).
* :class:`MultiThreadedExecutor`: the same selection, ``num_threads`` workers; callbacks of a
  MutuallyExclusiveCallbackGroup (the node default) never overlap.
* :class:`SimulatedTimeExecutor` (a stepped executor): owns simulated time. It runs every
  callback that is ready at the current sim time, then jumps straight to the next timer due
  time (no sleeping) and sets every node's clock. Messages are delivered at the sim time they
  were published (zero latency). With the same inputs the sequence of callbacks and messages
  is identical run after run. ``real_time_factor=1.0`` paces it to the wall clock instead.

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

An exception raised by a callback is logged by the callback's node logger with the traceback
(``[ERROR] [...] [node]: Exception in timer callback ...``) and does not stop the executor
or other callbacks. ``KeyboardInterrupt``/``SystemExit`` still propagate.
"""

from __future__ import annotations

import functools
import heapq
import inspect
import math
import os
import threading
import time
import traceback
from collections import deque
from collections.abc import Callable, Coroutine
from typing import Any, TypeVar, cast

from posekit.msgs.rosgraph_msgs import Clock as ClockMsg
from posekit.runtime.callback_groups import CallbackGroup
from posekit.runtime.clock import ROSClock
from posekit.runtime.context import Context, get_default_context
from posekit.runtime.entities import Subscription, Timer
from posekit.runtime.logging import get_logger
from posekit.runtime.node import Node
from posekit.runtime.parameters import Parameter
from posekit.runtime.qos import QoSProfile
from posekit.runtime.services import current_executor, set_current_executor
from posekit.runtime.task import Future, Task
from posekit.runtime.time_source import TimeSource
from posekit.time import ClockType, Duration, Time

__all__ = [
    "ClockConflictError",
    "Executor",
    "ExternalShutdownException",
    "Future",
    "MultiThreadedExecutor",
    "SimulatedTimeExecutor",
    "SingleThreadedExecutor",
    "Task",
    "get_global_executor",
    "graph_clock_publishers",
    "spin",
    "spin_once",
    "spin_until_future_complete",
]

_TIMER = 0
_MESSAGE = 1
_TASK = 2

_F = TypeVar("_F", bound=Callable[..., Any])


def _runs_callbacks(method: _F) -> _F:
    """Mark the calling thread as running this executor's callbacks for the call's
    duration (what ``Client.call`` checks to serve a request instead of deadlocking)."""

    @functools.wraps(method)
    def wrapper(self: Executor, *args: Any, **kwargs: Any) -> Any:
        if current_executor() is self:  # nested (spin -> spin_once): already marked
            return method(self, *args, **kwargs)
        previous = set_current_executor(self)
        try:
            return method(self, *args, **kwargs)
        finally:
            set_current_executor(previous)

    return cast(_F, wrapper)


class _WakeSignal:
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
        try:  # noqa: SIM105 - suppress() costs a context manager on the hot path
            self._lock.release()
        except RuntimeError:  # already signalled
            pass

    def clear(self) -> None:
        self._lock.acquire(False)

    def is_set(self) -> bool:
        return not self._lock.locked()

    def wait(self, timeout: float | None = None) -> bool:
        lock = self._lock
        if lock.acquire(True, -1 if timeout is None else max(0.0, timeout)):
            self.set()  # stay signalled, like an Event, until clear()
            return True
        return False


class ClockConflictError(RuntimeError):
    """Another ``/clock`` publisher is on the graph: a second simulation clock is refused."""


class ExternalShutdownException(Exception):  # noqa: N818 - rclpy name
    """The context was shut down while spinning (rclpy.executors.ExternalShutdownException)."""


class Executor:
    """Base executor (see the module docstring for the callback order)."""

    def __init__(self, *, context: Context | None = None) -> None:
        self._context = context or get_default_context()
        self._nodes: list[Node] = []
        self._fifo: deque[tuple[int, Subscription]] = deque()
        self._tasks: deque[Task] = deque()
        self._timers: list[Timer] = []
        self._wake_event = _WakeSignal()
        self._lock = threading.RLock()
        self._is_shutdown = False
        # True only while a spinning thread may block on _wake_event: publishers then set
        # the event (see _wait_for_work for why no wake-up is lost).
        self._waiting = False
        self._always_wake = False  # several waiting threads (MultiThreadedExecutor)
        #: Number of callbacks that raised (each was logged).
        self.callback_exceptions = 0
        self._context._register_executor(self)

    @property
    def context(self) -> Context:
        """The context whose shutdown stops this executor."""
        return self._context

    # -- nodes ------------------------------------------------------------------------
    def add_node(self, node: Node) -> bool:
        """Add ``node``; False if it is already here. A node has at most one executor."""
        with self._lock:
            if node in self._nodes:
                return False
            if node._executor is not None:
                node._executor.remove_node(node)
            self._nodes.append(node)
            node._executor = self
            pending = sorted(
                ((seq, sub) for sub in node._queued_entities() for seq, _ in list(sub.queue)),
                key=lambda item: item[0],
            )
            self._fifo.extend(pending)
            self._rebuild_timers()
        self.wake()
        return True

    def remove_node(self, node: Node) -> None:
        """Remove ``node`` (its queued messages stay queued in its subscriptions)."""
        with self._lock:
            if node in self._nodes:
                self._nodes.remove(node)
                node._executor = None
                self._rebuild_timers()
        self.wake()

    def get_nodes(self) -> list[Node]:
        """Nodes in this executor."""
        return list(self._nodes)

    def _node_changed(self, node: Node) -> None:
        with self._lock:
            self._rebuild_timers()
        self.wake()

    def _timer_changed(self, timer: Timer) -> None:
        """A timer was reset or re-periodised (its next call time moved)."""
        del timer
        self.wake()

    def _rebuild_timers(self) -> None:
        self._timers = sorted((t for n in self._nodes for t in n._timers), key=lambda t: t.seq)

    def wake(self) -> None:
        """Interrupt a wait (new work, shutdown)."""
        self._wake_event.set()

    def _message_ready(self, seq: int, sub: Subscription) -> None:
        self._fifo.append((seq, sub))
        if self._waiting:
            self._wake_event.set()

    # -- tasks ------------------------------------------------------------------------
    def _schedule_task(self, task: Task) -> None:
        self._tasks.append(task)
        self.wake()

    def create_task(self, callback: Callable[..., Any] | Coroutine[Any, Any, Any],
                    *args: Any, **kwargs: Any) -> Task:
        """Run ``callback`` (a coroutine, coroutine function or plain callable) on this
        executor; the returned Task is a Future of its result."""
        coro: Coroutine[Any, Any, Any]
        if inspect.iscoroutine(callback):
            coro = callback
        elif inspect.iscoroutinefunction(callback):
            coro = callback(*args, **kwargs)
        else:
            fn = callback

            async def run_plain() -> Any:
                return fn(*args, **kwargs)  # type: ignore[operator]

            coro = run_plain()
        task = Task(coro, self._schedule_task)
        self._schedule_task(task)
        return task

    # -- selecting work ---------------------------------------------------------------
    def _take_ready(self) -> tuple[int, Any, Any] | None:
        """Claim the next ready callback: (kind, entity, payload) or None."""
        with self._lock:
            if self._tasks:
                return (_TASK, self._tasks.popleft(), None)
            best = self._scan_timers(self._timers)
            if best is not None and best.callback_group.beginning_execution():
                best._mark_called()
                return (_TIMER, best, None)
            return self._take_message()

    @staticmethod
    def _scan_timers(timers: list[Timer]) -> Timer | None:
        """The ready timer due first (creation order among equals) whose group is free."""
        best: Timer | None = None
        for timer in timers:
            if timer.is_ready() and timer.callback_group.can_execute() and (
                best is None or timer._next_ns < best._next_ns
            ):
                best = timer
        return best

    def _take_message(self) -> tuple[int, Any, Any] | None:
        """Claim the oldest queued message whose group is free (caller holds the lock)."""
        fifo = self._fifo
        skipped: list[tuple[int, Subscription]] = []
        found: tuple[int, Any, Any] | None = None
        while fifo:
            entry = fifo.popleft()
            seq, sub = entry
            queue = sub.queue
            if sub.destroyed or not queue or queue[0][0] > seq or (
                sub._node._executor is not self
            ):
                continue  # stale: delivered, dropped by KEEP_LAST, or moved away
            if not sub.callback_group.beginning_execution():
                skipped.append(entry)
                continue
            _, msg = queue.popleft()
            found = (_MESSAGE, sub, msg)
            break
        if skipped:
            fifo.extendleft(reversed(skipped))
        return found

    def _drain_messages(self, budget: int) -> int:
        """Deliver up to ``budget`` queued messages in arrival order without re-checking
        timers and tasks between them (the hot path); returns how many ran."""
        fifo = self._fifo
        popleft = fifo.popleft
        done = 0
        while fifo and done < budget:
            try:
                seq, sub = popleft()
            except IndexError:  # another worker emptied it
                break
            queue = sub.queue
            if not queue or queue[0][0] != seq or sub.destroyed or (
                sub._node._executor is not self
            ):
                continue  # stale: dropped by KEEP_LAST, destroyed, or moved away
            group = sub.callback_group
            if not group.beginning_execution():
                fifo.appendleft((seq, sub))
                break
            try:
                msg = queue.popleft()[1]
                result = sub.callback(msg)
                if result is not None and inspect.iscoroutine(result):
                    self._spawn_callback_task(result, _MESSAGE, sub)
            except Exception:
                self._report(sub._node, self._describe(_MESSAGE, sub), traceback.format_exc())
            finally:
                group.ending_execution()
            done += 1
        return done

    def _spawn_callback_task(self, coro: Coroutine[Any, Any, Any], kind: int,
                             entity: Any) -> None:
        task = Task(coro, self._schedule_task)
        node = entity._node
        what = self._describe(kind, entity)
        task.add_done_callback(lambda f: self._report_future(node, what, f))
        self._schedule_task(task)

    # -- running ----------------------------------------------------------------------
    def _execute(self, work: tuple[int, Any, Any]) -> None:
        kind, entity, payload = work
        if kind == _TASK:
            entity.step()
            return
        group: CallbackGroup = entity.callback_group
        try:
            result = entity.callback(payload) if kind == _MESSAGE else entity.callback()
            if result is not None and inspect.iscoroutine(result):
                self._spawn_callback_task(result, kind, entity)
        except Exception:
            self._report(entity._node, self._describe(kind, entity), traceback.format_exc())
        finally:
            group.ending_execution()

    @staticmethod
    def _describe(kind: int, entity: Any) -> str:
        if kind == _MESSAGE:
            what = getattr(entity, "callback_description", None)
            return what or f"subscription callback on '{entity.topic_name}'"
        return "timer callback"

    def _report(self, node: Node, what: str, tb: str) -> None:
        self.callback_exceptions += 1
        node.get_logger().error(f"Exception in {what}:\n{tb.rstrip()}")

    def _report_future(self, node: Node, what: str, future: Future[Any]) -> None:
        exc = future.exception()
        if exc is not None:
            tb = "".join(traceback.format_exception(type(exc), exc, exc.__traceback__))
            self._report(node, what, tb)

    def _wall_wait_s(self) -> float | None:
        """Seconds until the next wall-clock timer (None: no wall timer)."""
        best: int | None = None
        for timer in self._timers:
            clock = timer.clock
            if isinstance(clock, ROSClock) and clock.ros_time_is_active:
                continue  # woken by /clock messages instead
            remaining = timer.time_until_next_call()
            if remaining is not None and (best is None or remaining < best):
                best = remaining
        return None if best is None else max(0.0, best / 1e9)

    def _wait_for_work(
        self, timeout_sec: float | None, condition: Callable[[], bool] | None = None
    ) -> tuple[int, Any, Any] | None:
        """The next ready callback, waiting up to ``timeout_sec`` (None: forever); None on
        timeout, shutdown, or once ``condition()`` is true (rclpy's wait condition: whoever
        makes it true must call :meth:`wake`, e.g. a future's done-callback)."""
        deadline = None
        if timeout_sec is not None and timeout_sec >= 0:
            deadline = time.monotonic() + timeout_sec
        if (self._fifo or self._tasks) and not self._is_shutdown and self._context.ok():
            # hot path: work is already queued, so the wake-up event need not be armed
            work = self._take_ready()
            if work is not None:
                return work
        try:
            while self._context.ok() and not self._is_shutdown:
                # Order matters: announce waiting, clear, then look for work. A message
                # appended after the look sees _waiting and sets the event.
                self._waiting = True
                self._wake_event.clear()
                if condition is not None and condition():
                    return None
                work = self._take_ready()
                if work is not None:
                    return work
                wait = self._wall_wait_s()
                if deadline is not None:
                    remaining = deadline - time.monotonic()
                    if remaining <= 0:
                        return None
                    wait = remaining if wait is None else min(wait, remaining)
                self._wake_event.wait(wait)
            return None
        finally:
            self._waiting = self._always_wake

    def _serve_until(self, future: Future[Any], timeout_sec: float | None) -> None:
        """Run ready callbacks (never moving simulated time) until ``future`` is done or
        ``timeout_sec`` wall seconds passed: a blocking call made inside a callback."""
        end = None if timeout_sec is None or timeout_sec < 0 else time.monotonic() + timeout_sec
        while not future.done() and self._context.ok():
            work = self._take_ready()
            if work is not None:
                self._execute(work)
                continue
            wait = 0.01
            if end is not None:
                remaining = end - time.monotonic()
                if remaining <= 0:
                    return
                wait = min(wait, remaining)
            future.wait(wait)

    @_runs_callbacks
    def spin_once(self, timeout_sec: float | None = None) -> None:
        """Wait up to ``timeout_sec`` (None: forever) for one callback and run it."""
        work = self._wait_for_work(timeout_sec)
        if work is not None:
            self._execute(work)

    @_runs_callbacks
    def spin(self) -> None:
        """Run callbacks until the context shuts down or shutdown() is called."""
        while self._context.ok() and not self._is_shutdown:
            self.spin_once()

    @_runs_callbacks
    def spin_some(self, max_duration: float = 0.0) -> None:
        """Run what is ready now (and for up to ``max_duration`` s more), then return."""
        end = time.monotonic() + max_duration
        while self._context.ok() and not self._is_shutdown:
            work = self._take_ready()
            if work is None:
                remaining = end - time.monotonic()
                if remaining <= 0:
                    return
                work = self._wait_for_work(remaining)
                if work is None:
                    return
            self._execute(work)
            if work[0] == _MESSAGE:
                self._drain_messages(64)

    def _spin_once_until(self, timeout_sec: float | None, future: Future[Any]) -> None:
        """spin_once that also returns when ``future`` completes (in any thread)."""
        work = self._wait_for_work(timeout_sec, future.done)
        if work is not None:
            self._execute(work)

    @_runs_callbacks
    def spin_until_future_complete(self, future: Future[Any], timeout_sec: float | None = None) -> None:
        """Spin until ``future`` is done or ``timeout_sec`` (wall seconds) passed. A future
        completed by another thread ends the wait at once (its done-callback wakes us)."""
        future.add_done_callback(lambda _f: self.wake())
        if timeout_sec is None or timeout_sec < 0:
            while self._context.ok() and not self._is_shutdown and not future.done():
                self._spin_once_until(None, future)
            return
        end = time.monotonic() + timeout_sec
        while self._context.ok() and not self._is_shutdown and not future.done():
            remaining = end - time.monotonic()
            if remaining <= 0:
                return
            self._spin_once_until(remaining, future)

    def spin_once_until_future_complete(
        self, future: Future[Any], timeout_sec: float | None = None
    ) -> None:
        """spin_once, returning early if ``future`` completes."""
        future.add_done_callback(lambda _f: self.wake())
        if not future.done():
            self._spin_once_until(timeout_sec, future)

    def shutdown(self, timeout_sec: float | None = None) -> bool:
        """Stop spinning and drop the nodes."""
        del timeout_sec
        self._is_shutdown = True
        for node in list(self._nodes):
            self.remove_node(node)
        self.wake()
        return True


class SingleThreadedExecutor(Executor):
    """Runs callbacks one at a time in the spinning thread."""


class MultiThreadedExecutor(Executor):
    """``num_threads`` worker threads (default: CPU count, at least 2) run callbacks;
    callback groups decide what may overlap. ``spin_once`` runs in the calling thread."""

    def __init__(self, num_threads: int | None = None, *, context: Context | None = None) -> None:
        super().__init__(context=context)
        self._num_threads = num_threads or max(2, os.cpu_count() or 2)
        self._always_wake = self._waiting = True
        if self._num_threads < 1:
            raise ValueError("num_threads must be >= 1")

    @property
    def num_threads(self) -> int:
        """How many workers spin() starts."""
        return self._num_threads

    @_runs_callbacks
    def _worker(self) -> None:
        while self._context.ok() and not self._is_shutdown:
            work = self._wait_for_work(0.05)
            if work is not None:
                self._execute(work)
                self.wake()  # a group was released: another worker may now proceed

    def spin(self) -> None:
        workers = [
            threading.Thread(target=self._worker, name=f"posekit-executor-{i}", daemon=True)
            for i in range(self._num_threads - 1)
        ]
        for w in workers:
            w.start()
        try:
            self._worker()
        finally:
            self._is_shutdown_workers(workers)

    def _is_shutdown_workers(self, workers: list[threading.Thread]) -> None:
        if self._context.ok() and not self._is_shutdown:
            return
        for w in workers:
            w.join(timeout=1.0)


def _clock_publisher_names(transport: Any) -> list[str]:
    infos = getattr(transport, "get_publishers_info_by_topic", None)
    return sorted(i.node_fqn for i in infos("/clock")) if callable(infos) else []


def graph_clock_publishers(transport: Any, *, settle_s: float = 0.3) -> list[str]:
    """The publishers of ``/clock`` on ``transport``'s graph (node names where the graph
    says, else ``"N publisher(s)"``); empty when there is none.

    A network graph is completed with its ``sync_graph`` query, repeated for up to
    ``settle_s`` wall seconds until a publisher shows up: one query right after a session
    opened can come back before the network answered."""
    deadline = time.monotonic() + settle_s
    sync = getattr(transport, "sync_graph", None)
    while True:
        if callable(sync):
            sync(max(0.05, deadline - time.monotonic()))
        count = int(transport.count_publishers("/clock"))
        if count > 0 or not callable(sync) or time.monotonic() >= deadline:
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
        self._rtf_window: tuple[float, int] | None = None
        self._behind_logged = -math.inf
        #: Simulated seconds per wall second over the last :data:`RTF_WINDOW_S` of a paced
        #: run (None before the first window, and when not paced).
        self.measured_real_time_factor: float | None = None
        #: Callbacks executed so far.
        self.callbacks_run = 0
        self._time_sources: list[TimeSource] = []
        self._heap: list[tuple[int, int, Timer]] = []
        self._zero_timers: list[Timer] = []
        self._other_timers: list[Timer] = []
        self._schedule_dirty = True

    # -- time -------------------------------------------------------------------------
    @property
    def now_ns(self) -> int:
        """Current simulated time in nanoseconds."""
        return self._now_ns

    def now(self) -> Time:
        """Current simulated time."""
        return Time(nanoseconds=self._now_ns, clock_type=ClockType.ROS_TIME)

    def add_node(self, node: Node) -> bool:
        # Driven first: the node never subscribes to /clock while the executor owns its time.
        node._time_source.set_driven(True)
        if not node.get_parameter("use_sim_time").value:
            node.set_parameters([Parameter("use_sim_time", value=True)])
        node._time_source.set_time_ns(self._now_ns)
        return super().add_node(node)

    def remove_node(self, node: Node) -> None:
        super().remove_node(node)
        if not self._is_shutdown and node._executor is None and not node._destroyed:
            node._time_source.set_driven(False)  # on its own again: follow /clock

    @property
    def publish_clock(self) -> bool:
        """Whether ``/clock`` is published at every step. Default (``publish_clock=None``):
        exactly when a node of the executor is visible to other processes; setting True or
        False forces it."""
        return self._publish_clock

    @publish_clock.setter
    def publish_clock(self, enabled: bool | None) -> None:
        self._publish_clock_choice = enabled
        self._update_publish_clock()

    def _update_publish_clock(self) -> None:
        choice = self._publish_clock_choice
        claimed = self._claimed is not None and self._claimed.crosses_processes
        self._publish_clock = bool(choice) if choice is not None else claimed or any(
            n._transport.crosses_processes for n in self._nodes
        )

    def _clock_transport(self) -> Any:
        if self._claimed is not None:
            return self._claimed
        for node in self._nodes:
            if node._transport.crosses_processes:
                return node._transport
        return self._context.transport()

    def claim_clock(self, transport: Any = None, *, timeout_sec: float = 0.3) -> None:
        """Refuse a second simulation clock. ``transport``: where the simulation's nodes are
        (or will be: ``posekit.launch`` claims before it creates any node, so a refused run
        never shows a node to others); default: the nodes' transport.

        When ``/clock`` is to be published there (``publish_clock`` True, or None and the
        transport crosses processes) and another publisher of ``/clock`` is already on its
        graph (see :func:`graph_clock_publishers`), raise :class:`ClockConflictError`;
        otherwise start publishing ``/clock`` there."""
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
            self._clock_node = Node(
                "posekit_sim_clock", context=self._context, transport=self._clock_transport()
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
        transport = self._clock_node._transport if self._clock_node else None
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
            node._time_source.set_time_ns(ns)
        self._schedule_dirty = True  # a backward jump restarts timer periods
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
            if delay > 0:
                time.sleep(delay)
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
        keep up goes on at the speed it can (as Gazebo does) instead of racing to catch up."""
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
    # Timers on their node's own ROS clock (sim time: every node clock of this executor
    # shows _now_ns) with a period sit in a heap keyed (next call ns, creation seq), so the
    # next due timer is found without scanning all of them; the heap is rebuilt whenever
    # timers, nodes, use_sim_time or the time itself change in a way it cannot follow
    # (_schedule_dirty), and entries of canceled timers are dropped when they surface.
    # Zero-period timers (once per step) and timers on any other clock (wall clocks,
    # another node's clock) are scanned as the base executor does.
    def _rebuild_timers(self) -> None:
        super()._rebuild_timers()
        self._time_sources = [node._time_source for node in self._nodes]
        self._schedule_dirty = True
        self._update_publish_clock()

    def _timer_changed(self, timer: Timer) -> None:
        self._schedule_dirty = True
        self.wake()

    def _rebuild_schedule(self) -> None:
        with self._lock:  # against a concurrent _rebuild_timers
            self._schedule_dirty = False  # first: a change during the rebuild marks it again
            heap: list[tuple[int, int, Timer]] = []
            zero: list[Timer] = []
            other: list[Timer] = []
            for timer in self._timers:
                if timer._canceled or timer.destroyed:
                    continue  # reset() marks the schedule dirty again
                clock = timer.clock
                node = timer._node
                if clock is node._clock and node._executor is self and clock._ros_time_active:
                    if timer._period_ns == 0:
                        zero.append(timer)
                    else:
                        timer.is_ready()  # applies backward-jump rescheduling first
                        heap.append((timer._next_ns, timer.seq, timer))
                else:
                    other.append(timer)
            heapq.heapify(heap)
            self._heap, self._zero_timers, self._other_timers = heap, zero, other

    def _heap_top(self) -> Timer | None:
        """The heap timer due first after dropping stale entries."""
        heap = self._heap
        while heap:
            due, seq, timer = heap[0]
            clock = timer.clock
            if (
                not timer._canceled
                and not timer.destroyed
                and timer._next_ns == due
                and clock._ros_time_active  # type: ignore[attr-defined]
                and clock._override_ns >= timer._last_ns  # type: ignore[attr-defined]
            ):
                return timer  # the common case: a valid entry, no backward jump
            if timer._canceled or timer.destroyed:
                heapq.heappop(heap)
            elif not clock._ros_time_active:  # type: ignore[attr-defined]
                # use_sim_time switched off behind the executor's back: reclassify.
                self._rebuild_schedule()
                heap = self._heap
            else:
                timer._check_jump(clock.now_ns())
                heapq.heapreplace(heap, (timer._next_ns, seq, timer))
        return None

    def _claim_due_timer(self) -> Timer | None:
        """Claim the timer to run next at the current time (due first, then creation order;
        its group claimed and the call marked), or None. Only the stepping thread calls
        this, so the heap needs no lock (node and timer changes from other threads only
        mark the schedule dirty)."""
        if self._schedule_dirty:
            self._rebuild_schedule()
        top = self._heap_top()
        best: Timer | None = None
        if top is not None and top._next_ns <= top.clock.now_ns():
            if top.callback_group.can_execute():
                best = top
            else:  # its group is busy (a re-entrant spin): the base executor's scan
                best = self._scan_timers(self._timers)
                # Whatever it picks may sit deeper in the heap: re-sort afterwards.
                self._schedule_dirty = True
        if self._zero_timers or self._other_timers:
            extra = self._scan_timers(self._zero_timers + self._other_timers)
            if extra is not None and (
                best is None or (extra._next_ns, extra.seq) < (best._next_ns, best.seq)
            ):
                best = extra
        if best is None or not best.callback_group.beginning_execution():
            return None
        best._mark_called()
        if best is top and not self._schedule_dirty:
            heapq.heapreplace(self._heap, (best._next_ns, best.seq, best))
        return best

    def _take_ready(self) -> tuple[int, Any, Any] | None:
        if self._tasks:
            return (_TASK, self._tasks.popleft(), None)
        timer = self._claim_due_timer()
        if timer is not None:
            return (_TIMER, timer, None)
        if not self._fifo:
            return None
        with self._lock:
            return self._take_message()

    def _next_timer_ns(self) -> int | None:
        """Sim time (ns) of the next timer call that moves time (None: no such timer)."""
        if self._schedule_dirty:
            self._rebuild_schedule()
        top = self._heap_top()
        best = None if top is None else max(top._next_ns, self._now_ns)
        if not self._other_timers:
            return best
        for timer in self._other_timers:
            if timer.is_canceled() or timer.destroyed:
                continue
            clock = timer.clock
            if not (isinstance(clock, ROSClock) and clock.ros_time_is_active):
                continue
            if timer.timer_period_ns == 0:
                continue  # runs once per step; it does not drive time
            timer.is_ready()  # applies backward-jump rescheduling
            due = max(timer.next_call_ns, self._now_ns)
            if best is None or due < best:
                best = due
        return best

    # -- running ----------------------------------------------------------------------
    def _run_ready(self) -> int:
        """Run every callback ready at the current sim time (the order of the module
        docstring: tasks, due timers, then messages in arrival order)."""
        count = 0
        context = self._context
        claim_timer = self._claim_due_timer
        while context._ok and not self._is_shutdown:
            if self._tasks:
                self._execute((_TASK, self._tasks.popleft(), None))
                count += 1
                continue
            timer = claim_timer()
            if timer is not None:
                # Executor._execute for a timer, inlined (the hot path of a stepped run).
                try:
                    result = timer.callback()
                    if result is not None and inspect.iscoroutine(result):
                        self._spawn_callback_task(result, _TIMER, timer)
                except Exception:
                    self._report(timer._node, "timer callback", traceback.format_exc())
                finally:
                    timer.callback_group.ending_execution()
                count += 1
                continue
            if not self._fifo:
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

    @_runs_callbacks
    def run_until(self, t: float | Time) -> int:
        """Advance simulated time to ``t`` (seconds or Time), running every callback due on
        the way in time order; returns the number of callbacks run."""
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

    @_runs_callbacks
    def spin_once(self, timeout_sec: float | None = None) -> None:
        """Run one ready callback; if none, jump to the next timer and run one there. With no
        timers at all, wait up to ``timeout_sec`` wall seconds for an outside message."""
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

    @_runs_callbacks
    def spin_until_future_complete(self, future: Future[Any], timeout_sec: float | None = None) -> None:
        """Step until ``future`` is done; ``timeout_sec`` counts *simulated* seconds."""
        future.add_done_callback(lambda _f: self.wake())
        end = None if timeout_sec is None or timeout_sec < 0 else self._now_ns + _to_ns(timeout_sec)
        while self._context.ok() and not self._is_shutdown and not future.done():
            if not self._run_ready():
                nxt = self._next_timer_ns()
                if nxt is None:
                    # Nothing moves sim time: wait for outside work, the future itself, or
                    # a new timer (a timer change marks the schedule dirty and wakes us).
                    work = self._wait_for_work(
                        None, lambda: future.done() or self._schedule_dirty
                    )
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
        result = super().shutdown(timeout_sec)
        if self._clock_node is not None and self._context.ok():
            self._clock_node.destroy_node()
        return result


# -- module-level rclpy functions ---------------------------------------------------------
_global_executors: dict[int, Executor] = {}


def get_global_executor(context: Context | None = None) -> Executor:
    """The SingleThreadedExecutor used by spin()/spin_once() without an executor."""
    ctx = context or get_default_context()
    executor = _global_executors.get(id(ctx))
    if executor is None or executor._context is not ctx or executor._is_shutdown:
        executor = SingleThreadedExecutor(context=ctx)
        _global_executors[id(ctx)] = executor
        key = id(ctx)

        def forget() -> None:
            _global_executors.pop(key, None)

        ctx.on_shutdown(forget)
    return executor


def spin_once(node: Node, *, executor: Executor | None = None,
              timeout_sec: float | None = None) -> None:
    """rclpy.spin_once: one callback of ``node`` (global executor unless given)."""
    executor = executor or get_global_executor(node.context)
    # The node stays in the executor afterwards (rclpy removes it; re-adding on every call
    # would re-scan its queues). A node belongs to one executor at a time either way.
    executor.add_node(node)
    executor.spin_once(timeout_sec=timeout_sec)


def spin(node: Node, executor: Executor | None = None) -> None:
    """rclpy.spin: run ``node``'s callbacks until shutdown."""
    executor = executor or get_global_executor(node.context)
    executor.add_node(node)
    try:
        executor.spin()
    finally:
        if node.executor is executor and executor is not None:
            executor.remove_node(node)


def spin_until_future_complete(
    node: Node,
    future: Future[Any],
    executor: Executor | None = None,
    timeout_sec: float | None = None,
) -> None:
    """rclpy.spin_until_future_complete."""
    executor = executor or get_global_executor(node.context)
    executor.add_node(node)
    executor.spin_until_future_complete(future, timeout_sec)
