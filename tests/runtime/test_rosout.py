"""/rosout: every node's logger publishes rcl_interfaces/msg/Log.

Oracles: the real ROS 2 Jazzy rclpy (its /rosout publisher's QoS and its CDR bytes of a Log;
the records themselves are compared with rclpy's in tests/rclpy/differential/rosout.py), a
fresh rosbags Jazzy typestore for the CDR, and rcl's documented rosout QoS (KEEP_LAST 1000,
RELIABLE, TRANSIENT_LOCAL, lifespan 10 s).
"""

from __future__ import annotations

import time
from typing import Any

import pytest
from rosbags.typesys import Stores, get_typestore

from _support.ros2 import run_ros2_script
from posekit.msgs import to_cdr
from posekit.msgs.builtin_interfaces import Time
from posekit.msgs.rcl_interfaces import Log
from posekit.msgs.std_msgs import String
from posekit.runtime.bus import InProcessBus
from posekit.runtime.context import Context
from posekit.runtime.logging import LoggingSeverity, RcutilsLogger
from posekit.runtime.node import Node
from posekit.runtime.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from posekit.runtime.rosout import qos_profile_rosout_default
from posekit.runtime.sim_executor import SimulatedTimeExecutor
from posekit.runtime.transport import EndpointInfo, PublisherEndpoint
from posekit.time import Duration

LATCHED = QoSProfile(depth=100, durability=DurabilityPolicy.TRANSIENT_LOCAL)

@pytest.mark.slow
def test_rosout_qos_and_log_cdr_match_the_real_rclpy() -> None:
    result = run_ros2_script(
        """
        import rclpy
        from rclpy.node import Node
        from rclpy.serialization import serialize_message
        from rcl_interfaces.msg import Log
        from builtin_interfaces.msg import Time
        rclpy.init()
        node = Node("qos_probe")
        (info,) = node.get_publishers_info_by_topic("/rosout")
        q = info.qos_profile
        print(int(q.reliability), int(q.durability), q.lifespan.nanoseconds)
        msg = Log(stamp=Time(sec=12, nanosec=345), level=40, name="a.b", msg="héllo!",
                  file="/x/y.py", function="fun", line=77)
        print(serialize_message(msg).hex())  # strings sized so CDR needs no padding
        """,
        domain_id=132,
    )
    assert result.returncode == 0, result.stderr
    qos_line, cdr_hex = result.stdout.split()[:3], result.stdout.split()[3]
    rosout = qos_profile_rosout_default
    assert [int(v) for v in qos_line] == [
        int(rosout.reliability), int(rosout.durability), rosout.lifespan_ns
    ]
    assert rosout.depth == 1000  # rcl_qos_profile_rosout_default (Fast DDS reports 0)
    ours = Log(Time(12, 345), 40, "a.b", "héllo!", "/x/y.py", "fun", 77)
    assert to_cdr(ours).hex() == cdr_hex
    store = get_typestore(Stores.ROS2_JAZZY)
    ref_cls = store.types["rcl_interfaces/msg/Log"]
    time_cls = store.types["builtin_interfaces/msg/Time"]
    ref_msg = ref_cls(time_cls(12, 345), 40, "a.b", "héllo!", "/x/y.py", "fun", 77)
    assert bytes(store.serialize_cdr(ref_msg, ref_cls.__msgtype__)).hex() == cdr_hex


def test_rosout_profile_is_rcls() -> None:
    q = qos_profile_rosout_default
    assert (q.depth, q.reliability, q.durability) == (
        1000, ReliabilityPolicy.RELIABLE, DurabilityPolicy.TRANSIENT_LOCAL)
    assert q.lifespan_ns == 10_000_000_000


def _rosout(ctx: Context, node: Node) -> list[Log]:
    got: list[Log] = []
    node.create_subscription(Log, "/rosout", got.append, LATCHED)
    return got


class _Listener:
    """A node (without its own /rosout) collecting /rosout on a single-threaded executor."""

    def __init__(self, ctx: Context, transport: Any = None) -> None:
        from posekit.runtime.executors import SingleThreadedExecutor

        self.node = Node("listener", context=ctx, enable_rosout=False, transport=transport)
        self.executor = SingleThreadedExecutor(context=ctx)
        self.executor.add_node(self.node)
        self.got = _rosout(ctx, self.node)

    def messages(self) -> list[str]:
        self.executor.spin_some()
        return [m.msg for m in self.got]


