"""Inbox and Handoff: the hand-off between a node's entities and its executor.

Oracles: FIFO order of the entries (what the executor's arrival-order delivery rests on,
rclpy's "messages in the order they arrived" across subscriptions); the no-lost-wake-up
protocol of a wait set (an item put after the waiter's last look still ends its wait,
before any timeout: rcl's guard condition semantics); and which inbox a node's items go to
after ``add_node`` / ``remove_node`` / moving to another executor (rclpy: a node belongs to
one executor at a time). Waits are bounded (LONG_S) and must end well before their bound.
"""

from __future__ import annotations

import threading
import time

import pytest

from posekit.msgs.std_msgs import String
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.inbox import Inbox
from posekit.runtime.node import Node

LONG_S = 30.0


def test_entries_come_out_in_put_order_and_put_back_keeps_it() -> None:
    inbox = Inbox()
    for seq in range(5):
        inbox.put(seq, f"e{seq}")
    assert len(inbox) == 5
    first, second = inbox.take(), inbox.take()
    assert (first, second) == ((0, "e0"), (1, "e1"))
    inbox.put_back([first, second])
    assert [inbox.take() for _ in range(5)] == [(i, f"e{i}") for i in range(5)]
    assert not inbox
    with pytest.raises(IndexError):
        inbox.take()


def test_put_after_prepare_wait_is_never_lost() -> None:
    inbox = Inbox()
    inbox.prepare_wait()  # the waiter announced itself, then looked (found nothing)
    inbox.put(1, "late")  # arrives between the look and the wait
    start = time.monotonic()
    assert inbox.wait(LONG_S) is True
    assert time.monotonic() - start < LONG_S / 2
    inbox.end_wait()


def test_put_without_a_waiter_does_not_signal() -> None:
    inbox = Inbox()
    inbox.prepare_wait()
    inbox.end_wait()
    inbox.prepare_wait()  # clears any earlier signal
    inbox.end_wait()
    inbox.put(1, "x")  # nobody waits: no signal (the hot path skips the lock)
    assert inbox.wait(0.0) is False
    inbox.wake()  # wake() always signals
    assert inbox.wait(0.0) is True


def test_always_wake_signals_every_put() -> None:
    inbox = Inbox(always_wake=True)
    inbox.prepare_wait()
    inbox.end_wait()  # stays "waiting": several workers may wait at any time
    inbox.prepare_wait()
    inbox.put(1, "x")
    assert inbox.wait(0.0) is True


def test_a_waiting_thread_is_woken_by_put() -> None:
    inbox = Inbox()
    inbox.prepare_wait()
    woke: list[bool] = []
    waiter = threading.Thread(target=lambda: woke.append(inbox.wait(LONG_S)))
    waiter.start()
    inbox.put(7, "msg")
    waiter.join(LONG_S)
    assert woke == [True]
    assert inbox.take() == (7, "msg")


def test_change_reports_reach_the_executor_hooks() -> None:
    seen: list[str] = []
    inbox = Inbox(on_timers_changed=lambda: seen.append("timers"),
                  on_entities_changed=lambda: seen.append("entities"))
    inbox.timers_changed()
    inbox.entities_changed()
    assert seen == ["timers", "entities"]
    Inbox().timers_changed()  # default hooks: nothing happens, nothing raises


def test_subscription_items_go_to_the_inbox_of_the_nodes_executor(ctx: Context) -> None:
    node = Node("talker", context=ctx)
    got: list[str] = []
    pub = node.create_publisher(String, "chat", 10)
    node.create_subscription(String, "chat", lambda m: got.append(m.data), 10)
    first, second = SingleThreadedExecutor(context=ctx), SingleThreadedExecutor(context=ctx)
    assert node.handoff.inbox is None
    pub.publish(String(data="q0"))  # queued before the node is in any executor
    assert first.add_node(node)
    assert node.handoff.executor is first
    assert node.handoff.inbox is first.inbox
    assert len(first.inbox) == 1  # add_node handed over the item queued before
    pub.publish(String(data="a"))
    assert (len(first.inbox), len(second.inbox)) == (2, 0)
    second.add_node(node)  # moves: one executor at a time
    assert node.executor is second
    assert first.get_nodes() == []
    assert len(second.inbox) == 2  # q0 and a, still queued in the subscription
    pub.publish(String(data="b"))
    assert (len(first.inbox), len(second.inbox)) == (2, 3)  # first keeps stale entries
    first.spin_once(timeout_sec=0.0)  # the moved node's items are not first's to run
    assert got == []
    second.spin_some()
    assert got == ["q0", "a", "b"]
    second.remove_node(node)
    assert node.handoff.inbox is None
    assert node.executor is None
