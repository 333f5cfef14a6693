"""QoS profiles: rclpy defaults, int shorthand, validation, offer/request matching."""

from __future__ import annotations

import itertools

import pytest

from posekit.runtime.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    QoSCompatibility,
    QoSProfile,
    ReliabilityPolicy,
    check_qos_compatibility,
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
    result = check_qos_compatibility(
        QoSProfile(depth=1, reliability=pub_rel, durability=pub_dur),
        QoSProfile(depth=1, reliability=sub_rel, durability=sub_dur),
    )
    assert (result == QoSCompatibility.OK) == expected_ok
