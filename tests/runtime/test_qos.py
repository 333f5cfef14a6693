"""QoS profiles: rclpy defaults, int shorthand, validation, offer/request matching."""

from __future__ import annotations

import itertools

import pytest

from posekit.runtime.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    OfferMatch,
    QoSProfile,
    ReliabilityPolicy,
    match_offer,
    qos_profile_sensor_data,
    to_qos_profile,
)


def test_int_shorthand_is_keep_last_reliable_volatile() -> None:
    q = to_qos_profile(7)
    assert (q.history, q.depth, q.reliability, q.durability) == (
        HistoryPolicy.KEEP_LAST, 7, ReliabilityPolicy.RELIABLE, DurabilityPolicy.VOLATILE
    )


def test_sensor_data_profile_matches_rclpy() -> None:
    # rclpy/qos.py: qos_profile_sensor_data = KEEP_LAST 5, BEST_EFFORT, VOLATILE
    assert qos_profile_sensor_data.depth == 5
    assert qos_profile_sensor_data.reliability == ReliabilityPolicy.BEST_EFFORT
    assert qos_profile_sensor_data.durability == DurabilityPolicy.VOLATILE


@pytest.mark.parametrize("bad", [True, 1.5, "10", None])
def test_bad_qos_argument_is_type_error(bad: object) -> None:
    with pytest.raises(TypeError):
        to_qos_profile(bad)  # type: ignore[arg-type]


def test_keep_last_needs_positive_depth() -> None:
    with pytest.raises(ValueError, match="depth"):
        QoSProfile(depth=0)
    with pytest.raises(ValueError, match="depth"):
        QoSProfile(depth=-1)
    assert QoSProfile(history=HistoryPolicy.KEEP_ALL, depth=0).queue_limit is None


@pytest.mark.parametrize(
    ("pub_rel", "pub_dur", "sub_rel", "sub_dur"),
    list(itertools.product(
        [ReliabilityPolicy.RELIABLE, ReliabilityPolicy.BEST_EFFORT],
        [DurabilityPolicy.VOLATILE, DurabilityPolicy.TRANSIENT_LOCAL],
        [ReliabilityPolicy.RELIABLE, ReliabilityPolicy.BEST_EFFORT],
        [DurabilityPolicy.VOLATILE, DurabilityPolicy.TRANSIENT_LOCAL],
    )),
)
def test_compatibility_matrix(pub_rel, pub_dur, sub_rel, sub_dur) -> None:
    # DDS request/offer: an offer must be at least as strong as the request.
    strength = {ReliabilityPolicy.BEST_EFFORT: 0, ReliabilityPolicy.RELIABLE: 1,
                DurabilityPolicy.VOLATILE: 0, DurabilityPolicy.TRANSIENT_LOCAL: 1}
    expected_ok = strength[pub_rel] >= strength[sub_rel] and strength[pub_dur] >= strength[sub_dur]
    result = match_offer(
        QoSProfile(depth=1, reliability=pub_rel, durability=pub_dur),
        QoSProfile(depth=1, reliability=sub_rel, durability=sub_dur),
    )
    assert (result == OfferMatch.OK) == expected_ok


def test_a_changed_profile_leaves_existing_endpoints_alone(ctx) -> None:
    # rclpy hands rcl a copy: changing the profile (or a shared preset) afterwards changes
    # what later endpoints get, never the queue or history of one that exists.
    from posekit.msgs.std_msgs import String
    from posekit.runtime.executors import SingleThreadedExecutor
    from posekit.runtime.node import Node

    node = Node("snapshot", context=ctx)
    profile = QoSProfile(depth=5)
    got: list[str] = []
    sub = node.create_subscription(String, "t", lambda m: got.append(m.data), profile)
    latched = QoSProfile(depth=3, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    pub_latched = node.create_publisher(String, "l", latched)
    profile.depth = 1
    latched.depth = 1
    latched.durability = DurabilityPolicy.VOLATILE
    assert sub.qos_profile is profile  # rclpy's attribute is the caller's object
    pub = node.create_publisher(String, "t", 10)
    for i in range(5):
        pub.publish(String(data=str(i)))
        pub_latched.publish(String(data=str(i)))
    late: list[str] = []
    node.create_subscription(String, "l", lambda m: late.append(m.data),
                             QoSProfile(depth=3, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(node)
    ex.spin_some()
    assert got == ["0", "1", "2", "3", "4"]  # depth 5, not 1
    assert late == ["2", "3", "4"]  # still TRANSIENT_LOCAL with 3 kept


def test_profiles_are_mutable_unhashable_values() -> None:
    q = QoSProfile(depth=5)
    q.depth = 3
    q.reliability = 2  # an int is taken as the policy, as rclpy
    assert q.reliability is ReliabilityPolicy.BEST_EFFORT
    assert q == QoSProfile(depth=3, reliability=ReliabilityPolicy.BEST_EFFORT)
    with pytest.raises(TypeError):
        hash(q)
    with pytest.raises(TypeError, match="depth"):
        q.depth = "3"  # type: ignore[assignment]
    with pytest.raises(ValueError, match="depth"):
        q.depth = 0
    # a KEEP_ALL profile may have depth 0; with_ sets history before depth whatever the order
    assert q.with_(depth=0, history=HistoryPolicy.KEEP_ALL).queue_limit is None


def test_system_default_depth_0_is_the_middlewares_default() -> None:
    from posekit.runtime.qos import SYSTEM_DEFAULT_DEPTH, qos_profile_system_default

    assert qos_profile_system_default.depth == 0  # as rclpy prints it
    assert qos_profile_system_default.queue_limit == SYSTEM_DEFAULT_DEPTH
