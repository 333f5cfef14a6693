"""Transport selection (node option, init option, POSEKIT_TRANSPORT), the registry, and the
contract's declared optional capabilities.

Oracle for the capabilities: the module docstring of :mod:`posekit.runtime.transport` (what a
transport that cannot tell returns) and the nodes and publishers created in the test."""

from __future__ import annotations

import subprocess
import sys

import pytest

from posekit.msgs.geometry_msgs import Twist
from posekit.runtime.bus import InProcessBus
from posekit.runtime.context import Context
from posekit.runtime.node import Node
from posekit.runtime.qos import QoSProfile
from posekit.runtime.transport import (
    ENV_TRANSPORT,
    EndpointInfo,
    MessageSink,
    PublisherEndpoint,
    SubscriptionEndpoint,
    Transport,
    UnknownTransportError,
    register_transport,
    selected_transport_name,
)


class RecordingBus(InProcessBus):
    """A distinguishable transport: the in-process bus under another name."""

    name = "recording"


register_transport("recording", RecordingBus)


def test_default_is_inprocess_and_shared_per_context(ctx, monkeypatch) -> None:
    monkeypatch.delenv(ENV_TRANSPORT, raising=False)
    a, b = Node("a", context=ctx), Node("b", context=ctx)
    assert type(a.transport) is InProcessBus
    assert a.transport is b.transport
    other = Context()
    other.init()
    try:
        assert Node("c", context=other).transport is not a.transport  # contexts are isolated
    finally:
        other.shutdown()


def test_env_and_options_select(monkeypatch) -> None:
    monkeypatch.setenv(ENV_TRANSPORT, "recording")
    assert selected_transport_name() == "recording"
    assert selected_transport_name("inprocess") == "inprocess"
    context = Context()
    context.init()
    try:
        assert type(Node("a", context=context).transport) is RecordingBus
        assert type(Node("b", context=context, transport="inprocess").transport) is InProcessBus
    finally:
        context.shutdown()
    monkeypatch.delenv(ENV_TRANSPORT)
    context = Context()
    context.init(transport="recording")
    try:
        assert type(Node("a", context=context).transport) is RecordingBus
    finally:
        context.shutdown()


def test_unknown_transport_is_a_clear_error(ctx, monkeypatch) -> None:
    monkeypatch.setenv(ENV_TRANSPORT, "carrier_pigeon")
    with pytest.raises(UnknownTransportError, match=r"carrier_pigeon.*known:.*inprocess"):
        Node("a", context=ctx)


@pytest.mark.parametrize(("name", "library"), [("zenoh", "zenoh"), ("dds", "cyclonedds")])
def test_a_missing_network_library_names_the_extra(name: str, library: str) -> None:
    # A fresh interpreter where the library cannot be imported (None in sys.modules makes
    # Python refuse the import, as if it were not installed).
    code = (f"import sys; sys.modules[{library!r}] = None\n"
            "from posekit.runtime.transport import UnknownTransportError, create_transport\n"
            f"try:\n    create_transport({name!r})\n"
            "except UnknownTransportError as exc:\n    print(exc)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=60, check=True).stdout
    assert f"transport '{name}' is not available" in out, out
    assert f"pip install 'posekit[{name}]'" in out, out


class _TopicsOnly(Transport):
    """The least a transport implements: the abstract methods only."""

    name = "topics_only"

    def advertise(self, info: EndpointInfo) -> PublisherEndpoint:
        raise NotImplementedError

    def subscribe(self, info: EndpointInfo, sink: MessageSink) -> SubscriptionEndpoint:
        raise NotImplementedError

    def get_topic_names_and_types(self) -> list[tuple[str, list[str]]]:
        return []

    def count_publishers(self, topic: str) -> int:
        return 0

    def count_subscribers(self, topic: str) -> int:
        return 0


def test_optional_capabilities_have_declared_defaults() -> None:
    t = _TopicsOnly()
    assert t.crosses_processes is False
    assert t.supports_services is False
    assert t.publisher_qos_profiles("/x") is None
    assert t.get_node_names() == []
    assert t.get_publishers_info_by_topic("/x") == []
    assert t.get_subscriptions_info_by_topic("/x") == []
    assert t.graph_entities() == []
    assert t.sync_graph(0.0) == 0
    assert t.graph_description() == "the topics_only graph"
    assert t.own_topic("/clock") is None


def test_in_process_bus_answers_the_graph_questions(ctx) -> None:
    a = Node("talker", namespace="/robot", context=ctx)
    Node("talker", namespace="/robot", context=ctx)  # a duplicate name stays listed twice
    a.create_publisher(Twist, "cmd_vel", QoSProfile(depth=3))
    bus = a.transport
    assert bus.get_node_names() == ["/robot/talker", "/robot/talker"]
    assert [p.depth for p in bus.publisher_qos_profiles("/robot/cmd_vel") or []] == [3]
    assert bus.sync_graph(1.0) == 0  # nothing to wait for in one process


def test_endpoint_type_name_for_ros_and_plain_classes(ctx) -> None:
    node = Node("n", context=ctx)

    class Plain:
        pass

    def info(msg_type: type) -> EndpointInfo:
        return EndpointInfo("/t", msg_type, QoSProfile(depth=1), "n", "/", node.get_logger())

    assert info(Twist).type_name == "geometry_msgs/msg/Twist"
    assert info(Plain).type_name == f"{__name__}.{Plain.__qualname__}"
