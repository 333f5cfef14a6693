"""Node.create_rate / Rate.sleep and rclpy.wait_for_message.

Oracles: the rate's own period (the k-th sleep cannot end before k periods) and the
messages the test publishes. The behaviour is compared with the real rclpy's in
tests/rclpy/differential/rate_wait.py (errors after destroy and on shutdown, timeouts,
latched delivery, clean-up).
"""

from __future__ import annotations

import itertools
import threading
import time

import pytest

from posekit.msgs.std_msgs import String
from posekit.runtime.context import Context
from posekit.runtime.executors import MultiThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.rate import ROSInterruptException
from posekit.runtime.wait_for_message import wait_for_message


def test_rate_follows_the_node_clock_of_a_spinning_executor(ctx: Context) -> None:
    node = Node("rates", context=ctx)
    executor = MultiThreadedExecutor(context=ctx)
    executor.add_node(node)
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    start = node.get_clock().now().nanoseconds
    rate = node.create_rate(100)
    stamps = []
    for _ in range(4):
        rate.sleep()
        stamps.append(node.get_clock().now().nanoseconds)
    # every sleep waits for a new tick of the 10 ms timer (late ticks may be skipped, none
    # is used twice): the k-th sleep ends at least k periods after the rate was created
    assert all(b >= a for a, b in itertools.pairwise(stamps))
    assert all(t - start >= k * 10_000_000 for k, t in enumerate(stamps, 1))
    ctx.shutdown()
    thread.join(5)
    assert not thread.is_alive()
    with pytest.raises(ROSInterruptException):
        rate.sleep()


def test_wait_for_message_gets_a_message_published_later_by_another_thread(
    ctx: Context,
) -> None:
    node = Node("waiter", context=ctx)
    pub = node.create_publisher(String, "chat", 10)

    def publish_when_subscribed() -> None:
        deadline = time.monotonic() + 5
        while pub.get_subscription_count() == 0 and time.monotonic() < deadline:
            time.sleep(0.005)
        pub.publish(String(data="hi"))

    threading.Thread(target=publish_when_subscribed, daemon=True).start()
    assert wait_for_message(String, node, "chat", time_to_wait=5) == (True, String(data="hi"))
    assert pub.get_subscription_count() == 0  # the temporary subscription is gone


def test_wait_for_message_returns_on_shutdown(ctx: Context) -> None:
    node = Node("waiter", context=ctx)
    threading.Timer(0.2, ctx.shutdown).start()
    start = time.monotonic()
    assert wait_for_message(String, node, "never", time_to_wait=30) == (False, None)
    assert time.monotonic() - start < 25  # ended by the shutdown, not the timeout
