"""The passive "observe every topic" engine (posekit.runtime.observe.TopicObserver).

Oracles: rosbag2 Jazzy's adaptive QoS rule, stated here independently of the code (request
RELIABLE only if every publisher offers it, TRANSIENT_LOCAL only if every publisher offers
it); the messages each publisher actually delivers to the observer (a request that does not
match a publisher receives nothing from it, so delivery proves the match); the latched
sample a transient-local publisher sent before the observer existed; the graph (the
observer's subscription leaves it when the publishers are gone, and after ``close``); the
QoS each publisher was created with, compared with what a Zenoh or DDS session in another
context reads from the graph.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

from _support.network import network_contexts
from _support.waiting import wait_for
from posekit.msgs.std_msgs import Float64, String
from posekit.runtime.context import Context
from posekit.runtime.node import Node
from posekit.runtime.observe import ObservedTopic, TopicObserver, TopicSkipped, observing_qos
from posekit.runtime.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    QoSProfile,
    ReliabilityPolicy,
    qos_profile_sensor_data,
)

LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)


class Log:
    """Collects what an observer hands its owner."""

    def __init__(self) -> None:
        self.received: dict[str, list[Any]] = {}
        self.started: list[ObservedTopic] = []
        self.removed: list[str] = []
        self.skipped: list[tuple[str, str]] = []

    def sink_for(self, topic: ObservedTopic) -> Any:
        self.started.append(topic)
        if topic.name == "/refused":
            raise TopicSkipped("the owner does not want it")
        box = self.received.setdefault(topic.name, [])
        return box.append

    def observer(self, ctx: Context, **options: Any) -> TopicObserver:
        return TopicObserver(ctx.transport(), self.sink_for, on_removed=self.removed.append,
                             on_skipped=lambda t, r: self.skipped.append((t, r)), **options)

    def data(self, topic: str) -> list[Any]:
        return [m.data for m in self.received.get(topic, [])]


def test_the_request_follows_rosbag2s_rule() -> None:
    reliable, best_effort = QoSProfile(depth=10), qos_profile_sensor_data
    cases = [
        ([reliable], ReliabilityPolicy.RELIABLE, DurabilityPolicy.VOLATILE),
        ([LATCHED], ReliabilityPolicy.RELIABLE, DurabilityPolicy.TRANSIENT_LOCAL),
        ([LATCHED, reliable], ReliabilityPolicy.RELIABLE, DurabilityPolicy.VOLATILE),
        ([reliable, best_effort], ReliabilityPolicy.BEST_EFFORT, DurabilityPolicy.VOLATILE),
        ([], ReliabilityPolicy.RELIABLE, DurabilityPolicy.VOLATILE),
    ]
    for offered, reliability, durability in cases:
        qos = observing_qos(offered, depth=None)
        assert (qos.reliability, qos.durability) == (reliability, durability), offered
        assert qos.history == HistoryPolicy.KEEP_ALL
    assert observing_qos([LATCHED], depth=1).depth >= 100  # every latched sample fits


def test_latched_best_effort_and_mixed_topics_are_all_received(ctx: Context) -> None:
    node = Node("talkers", context=ctx)
    static = node.create_publisher(String, "/tf_like_static", LATCHED)
    static.publish(String(data="latched before the observer existed"))
    sensor = node.create_publisher(Float64, "/sensor", qos_profile_sensor_data)
    mixed_reliable = node.create_publisher(String, "/mixed", 10)
    mixed_best_effort = node.create_publisher(String, "/mixed", qos_profile_sensor_data)
    log = Log()
    observer = log.observer(ctx, depth=None)
    observer.refresh()
    qos = {t.name: t.qos for t in log.started}
    assert qos["/tf_like_static"].durability == DurabilityPolicy.TRANSIENT_LOCAL
    assert qos["/sensor"].reliability == ReliabilityPolicy.BEST_EFFORT
    assert qos["/mixed"].reliability == ReliabilityPolicy.BEST_EFFORT
    assert qos["/mixed"].durability == DurabilityPolicy.VOLATILE
    assert len(next(t for t in log.started if t.name == "/mixed").offered) == 2
    sensor.publish(Float64(data=7.0))
    mixed_reliable.publish(String(data="r"))
    mixed_best_effort.publish(String(data="b"))
    assert log.data("/tf_like_static") == ["latched before the observer existed"]
    assert log.data("/sensor") == [7.0]
    assert log.data("/mixed") == ["r", "b"]
    observer.close()


def test_a_best_effort_publisher_joining_makes_the_observer_subscribe_again(
    ctx: Context,
) -> None:
    node = Node("talkers", context=ctx)
    reliable = node.create_publisher(String, "/words", 10)
    log = Log()
    observer = log.observer(ctx)
    observer.refresh()
    assert observer.topics()["/words"].qos.reliability == ReliabilityPolicy.RELIABLE
    late = Node("late", context=ctx).create_publisher(String, "/words", qos_profile_sensor_data)
    late.publish(String(data="lost: the reliable request does not match it"))
    observer.refresh()
    assert observer.topics()["/words"].qos.reliability == ReliabilityPolicy.BEST_EFFORT
    late.publish(String(data="late"))
    reliable.publish(String(data="first"))
    assert log.data("/words") == ["late", "first"]
    assert [t.name for t in log.started].count("/words") == 1  # the owner's sink is kept
    assert ctx.transport().count_subscribers("/words") == 1
    observer.close()


def test_topics_that_leave_are_let_go_and_come_back_afresh(ctx: Context) -> None:
    node = Node("talkers", context=ctx)
    pub = node.create_publisher(String, "/comes_and_goes", 10)
    log = Log()
    observer = log.observer(ctx, grace_refreshes=2)
    observer.refresh()
    transport = ctx.transport()
    assert transport.count_subscribers("/comes_and_goes") == 1
    node.destroy_publisher(pub)
    observer.refresh()
    assert log.removed == []  # one refresh without publishers: still within the grace
    observer.refresh()
    assert log.removed == ["/comes_and_goes"]
    assert "/comes_and_goes" not in observer.topics()
    assert transport.count_subscribers("/comes_and_goes") == 0
    assert "/comes_and_goes" not in dict(transport.get_topic_names_and_types())
    back = node.create_publisher(Float64, "/comes_and_goes", LATCHED)  # another type, latched
    back.publish(Float64(data=3.0))
    observer.refresh()
    again = observer.topics()["/comes_and_goes"]
    assert again.type_name == "std_msgs/msg/Float64"
    assert again.qos.durability == DurabilityPolicy.TRANSIENT_LOCAL
    assert log.received["/comes_and_goes"][-1].data == 3.0
    observer.close()


def test_selection_limits_unknown_types_and_refusals(ctx: Context) -> None:
    node = Node("talkers", context=ctx)
    for name in ("/a", "/b", "/c", "/important", "/refused", "/_hidden"):
        node.create_publisher(String, name, 10)
    node.create_subscription(String, "/only_subscribed", lambda m: None, 10)
    log = Log()
    observer = log.observer(ctx, max_topics=3, priority=["/important"],
                            select=lambda topic, type_name: not topic.startswith("/_"))
    observer.refresh()
    observed = set(observer.topics())
    assert "/important" in observed
    assert len(observed) == 3
    assert "/_hidden" not in observed
    assert "/only_subscribed" not in observed
    assert "/refused" not in observed
    skipped = observer.skipped
    assert any("at most 3" in reason for reason in skipped.values())
    started_before = len(log.started)
    observer.refresh()  # skipped topics are not retried while their type stays
    assert len(log.started) == started_before
    assert {name for name, _ in observer.graph()} >= {"/a", "/only_subscribed", "/_hidden"}


def test_unknown_types_are_skipped_with_the_reason(ctx: Context) -> None:
    node = Node("talkers", context=ctx)
    node.create_publisher(String, "/text", 10)

    def resolve(type_name: str) -> type:
        raise LookupError(f"no class for {type_name}")

    log = Log()
    observer = log.observer(ctx, resolve=resolve)
    assert observer.refresh() == []
    text = [entry for entry in log.skipped if entry[0] == "/text"]
    assert text == [("/text", "no class for std_msgs/msg/String")]
    assert observer.skipped["/text"] == "no class for std_msgs/msg/String"
    said = len(log.skipped)
    assert observer.refresh() == []
    assert len(log.skipped) == said


def test_skip_warnings_are_one_per_topic_and_a_flood_of_names_is_rate_limited(
        ctx: Context, capfd: pytest.CaptureFixture[str]) -> None:
    # 300 topics of a type nobody can resolve: the names are the publishers' choice. The
    # observer's own warning (no on_skipped owner) names each of the first topics once; past
    # the rate limiter's table of reasons the rest share one line a second.
    node = Node("talkers", context=ctx)
    for i in range(300):
        node.create_publisher(String, f"/flood_{i}", 10)

    def resolve(type_name: str) -> type:
        raise LookupError(f"no class for {type_name}")

    observer = TopicObserver(ctx.transport(), lambda topic: lambda msg: None, resolve=resolve)
    capfd.readouterr()
    observer.refresh()
    assert len(observer.skipped) >= 300  # every topic was considered and refused
    lines = [line for line in capfd.readouterr().err.splitlines() if "not observing" in line]
    assert any(line.endswith("not observing '/flood_0': no class for std_msgs/msg/String")
               for line in lines), lines[:3]
    assert len(set(lines)) == len(lines)  # no topic twice
    assert 10 <= len(lines) <= 64 + 1, len(lines)


def test_close_tears_down_every_subscription(ctx: Context) -> None:
    node = Node("talkers", context=ctx)
    pub = node.create_publisher(String, "/words", 10)
    log = Log()
    with log.observer(ctx) as observer:
        observer.refresh()
        pub.publish(String(data="one"))
    assert observer.closed
    pub.publish(String(data="two"))
    assert log.data("/words") == ["one"]
    assert ctx.transport().count_subscribers("/words") == 0
    assert observer.refresh() == []
    observer.close()  # idempotent


# -- across contexts: the QoS a network graph reports ---------------------------------------


@pytest.fixture(params=["zenoh", "dds"])
def network(request: pytest.FixtureRequest,
            monkeypatch: pytest.MonkeyPatch) -> Iterator[tuple[Context, Context]]:
    """Two contexts on the network transport ``request.param``: a publisher and an observer
    (as two processes would be)."""
    with network_contexts(request.param, monkeypatch) as contexts:
        yield contexts


@pytest.mark.slow
def test_over_the_network_the_offers_are_read_from_the_graph(
    network: tuple[Context, Context],
) -> None:
    talker, watcher = network
    node = Node("net_talker", context=talker)
    static = node.create_publisher(String, "/net_static", LATCHED)
    static.publish(String(data="latched"))
    sensor = node.create_publisher(Float64, "/net_sensor", qos_profile_sensor_data)
    transport = watcher.transport()
    assert wait_for(lambda: transport.count_publishers("/net_static") == 1
                    and transport.count_publishers("/net_sensor") == 1, 15.0)
    offers = transport.publisher_qos_profiles("/net_sensor")
    assert offers is not None
    assert len(offers) == 1
    assert offers[0].reliability == ReliabilityPolicy.BEST_EFFORT
    assert offers[0].durability == DurabilityPolicy.VOLATILE
    latched_offer = (transport.publisher_qos_profiles("/net_static") or [QoSProfile()])[0]
    assert latched_offer.durability == DurabilityPolicy.TRANSIENT_LOCAL
    log = Log()
    observer = log.observer(watcher, node_name="net_observer")
    observer.refresh()
    assert observer.topics()["/net_sensor"].qos.reliability == ReliabilityPolicy.BEST_EFFORT
    assert observer.topics()["/net_static"].qos.durability == DurabilityPolicy.TRANSIENT_LOCAL
    assert wait_for(lambda: log.data("/net_static") == ["latched"], 15.0), log.received

    def published_and_received() -> bool:
        sensor.publish(Float64(data=5.0))
        return bool(log.data("/net_sensor"))

    assert wait_for(published_and_received, 15.0, interval=0.1)
    assert set(log.data("/net_sensor")) == {5.0}
    observer.close()