def test_records_carry_the_node_clock_in_sim_time(ctx: Context) -> None:
    executor = SimulatedTimeExecutor(context=ctx, start_time=42.5, publish_clock=False)
    talker = Node("talker", context=ctx)
    listener = Node("listener", context=ctx)
    executor.add_node(talker)
    got = _rosout(ctx, listener)
    talker.create_timer(0.25, lambda: talker.get_logger().info("tick"))
    executor.add_node(listener)
    executor.run_for(0.5)
    ticks = [m for m in got if m.msg == "tick"]
    assert [(m.stamp.sec, m.stamp.nanosec) for m in ticks] == [(42, 750_000_000), (43, 0)]
    assert {m.name for m in ticks} == {"talker"}


def test_level_filter_throttle_and_enable_rosout_false(ctx: Context) -> None:
    talker = Node("talker", context=ctx)
    quiet = Node("quiet", context=ctx, enable_rosout=False)
    listener = _Listener(ctx)
    talker.get_logger().debug("filtered")
    for _ in range(3):
        talker.get_logger().info("once", once=True)
    quiet.get_logger().info("not published")
    talker.get_logger().set_level(LoggingSeverity.DEBUG)
    talker.get_logger().debug("now shown")
    assert listener.messages() == ["once", "now shown"]
    assert ctx.transport().count_publishers("/rosout") == 1  # talker's only


def test_destroyed_node_stops_publishing_and_frees_its_logger_names(ctx: Context) -> None:
    talker = Node("talker", context=ctx)
    child = talker.get_logger().get_child("part")
    listener = _Listener(ctx)
    child.info("before destroy")
    talker.destroy_node()
    child.info("after destroy")
    RcutilsLogger("talker").info("by name after destroy")
    assert listener.messages() == ["before destroy"]
    assert ctx.transport().count_publishers("/rosout") == 0


def test_late_subscription_gets_only_records_within_the_lifespan() -> None:
    bus = InProcessBus()
    logger = RcutilsLogger("test")
    lifespan = QoSProfile(depth=10, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                          lifespan=Duration(seconds=0.2))
    pub = bus.advertise(EndpointInfo("/t", String, lifespan, "n", "/", logger))
    pub.publish(String(data="old"))
    published = time.monotonic()
    while time.monotonic() - published <= 0.25:  # let "old" outlive its lifespan
        time.sleep(0.01)
    pub.publish(String(data="new"))
    got: list[Any] = []
    bus.subscribe(EndpointInfo("/t", String, LATCHED, "m", "/", logger), got.append)
    assert [m.data for m in got] == ["new"]
    # without a lifespan the history keeps both
    keep = bus.advertise(EndpointInfo("/u", String, LATCHED, "n", "/", logger))
    keep.publish(String(data="a"))
    keep.publish(String(data="b"))
    got.clear()
    bus.subscribe(EndpointInfo("/u", String, LATCHED, "m", "/", logger), got.append)
    assert [m.data for m in got] == ["a", "b"]


class _LoggingBus(InProcessBus):
    """A bus whose publishers log on the node's logger while publishing (as a network
    transport may, e.g. about a slow peer)."""

    def advertise(self, info: EndpointInfo) -> PublisherEndpoint:
        endpoint = super().advertise(info)
        inner = endpoint.publish_transfer

        def publish_transfer(msg: Any) -> None:
            info.logger.warning("transport says something")
            inner(msg)

        endpoint.publish_transfer = publish_transfer  # type: ignore[method-assign]
        return endpoint


def test_logging_inside_the_rosout_publish_does_not_recurse(ctx: Context, logs: list[Any]) -> None:
    bus = _LoggingBus()
    talker = Node("talker", context=ctx, transport=bus)
    listener = _Listener(ctx, transport=bus)
    talker.get_logger().info("hello")
    # printed: the line and the transport's warning; published: only the line
    assert listener.messages() == ["hello"]
    assert [r.message for r in logs] == ["hello", "transport says something"]
