"""Node.create_rate / Rate.sleep and rclpy.wait_for_message.

Oracle: the real ROS 2 Jazzy rclpy — the same script (rates in a multithreaded executor,
errors after destroy and on shutdown, wait_for_message's timeout, latched delivery and
clean-up) prints the same lines under both.
"""

from __future__ import annotations

import itertools
import threading
import time

import pytest

from _support.differential import run_both
from posekit.msgs.std_msgs import String
from posekit.runtime.context import Context
from posekit.runtime.executors import MultiThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.rate import ROSInterruptException
from posekit.runtime.wait_for_message import wait_for_message

RATE_SCRIPT = """
import threading, time
import rclpy
from rclpy.node import Node
from rclpy.executors import MultiThreadedExecutor
rclpy.init()
node = Node("rates")
try:
    node.create_rate(0)
except Exception as e:
    print(type(e).__name__, e)
executor = MultiThreadedExecutor()
executor.add_node(node)
threading.Thread(target=executor.spin, daemon=True).start()
rate = node.create_rate(50)
start = time.monotonic()
for _ in range(5):
    rate.sleep()
print("five sleeps take at least four periods:", time.monotonic() - start >= 0.08)
print(node.destroy_rate(rate))
try:
    rate.sleep()
except Exception as e:
    print(type(e).__name__, e)
slow = node.create_rate(5)
threading.Timer(0.3, rclpy.shutdown).start()
try:
    while True:
        slow.sleep()
except Exception as e:
    print(type(e).__name__, e)
"""

WAIT_SCRIPT = """
import rclpy
from rclpy.node import Node
from rclpy.qos import QoSProfile, DurabilityPolicy
from rclpy.wait_for_message import wait_for_message
from std_msgs.msg import String
rclpy.init()
node = Node("waiter")
print(wait_for_message(String, node, "nobody", time_to_wait=0.3))
latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
pub = node.create_publisher(String, "latched", latched)
pub.publish(String(data="kept"))
ok, msg = wait_for_message(String, node, "latched", qos_profile=latched, time_to_wait=10)
print(ok, msg.data)
print(node.count_subscribers("latched"), len(list(node.subscriptions)))
"""


@pytest.mark.slow
def test_rate_behaves_like_the_real_rclpy() -> None:
    ref, ours = run_both(RATE_SCRIPT, domain_id=133)
    assert ours == ref
    assert ref.splitlines() == [
        "ValueError frequency must be > 0",
        "five sleeps take at least four periods: True",
        "True",
        "RuntimeError Rate cannot sleep because it has been destroyed",
        "ROSInterruptException rclpy.shutdown() has been called",
    ]


@pytest.mark.slow
def test_wait_for_message_behaves_like_the_real_rclpy() -> None:
    ref, ours = run_both(WAIT_SCRIPT, domain_id=134)
    assert ours == ref
    assert ref.splitlines() == ["(False, None)", "True kept", "0 0"]


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
