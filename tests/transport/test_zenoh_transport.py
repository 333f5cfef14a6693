"""ZenohTransport behind the runtime's Node API (two contexts = two independent sessions)."""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator

import pytest

from _support.ports import free_port
from posekit.msgs.geometry_msgs import TransformStamped, Twist
from posekit.msgs.std_msgs import String
from posekit.msgs.tf2_msgs import TFMessage
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node, NodeNameNonExistentError
from posekit.runtime.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from posekit.runtime.transport import create_transport
from posekit.transport.zenoh_session import SessionOptions
from posekit.transport.zenoh_transport import ZenohTransport, options_from_env, wire_qos
from posekit.transport.zenoh_wire import WireQoS

pytestmark = pytest.mark.slow  # real processes, sessions or a browser

STATIC = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)




@pytest.fixture
def two_sides(monkeypatch: pytest.MonkeyPatch) -> Iterator[tuple[Context, Context, SessionOptions]]:
    for var in ("ZENOH_SESSION_CONFIG_URI", "ZENOH_CONFIG_OVERRIDE", "ROS_DOMAIN_ID"):
        monkeypatch.delenv(var, raising=False)
    options = SessionOptions(router_endpoint=f"tcp/127.0.0.1:{free_port()}")
    a, b = Context(), Context()
    a.init()
    b.init()
    yield a, b, options
    b.try_shutdown()
    a.try_shutdown()


def spin_until(
    executor: SingleThreadedExecutor, cond: Callable[[], bool], timeout: float = 5
) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if cond():
            return True
        executor.spin_once(timeout_sec=0.02)
    return cond()


def test_qos_mapping() -> None:
    assert wire_qos(QoSProfile(depth=100)) == WireQoS(depth=100)
    assert wire_qos(STATIC) == WireQoS(durability=1, depth=1)
    assert wire_qos(QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT)) == WireQoS(
        reliability=2, depth=5
    )


def test_registry_name_resolves_to_zenoh_transport(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("POSEKIT_ZENOH_ROUTER", f"tcp/127.0.0.1:{free_port()}")
    monkeypatch.setenv("POSEKIT_ZENOH_ATTACHMENT", "legacy")
    assert options_from_env().legacy_attachment
    transport = create_transport("zenoh")
    try:
        assert isinstance(transport, ZenohTransport)
        assert transport.session.hosts_router
        assert transport.session.options.legacy_attachment
    finally:
        transport.close()
    monkeypatch.setenv("POSEKIT_ZENOH_ATTACHMENT", "weird")
    with pytest.raises(ValueError, match="POSEKIT_ZENOH_ATTACHMENT"):
        options_from_env()


def test_nodes_exchange_messages_and_late_static(
    two_sides: tuple[Context, Context, SessionOptions],
) -> None:
    ctx_a, ctx_b, options = two_sides
    ta, tb = ZenohTransport(options), ZenohTransport(options)
    ctx_a.on_shutdown(ta.close)
    ctx_b.on_shutdown(tb.close)
    talker = Node("talker", context=ctx_a, transport=ta)
    pub = talker.create_publisher(String, "chatter", 10)
    static_pub = talker.create_publisher(TFMessage, "/tf_static", STATIC)
    static_pub.publish(TFMessage([TransformStamped(child_frame_id="laser")]))

    listener = Node("listener", namespace="/robot1", context=ctx_b, transport=tb)
    got: list[str] = []
    statics: list[TFMessage] = []
    listener.create_subscription(String, "/chatter", lambda m: got.append(m.data), 10)
    listener.create_subscription(TFMessage, "/tf_static", statics.append, STATIC)
    executor = SingleThreadedExecutor(context=ctx_b)
    executor.add_node(listener)
    assert spin_until(executor, lambda: bool(statics))
    assert statics[0].transforms[0].child_frame_id == "laser"
    assert spin_until(executor, lambda: bool(got) or (pub.publish(String(data="hello")) and False))
    assert got[0] == "hello"
    # graph across processes, own entities visible at once
    assert tb.count_subscribers("/chatter") == 1
    assert spin_until(executor, lambda: tb.count_publishers("/chatter") == 1)
    assert ("/chatter", ["std_msgs/msg/String"]) in tb.get_topic_names_and_types()
    assert spin_until(executor, lambda: "/talker" in tb.get_node_names())
    assert "/robot1/listener" in tb.get_node_names()
    # by node, from the other session's liveliness tokens (rosout and parameter events too)
    assert dict(listener.get_publisher_names_and_types_by_node("talker", "/")) == {
        "/chatter": ["std_msgs/msg/String"], "/tf_static": ["tf2_msgs/msg/TFMessage"],
        "/rosout": ["rcl_interfaces/msg/Log"],
        "/parameter_events": ["rcl_interfaces/msg/ParameterEvent"]}
    assert spin_until(executor, lambda: "/robot1/listener" in ta.get_node_names() and (
        talker.get_subscriber_names_and_types_by_node("listener", "/robot1") == [
            ("/chatter", ["std_msgs/msg/String"]), ("/tf_static", ["tf2_msgs/msg/TFMessage"])]))
    with pytest.raises(NodeNameNonExistentError):
        talker.get_subscriber_names_and_types_by_node("listener", "/")
    with pytest.raises(TypeError, match="expects String"):
        pub.publish(Twist())
    talker.destroy_publisher(pub)
    assert spin_until(executor, lambda: tb.count_publishers("/chatter") == 0)


def test_same_process_delivery_copies(two_sides: tuple[Context, Context, SessionOptions]) -> None:
    ctx_a, _, options = two_sides
    transport = ZenohTransport(options)
    ctx_a.on_shutdown(transport.close)
    node = Node("solo", context=ctx_a, transport=transport)
    received: list[TFMessage] = []
    node.create_subscription(TFMessage, "/tf", received.append, 100)
    pub = node.create_publisher(TFMessage, "/tf", 100)
    assert pub.get_subscription_count() == 1
    executor = SingleThreadedExecutor(context=ctx_a)
    executor.add_node(node)
    msg = TFMessage([TransformStamped(child_frame_id="a")])
    assert spin_until(executor, lambda: bool(received) or (pub.publish(msg) and False))
    assert received[0] == msg
    assert received[0] is not msg
