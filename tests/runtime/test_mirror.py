"""MirroredTransport: in-process delivery plus visibility and traffic on a network transport,
over Zenoh and over DDS.

Oracles: the messages each subscription must receive, counted by sender (every local message
exactly once, never echoed back through the network; remote messages once; none on an owned
topic), the KEEP_LAST promise (the newest ``depth`` messages survive a stalled network), the
graph another session sees (the node names created here), and the isolated run of the same
scenario. A network endpoint that blocks forever stands in for a vanished subscriber:
publishing must still return.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from _support.dds import dds_domain
from _support.ports import free_port
from _support.world import use_zenoh_endpoint
from posekit.msgs.std_msgs import String
from posekit.runtime.bus import InProcessBus
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.mirror import MirroredTransport
from posekit.runtime.node import Node
from posekit.runtime.qos import QoSProfile
from posekit.runtime.transport import (
    EndpointInfo,
    MessageSink,
    PublisherEndpoint,
    SubscriptionEndpoint,
    Transport,
    UnknownTransportError,
    create_transport,
    register_transport,
)


class _StuckPublisher(PublisherEndpoint):
    """Stuck on ``/chatter``; other topics (a node's /parameter_events) have no remote
    subscriber."""

    def __init__(self, net: StuckNetwork, topic: str) -> None:
        self.net = net
        self.stuck = topic == "/chatter"

    def publish(self, msg: Any) -> None:
        if not self.stuck:
            return
        self.net.entered.set()
        self.net.release.wait()
        self.net.sent.append(msg.data)

    def destroy(self) -> None:
        pass

    @property
    def subscription_count(self) -> int:
        return 1 if self.stuck else 0  # a remote subscriber that never reads


class _NoSubscription(SubscriptionEndpoint):
    def destroy(self) -> None:
        pass

    @property
    def publisher_count(self) -> int:
        return 0


class StuckNetwork(Transport):
    """A network whose every send blocks until ``release`` is set."""

    name = "stuck"

    def __init__(self) -> None:
        self.entered = threading.Event()
        self.release = threading.Event()
        self.sent: list[str] = []
        self.remote_only: list[bool] = []

    def advertise(self, info: EndpointInfo) -> PublisherEndpoint:
        self.remote_only.append(info.remote_only)
        return _StuckPublisher(self, info.topic)

    def subscribe(self, info: EndpointInfo, sink: MessageSink) -> SubscriptionEndpoint:
        self.remote_only.append(info.remote_only)
        return _NoSubscription()

    def get_topic_names_and_types(self) -> list[tuple[str, list[str]]]:
        return []

    def count_publishers(self, topic: str) -> int:
        return 0

    def count_subscribers(self, topic: str) -> int:
        return 0


register_transport("test_stuck", StuckNetwork)


def test_transport_names_build_mirrors() -> None:
    mirror = create_transport("inprocess+test_stuck")
    try:
        assert isinstance(mirror, MirroredTransport)
        assert isinstance(mirror.local, InProcessBus)
        assert isinstance(mirror.network, StuckNetwork)
        assert mirror.name == "inprocess+stuck"
    finally:
        mirror.close()
    with pytest.raises(UnknownTransportError, match="no_such_net"):
        create_transport("inprocess+no_such_net")


def test_a_stuck_network_never_blocks_the_publisher_and_keeps_the_newest() -> None:
    ctx = Context()
    ctx.init(transport="inprocess+test_stuck")
    mirror = ctx.transport()
    assert isinstance(mirror, MirroredTransport)
    net = mirror.network
    assert isinstance(net, StuckNetwork)
    try:
        node = Node("talker", context=ctx)
        got: list[str] = []
        sub = Node("listener", context=ctx)
        sub.create_subscription(String, "/chatter", lambda m: got.append(m.data), 1000)
        pub = node.create_publisher(String, "/chatter", QoSProfile(depth=5))
        assert pub.get_subscription_count() == 2  # the local listener + the remote one
        assert all(net.remote_only)

        pub.publish(String(data="m0"))
        assert net.entered.wait(10), "the forwarder never sent"  # now stuck in m0's send

        def publish_rest() -> None:
            for i in range(1, 500):
                pub.publish(String(data=f"m{i}"))

        thread = threading.Thread(target=publish_rest, daemon=True)
        thread.start()
        thread.join(30)
        assert not thread.is_alive(), "publish() blocked on the stuck network"
        executor = SingleThreadedExecutor(context=ctx)
        executor.add_node(sub)
        executor.spin_some(0.5)
        assert got == [f"m{i}" for i in range(500)]  # local delivery untouched
        assert mirror.dropped["/chatter"] == 500 - 1 - 5
        net.release.set()
        assert mirror.flush(10)
        deadline = time.monotonic() + 10
        while len(net.sent) < 6 and time.monotonic() < deadline:
            time.sleep(0.01)
        assert net.sent == ["m0", *(f"m{i}" for i in range(495, 500))]  # KEEP_LAST 5
    finally:
        net.release.set()
        ctx.shutdown()


def test_destroying_a_publisher_waits_for_its_send_and_ends_its_lane() -> None:
    """A forwarding thread left inside the network library when the interpreter exits is
    killed there (zenoh aborts the process on that): destroy() waits for the send under way
    and the lane thread ends."""
    ctx = Context()
    ctx.init(transport="inprocess+test_stuck")
    mirror = ctx.transport()
    assert isinstance(mirror, MirroredTransport)
    net = mirror.network
    assert isinstance(net, StuckNetwork)
    try:
        node = Node("talker", context=ctx)
        pub = node.create_publisher(String, "/chatter", 10)
        pub.publish(String(data="m0"))
        assert net.entered.wait(10), "the forwarder never sent"
        lanes = [t for t in threading.enumerate() if t.name == "posekit-mirror-out /chatter"]
        assert len(lanes) == 1
        threading.Timer(0.2, net.release.set).start()
        node.destroy_publisher(pub)
        assert net.sent == ["m0"], "destroy returned before the send under way finished"
        lanes[0].join(5)
        assert not lanes[0].is_alive(), "the destroyed publisher's lane is still running"
    finally:
        net.release.set()
        ctx.shutdown()


# -- over real Zenoh sessions -------------------------------------------------------------


@pytest.fixture
def router(monkeypatch: pytest.MonkeyPatch) -> str:
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    use_zenoh_endpoint(monkeypatch, endpoint)
    return endpoint


@pytest.fixture(params=["zenoh", "dds"])
def contexts(request: pytest.FixtureRequest,
             monkeypatch: pytest.MonkeyPatch) -> Iterator[tuple[Context, Context]]:
    """A mirrored context and a plain one ("another process": its own session or DDS
    participant) on the network transport ``request.param``."""
    network = request.param
    if network == "zenoh":
        use_zenoh_endpoint(monkeypatch, f"tcp/127.0.0.1:{free_port()}")
    else:
        pytest.importorskip("cyclonedds")
        dds_domain(monkeypatch, 171)
    mirrored, remote = Context(), Context()
    mirrored.init(transport=f"inprocess+{network}")
    remote.init(transport=network)
    try:
        yield mirrored, remote
    finally:
        remote.shutdown()
        mirrored.shutdown()


def spin_until(executors: list[SingleThreadedExecutor], cond: Callable[[], bool],
               timeout: float, what: str) -> None:
    deadline = time.monotonic() + timeout
    while not cond():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        for executor in executors:
            executor.spin_some(0.02)


@pytest.mark.slow
def test_mirrored_nodes_are_seen_and_reached_without_echo(
    contexts: tuple[Context, Context],
) -> None:
    mirrored, remote = contexts
    assert isinstance(mirrored.transport(), MirroredTransport)
    here_pub, here_sub = Node("here_talker", context=mirrored), Node("here_listener",
                                                                     context=mirrored)
    there = Node("there", context=remote)
    here: list[str] = []
    away: list[str] = []
    here_sub.create_subscription(String, "/chatter", lambda m: here.append(m.data), 100)
    there.create_subscription(String, "/chatter", lambda m: away.append(m.data), 100)
    pub_here = here_pub.create_publisher(String, "/chatter", 100)
    pub_there = there.create_publisher(String, "/chatter", 100)
    ex_here, ex_there = SingleThreadedExecutor(context=mirrored), SingleThreadedExecutor(
        context=remote)
    ex_here.add_node(here_pub)
    ex_here.add_node(here_sub)
    ex_there.add_node(there)

    graph = remote.transport()
    spin_until([ex_here, ex_there],
               lambda: {"/here_talker", "/here_listener"} <= set(graph.get_node_names()),
               20, "the mirrored nodes on the remote graph")
    spin_until([ex_here, ex_there], lambda: pub_here.get_subscription_count() == 2, 20,
               "the remote subscription to be noticed")
    spin_until([ex_here, ex_there], lambda: pub_there.get_subscription_count() >= 2, 20,
               "the remote side to see both subscriptions")
    for i in range(20):
        pub_here.publish(String(data=f"here{i}"))
        pub_there.publish(String(data=f"there{i}"))
    spin_until([ex_here, ex_there], lambda: len(here) >= 40 and len(away) >= 40, 20,
               "every message")
    ex_here.spin_some(0.3)
    ex_there.spin_some(0.3)
    # Local messages exactly once (none echoed back), remote ones once, in order per sender.
    assert [m for m in here if m.startswith("here")] == [f"here{i}" for i in range(20)]
    assert [m for m in here if m.startswith("there")] == [f"there{i}" for i in range(20)]
    assert [m for m in away if m.startswith("here")] == [f"here{i}" for i in range(20)]
    assert [m for m in away if m.startswith("there")] == [f"there{i}" for i in range(20)]


@pytest.mark.slow
def test_an_owned_topic_is_never_taken_from_other_processes(
    contexts: tuple[Context, Context],
) -> None:
    mirrored, remote = contexts
    transport = mirrored.transport()
    assert isinstance(transport, MirroredTransport)
    transport.own_topic("/owned")
    owner, outsider = Node("owner", context=mirrored), Node("outsider", context=remote)
    got: list[str] = []
    control: list[str] = []
    owner.create_subscription(String, "/owned", lambda m: got.append(m.data), 10)
    owner.create_subscription(String, "/control", lambda m: control.append(m.data), 10)
    local_pub = owner.create_publisher(String, "/owned", 10)
    stray = outsider.create_publisher(String, "/owned", 10)
    control_pub = outsider.create_publisher(String, "/control", 10)
    ex_here, ex_there = SingleThreadedExecutor(context=mirrored), SingleThreadedExecutor(
        context=remote)
    ex_here.add_node(owner)
    ex_there.add_node(outsider)
    # The same path on a topic the owner does not own works: the outsider reaches it.
    spin_until([ex_here, ex_there], lambda: control_pub.get_subscription_count() == 1, 20,
               "the owner's /control subscription")
    for i in range(5):
        stray.publish(String(data=f"stray{i}"))
        local_pub.publish(String(data=f"own{i}"))
    control_pub.publish(String(data="after the strays"))
    spin_until([ex_here], lambda: len(got) >= 5 and control == ["after the strays"], 10,
               "the local messages and the control message")
    ex_here.spin_some(0.5)
    assert got == [f"own{i}" for i in range(5)]
    assert stray.get_subscription_count() == 0  # nobody here subscribes to it remotely


@pytest.mark.slow
def test_a_mirrored_scenario_runs_exactly_as_the_isolated_one(router: str) -> None:
    """Oracle: the isolated run of the same scenario and seed, message for message."""
    import numpy as np

    from posekit.robot.scenarios import run_robot_scenario

    runs = [run_robot_scenario("p_controller", {}, seed=2, until_sim_time=8.0, transport=t,
                         publish_clock=t != "inprocess")
            for t in ("inprocess", "inprocess+zenoh")]
    isolated, mirrored = (r.recording for r in runs)
    assert isolated is not None
    assert mirrored is not None
    assert set(isolated.series) == set(mirrored.series)
    assert {"ground_truth", "filtered"} <= set(isolated.series), set(isolated.series)
    for name, rows in isolated.series.items():
        assert len(rows) > 100, name
        np.testing.assert_array_equal(rows, mirrored.series[name], err_msg=name)
