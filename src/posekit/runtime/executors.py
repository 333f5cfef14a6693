"""Executors: who calls the callbacks, in which order, in which thread.

* :class:`SingleThreadedExecutor`: one thread runs timers, subscription callbacks and tasks
  one at a time. Ready tasks first, then ready timers (earliest due first, then creation
  order), then queued messages in arrival order across all subscriptions (context-wide
  sequence numbers).
* :class:`MultiThreadedExecutor`: the same selection, ``num_threads`` workers; callbacks of a
  MutuallyExclusiveCallbackGroup (the node default) never overlap.
* The stepped :class:`~posekit.runtime.sim_executor.SimulatedTimeExecutor`, which owns
  simulated time, is built on the same base (:mod:`posekit.runtime.sim_executor`).

How work reaches an executor: a node's subscriptions, service servers and clients put an
entry in the executor's :class:`~posekit.runtime.inbox.Inbox` when they queue an item (the
node's :class:`~posekit.runtime.inbox.Handoff` says which inbox); which timer is due is the
executor's :class:`~posekit.runtime.timer_schedule.TimerSchedule`; every callback is run by
one method (:meth:`Executor._call`), which also turns a coroutine result into a task and
reports an exception. The loop that drains queued messages (``_drain_messages``, one pass
per message) runs the same steps inlined, the hot-path policy of docs/architecture.md.

An exception raised by a callback is logged by the callback's node logger with the traceback
(``[ERROR] [...] [node]: Exception in timer callback ...``) and does not stop the executor
or other callbacks. ``KeyboardInterrupt``/``SystemExit`` still propagate.

Executors are context managers, as in rclpy: ``with SingleThreadedExecutor() as executor:``
calls :meth:`Executor.shutdown` on leaving the block.
"""

from __future__ import annotations

import functools
import inspect
import os
import threading
import time
import traceback
from collections import deque
from collections.abc import Callable, Coroutine
from types import TracebackType
from typing import Any, Self, TypeVar, cast

from posekit.runtime.context import Context, get_default_context
from posekit.runtime.inbox import Inbox
from posekit.runtime.node import Node
from posekit.runtime.services import current_executor, set_current_executor
from posekit.runtime.task import Future, Task
from posekit.runtime.timer_schedule import TimerSchedule

__all__ = [
    "Executor",
    "ExternalShutdownException",
    "Future",
    "MultiThreadedExecutor",
    "SingleThreadedExecutor",
    "Task",
    "get_global_executor",
    "spin",
    "spin_once",
    "spin_until_future_complete",
]

# Kinds of work: (kind, entity, payload) as taken by _take_ready and run by _execute.
_TIMER = 0
_MESSAGE = 1
_TASK = 2

_F = TypeVar("_F", bound=Callable[..., Any])

#: ``payload`` of :meth:`Executor._call` for a callback taking no argument (a timer's).
_NO_PAYLOAD: Any = object()


def runs_callbacks(method: _F) -> _F:
    """Decorator for an executor's spinning methods.

    Marks the calling thread as running this executor's callbacks for the call's duration (what
    ``Client.call`` checks to serve a request instead of deadlocking), and counts it among the
    threads :meth:`Executor.shutdown` waits for.
    """

    @functools.wraps(method)
    def wrapper(self: Executor, *args: Any, **kwargs: Any) -> Any:
        if current_executor() is self:  # nested (spin -> spin_once): already marked
            return method(self, *args, **kwargs)
        previous = set_current_executor(self)
        running = self._running
        with running:
            self._threads_running += 1
        try:
            return method(self, *args, **kwargs)
        finally:
            with running:
                self._threads_running -= 1
                running.notify_all()
            set_current_executor(previous)

    return cast(_F, wrapper)


class ExternalShutdownException(Exception):  # noqa: N818 - rclpy name
    """The context was shut down while spinning (rclpy.executors.ExternalShutdownException)."""


class Executor:
    """Base executor (see the module docstring for the callback order)."""

    #: Every inbox ``put`` wakes a waiting thread (several may wait: multi-threaded).
    _wake_on_every_put = False
    #: Take samples from subscriptions whose transport allows it on the spinning thread
    #: (:meth:`SubscriptionEndpoint.pull_into`), instead of having the transport's thread
    #: queue them: one thread waits, as rclpy's executor on the middleware's wait set.
    _pulls_samples = False
    #: Samples taken from one pulled source per look (fairness with timers and tasks).
    _PULL_BUDGET = 64
    #: Queued messages run back to back at most (see :meth:`_execute_and_drain`).
    _MESSAGE_BATCH = 64

    def __init__(self, *, context: Context | None = None) -> None:
        self._context = context or get_default_context()
        self._nodes: list[Node] = []
        self._tasks: deque[Task] = deque()
        self._lock = threading.RLock()
        self._is_shutdown = False
        #: Threads inside a spinning method (spin, spin_once, a worker...), and its condition.
        self._threads_running = 0
        self._running = threading.Condition(threading.Lock())
        self._schedule = self._make_schedule()
        #: Where this executor's nodes hand their queued work (see posekit.runtime.inbox).
        self.inbox = Inbox(
            always_wake=self._wake_on_every_put,
            on_timers_changed=self._timers_changed,
            on_entities_changed=self._entities_changed,
        )
        #: Number of callbacks that raised (each was logged).
        self.callback_exceptions = 0
        #: Endpoints whose samples this executor pulls (see ``_pulls_samples``).
        self._pulled: dict[Any, Any] = {}  # endpoint -> its subscription
        self._context.on_shutdown(self.wake)  # spin returns when the context shuts down

    def _make_schedule(self) -> TimerSchedule:
        return TimerSchedule()

    @property
    def context(self) -> Context:
        """The context whose shutdown stops this executor."""
        return self._context

    def __enter__(self) -> Self:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.shutdown()

    # -- nodes ------------------------------------------------------------------------
    def add_node(self, node: Node) -> bool:
        """Add ``node``; False if it is already here. A node has at most one executor."""
        with self._lock:
            if node in self._nodes:
                return False
            handoff = node.handoff
            if handoff.executor is not None:
                handoff.executor.remove_node(node)
            self._nodes.append(node)
            handoff.connect(self, self.inbox)
            # Items queued while the node was in no executor, in arrival order.
            pending = sorted(
                ((seq, entity) for entity in handoff.queued_entities()
                 for seq, _ in list(entity.queue)),
                key=lambda item: item[0],
            )
            self.inbox.extend(pending)
            self._rebuild_timers()
            self._sync_pulled()
        self.wake()
        return True

    def remove_node(self, node: Node) -> None:
        """Remove ``node`` (its queued messages stay queued in its subscriptions)."""
        with self._lock:
            if node in self._nodes:
                self._nodes.remove(node)
                node.handoff.disconnect()
                self._rebuild_timers()
                self._sync_pulled()
        self.wake()

    def get_nodes(self) -> list[Node]:
        """Nodes in this executor."""
        return list(self._nodes)

    def _entities_changed(self) -> None:
        """Inbox report: a node's timers/subscriptions/servers changed (any thread)."""
        with self._lock:
            self._rebuild_timers()
            self._sync_pulled()
        self.wake()

    def _sync_pulled(self) -> None:
        """Pull exactly the live subscriptions of this executor's nodes that allow it.

        Others go back to their transport's own thread. The caller holds the lock.
        """
        if not self._pulls_samples and not self._pulled:
            return
        wanted = {}
        if self._pulls_samples and not self._is_shutdown:
            wanted = {sub.endpoint: sub for node in self._nodes for sub in node.subscriptions
                      if not sub.destroyed and sub.endpoint is not None}
        for endpoint in [e for e in self._pulled if e not in wanted]:
            del self._pulled[endpoint]
            endpoint.release_pull(self.inbox)
        for endpoint, sub in wanted.items():
            if endpoint not in self._pulled and endpoint.pull_into(self.inbox):
                self._pulled[endpoint] = sub

    def _timers_changed(self) -> None:
        """Inbox report: a timer was cancelled, reset or re-periodised (any thread)."""
        self._schedule.invalidate()
        self.wake()

    def _rebuild_timers(self) -> None:
        """Hand every timer of the nodes to the schedule (caller holds the lock)."""
        self._schedule.set_timers([t for node in self._nodes for t in node.timers])

    def wake(self) -> None:
        """Interrupt a wait (new work, shutdown)."""
        self.inbox.wake()

    # -- tasks ------------------------------------------------------------------------
    def _schedule_task(self, task: Task) -> None:
        self._tasks.append(task)
        self.wake()

    def create_task(self, callback: Callable[..., Any] | Coroutine[Any, Any, Any],
                    *args: Any, **kwargs: Any) -> Task:
        """Run ``callback`` on this executor; the returned Task is a Future of its result.

        ``callback`` is a coroutine, a coroutine function or a plain callable.
        """
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
            return self._take_task_or_timer() or self._take_message()

    def _take_task_or_timer(self) -> tuple[int, Any, Any] | None:
        """Claim a ready task, else the due timer (its group claimed), else None."""
        if self._tasks:
            return (_TASK, self._tasks.popleft(), None)
        timer = self._schedule.claim_due()
        if timer is not None:
            return (_TIMER, timer, None)
        return None

    def _take_message(self) -> tuple[int, Any, Any] | None:
        """Claim the oldest queued item whose group is free (caller holds the lock)."""
        inbox = self.inbox
        take = inbox.take
        skipped: list[tuple[int, Any]] = []
        found: tuple[int, Any, Any] | None = None
        while True:
            try:
                entry = take()
            except IndexError:
                break
            seq, entity = entry
            queue = entity.queue
            if entity.destroyed or not queue or queue[0][0] > seq or (
                entity.handoff.executor is not self
            ):
                continue  # stale: delivered, dropped by KEEP_LAST, or moved away
            if not entity.callback_group.beginning_execution():
                skipped.append(entry)
                continue
            _, payload = queue.popleft()
            found = (_MESSAGE, entity, payload)
            break
        if skipped:
            inbox.put_back(skipped)
        return found

    def _drain_messages(self, budget: int, until: float | None = None) -> int:
        """Deliver up to ``budget`` queued items in arrival order; returns how many ran.

        The hot path: it runs each callback as :meth:`_call` does, inlined, and claims no
        timer. So it stops before the next item once a task is ready, the timers changed, or
        ``time.monotonic()`` reached ``until`` (when a timer comes due): the order stays
        that of one callback per look (tasks, timers, messages). Shutdown removes the nodes,
        which makes the rest stale.
        """
        inbox = self.inbox
        take = inbox.take
        iscoroutine = inspect.iscoroutine
        schedule = self._schedule
        tasks = self._tasks
        monotonic = time.monotonic
        done = 0
        while done < budget:
            if tasks or schedule.changed or (until is not None and monotonic() >= until):
                break
            try:
                seq, entity = take()
            except IndexError:  # empty (or another worker emptied it)
                break
            queue = entity.queue
            if not queue or queue[0][0] != seq or entity.destroyed or (
                entity.handoff.executor is not self
            ):
                continue  # stale: dropped by KEEP_LAST, destroyed, or moved away
            group = entity.callback_group
            if not group.beginning_execution():
                inbox.put_back([(seq, entity)])
                break
            # :meth:`_call` inlined (one Python frame less per message; the reference stays
            # _call, and tests/runtime/test_executors.py runs both on the same callbacks)
            try:
                result = entity.callback(queue.popleft()[1])
                if result is not None and iscoroutine(result):
                    self._spawn_callback_task(result, entity)
            except Exception:
                self._report(entity, traceback.format_exc())
            finally:
                group.ending_execution()
            done += 1
        return done

    # -- running ----------------------------------------------------------------------
    def _call(self, entity: Any, payload: Any = _NO_PAYLOAD) -> None:
        """Run ``entity.callback`` (with ``payload``, if given) in its claimed callback group.

        The caller claimed the group. The one place that turns a coroutine result into a task,
        reports an exception and releases the group.
        """
        try:
            result = entity.callback() if payload is _NO_PAYLOAD else entity.callback(payload)
            if result is not None and inspect.iscoroutine(result):
                self._spawn_callback_task(result, entity)
        except Exception:
            self._report(entity, traceback.format_exc())
        finally:
            entity.callback_group.ending_execution()

    def _execute(self, work: tuple[int, Any, Any]) -> None:
        kind, entity, payload = work
        if kind == _TASK:
            entity.step()
        elif kind == _MESSAGE:
            self._call(entity, payload)
        else:
            self._call(entity)

    def _execute_and_drain(self, work: tuple[int, Any, Any]) -> None:
        """Run ``work``; after a message, the messages queued behind it until a timer is due.

        As rclpy runs every callback one wait found ready before waiting again, but never
        past a timer coming due (the wall-clock window of the schedule) or a ready task:
        a look per message cost about 15 % more CPU per Zenoh ``tf`` message
        (docs/performance.md).
        """
        kind, entity, payload = work
        if kind != _MESSAGE:
            self._execute(work)
            return
        self._call(entity, payload)
        if not len(self.inbox) or self._tasks:
            return
        window = self._schedule.quiet_wall_s()
        if window is None:
            self._drain_messages(self._MESSAGE_BATCH)
        elif window > 0:
            self._drain_messages(self._MESSAGE_BATCH, time.monotonic() + window)

    def _spawn_callback_task(self, coro: Coroutine[Any, Any, Any], entity: Any) -> None:
        """Run a coroutine callback's coroutine as a task; its exception is reported."""
        task = Task(coro, self._schedule_task)

        def report(future: Future[Any]) -> None:
            exc = future.exception()
            if exc is not None:
                tb = "".join(traceback.format_exception(type(exc), exc, exc.__traceback__))
                self._report(entity, tb)

        task.add_done_callback(report)
        self._schedule_task(task)

    def _report(self, entity: Any, tb: str) -> None:
        self.callback_exceptions += 1
        entity.handoff.node.get_logger().error(
            f"Exception in {entity.callback_description}:\n{tb.rstrip()}"
        )

    def _wait_for_work(
        self, timeout_sec: float | None, condition: Callable[[], bool] | None = None
    ) -> tuple[int, Any, Any] | None:
        """The next ready callback, waiting up to ``timeout_sec`` (None: forever).

        None on timeout, shutdown, or once ``condition()`` is true (rclpy's wait condition:
        whoever makes it true must call :meth:`wake`, e.g. a future's done-callback).
        """
        deadline = None
        if timeout_sec is not None and timeout_sec >= 0:
            deadline = time.monotonic() + timeout_sec
        inbox = self.inbox
        if (self._tasks or len(inbox)) and not self._is_shutdown and self._context.ok():
            # hot path: work is already queued, so the wake-up need not be armed
            work = self._take_ready()
            if work is not None:
                return work
        try:
            while self._context.ok() and not self._is_shutdown:
                if inbox.sources:
                    # Outside the announced wait (end_wait), so the samples this thread
                    # queues do not signal it. One arriving after this pull still ends the
                    # wait: a DDS read condition stays raised while samples wait in the
                    # reader, and a Zenoh hand-over is looked at (sources_pending) below.
                    inbox.end_wait()
                    if inbox.pull_sources(self._PULL_BUDGET):
                        work = self._take_ready()  # found: no need to arm the wait
                        if work is not None:
                            return work
                # Order matters: announce waiting, then look for work (Inbox.prepare_wait).
                # A shutdown that woke this thread before the announcement cleared the
                # wake-up is part of that look: its flag is set before it wakes.
                inbox.prepare_wait()
                if self._is_shutdown or not self._context.ok() or (
                    condition is not None and condition()
                ):
                    return None
                work = self._take_ready()
                if work is not None:
                    return work
                if inbox.sources and inbox.sources_pending():
                    continue  # handed over between the pull and prepare_wait
                wait = self._schedule.wall_wait_s()
                if deadline is not None:
                    remaining = deadline - time.monotonic()
                    if remaining <= 0:
                        return None
                    wait = remaining if wait is None else min(wait, remaining)
                inbox.wait(wait)
            return None
        finally:
            inbox.end_wait()

    @runs_callbacks
    def serve_until_future_complete(
        self, future: Future[Any], timeout_sec: float | None = None
    ) -> None:
        """Run ready callbacks until ``future`` is done or ``timeout_sec`` wall seconds passed.

        posekit's, not rclpy API: what ``Client.call`` does inside one of this executor's
        callbacks. Unlike :meth:`spin_until_future_complete` it never moves simulated time
        (a :class:`~posekit.runtime.sim_executor.SimulatedTimeExecutor` steps only where it
        spins). It waits as ``spin_once`` does: a response queued for this executor, or the
        future completed on another thread, ends the wait at once.
        """
        future.add_done_callback(lambda _f: self.wake())
        end = None if timeout_sec is None or timeout_sec < 0 else time.monotonic() + timeout_sec
        while not future.done() and self._context.ok() and not self._is_shutdown:
            remaining = None
            if end is not None:
                remaining = end - time.monotonic()
                if remaining <= 0:
                    return
            self._spin_once_until(remaining, future)

    def _run_once(self, timeout_sec: float | None = None) -> None:
        """Wait up to ``timeout_sec`` (None: forever) for one callback and run it."""
        work = self._wait_for_work(timeout_sec)
        if work is not None:
            self._execute(work)

    spin_once = runs_callbacks(_run_once)
    spin_once.__name__, spin_once.__qualname__ = "spin_once", "Executor.spin_once"

    @runs_callbacks
    def spin(self) -> None:
        """Run callbacks until the context shuts down or shutdown() is called."""
        if type(self).spin_once is not Executor.spin_once:
            while self._context.ok() and not self._is_shutdown:
                self.spin_once()  # a subclass's own (rclpy's spin calls spin_once)
            return
        while self._context.ok() and not self._is_shutdown:
            work = self._wait_for_work(None)
            if work is not None:
                self._execute_and_drain(work)

    @runs_callbacks
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
            self._execute_and_drain(work)

    def _spin_once_until(self, timeout_sec: float | None, future: Future[Any]) -> None:
        """spin_once that also returns when ``future`` completes (in any thread)."""
        work = self._wait_for_work(timeout_sec, future.done)
        if work is not None:
            self._execute(work)

    @runs_callbacks
    def spin_until_future_complete(
        self, future: Future[Any], timeout_sec: float | None = None
    ) -> None:
        """Spin until ``future`` is done or ``timeout_sec`` (wall seconds) passed.

        A future completed by another thread ends the wait at once (its done-callback wakes us).
        """
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
        """Stop spinning, drop the nodes and wait for the callbacks running now to finish.

        As rclpy: waits up to ``timeout_sec`` s (None or negative: until they finish) for every
        thread spinning this executor to return (each returns once its current callback
        does); True when they all did, False on timeout. Called from one of this executor's
        own callbacks, it does not wait for that callback. A node destroyed after this
        returned True is never in use by a callback of this executor.
        """
        self._is_shutdown = True
        for node in list(self._nodes):
            self.remove_node(node)
        with self._lock:
            self._sync_pulled()
        self.wake()
        own = 1 if current_executor() is self else 0
        timeout = None if timeout_sec is None or timeout_sec < 0 else timeout_sec
        with self._running:
            return self._running.wait_for(lambda: self._threads_running <= own, timeout)


class SingleThreadedExecutor(Executor):
    """Runs callbacks one at a time in the spinning thread.

    Subscriptions on a transport that allows it (DDS) are read by the spinning thread
    itself, which then waits on the middleware's wait set (see ``_pulls_samples``).
    """

    _pulls_samples = True


class MultiThreadedExecutor(Executor):
    """``num_threads`` worker threads (default: CPU count, at least 2) run callbacks.

    Callback groups decide what may overlap. ``spin_once`` runs in the calling thread.
    """

    _wake_on_every_put = True

    def __init__(self, num_threads: int | None = None, *, context: Context | None = None) -> None:
        super().__init__(context=context)
        self._num_threads = num_threads or max(2, os.cpu_count() or 2)
        if self._num_threads < 1:
            raise ValueError("num_threads must be >= 1")

    @property
    def num_threads(self) -> int:
        """How many workers spin() starts."""
        return self._num_threads

    @runs_callbacks
    def _worker(self) -> None:
        while self._context.ok() and not self._is_shutdown:
            work = self._wait_for_work(0.05)
            if work is not None:
                self._execute(work)
                self.wake()  # a group was released: another worker may now proceed

    def spin(self) -> None:
        """Run callbacks on the worker threads and this one until shutdown."""
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


# -- module-level rclpy functions ---------------------------------------------------------
_global_executors: dict[int, Executor] = {}


def get_global_executor(context: Context | None = None) -> Executor:
    """The SingleThreadedExecutor used by spin()/spin_once() without an executor."""
    ctx = context or get_default_context()
    executor = _global_executors.get(id(ctx))
    if executor is None or executor.context is not ctx or executor._is_shutdown:
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
