"""TimeCache and StaticCache rules (docs/specs/tf2.md sections 3 and 4), values checked by hand."""

from __future__ import annotations

import math

import pytest

from posekit.tf2 import (
    BackwardExtrapolationException,
    ExtrapolationException,
    ForwardExtrapolationException,
    NoDataForExtrapolationException,
)
from posekit.tf2.static_cache import StaticCache
from posekit.tf2.time_cache import TimeCache, display_time

S = 1_000_000_000


def tx(x: float) -> tuple[float, ...]:
    """Identity rotation, translation (x, 0, 0)."""
    return (0.0, 0.0, 0.0, 1.0, float(x), 0.0, 0.0)


def filled(*stamps_values: tuple[float, float], parent: int = 1) -> TimeCache:
    c = TimeCache(10 * S)
    for sec, x in stamps_values:
        assert c.insert(round(sec * S), parent, tx(x))  # type: ignore[arg-type]
    return c


def x_at(c: TimeCache, sec: float) -> float:
    return c.get(round(sec * S))[1][4]


def test_duplicate_stamp_model_from_spec() -> None:
    # d@1.0 = 1 then 2, d@1.5 = 7 then 8, d@2.0 = 5
    c = filled((1.0, 1), (1.0, 2), (1.5, 7), (1.5, 8), (2.0, 5))
    assert x_at(c, 1.0) == 1  # exact hit on the oldest stamp: first inserted
    assert x_at(c, 1.5) == 8  # middle stamp: newest insert wins
    assert x_at(c, 1.25) == 4.5  # mid(2, 7): older bracket newest, newer bracket earliest
    assert x_at(c, 2.0) == 5
    assert c.get(0)[1][4] == 5


def test_newest_insert_wins_at_latest() -> None:
    c = filled((1.0, 1), (2.0, 3), (2.0, 4))
    assert x_at(c, 2.0) == 4
    assert c.get(0)[1][4] == 4
    assert len(c) == 3


def test_exact_duplicate_is_accepted_but_not_stored() -> None:
    c = filled((1.0, 1), (2.0, 3))
    assert c.insert(2 * S, 1, tx(3))  # type: ignore[arg-type]
    assert len(c) == 2
    assert c.insert(2 * S, 2, tx(3))  # different parent is a different sample
    assert len(c) == 3


def test_out_of_order_inserts_sort() -> None:
    c = filled((3.0, 30), (1.0, 10), (2.0, 20))
    assert c.stamps == [S, 2 * S, 3 * S]
    assert x_at(c, 1.5) == pytest.approx(15)


def test_prune_before_insert_against_old_newest() -> None:
    # samples 0..11 s, cache 10 s; inserting 12 prunes against 11 -> keeps 1..12 (ROS 2)
    c = filled(*[(float(i), float(i)) for i in range(12)])
    assert c.oldest_stamp() == 0  # inserting 11 pruned against 10: 0 + 10 < 10 is false
    c.insert(12 * S, 1, tx(12))  # type: ignore[arg-type]
    assert c.oldest_stamp() == 1 * S
    assert x_at(c, 1.5) == pytest.approx(1.5)


def test_old_data_boundary_is_inclusive() -> None:
    c = filled((20.0, 0))
    assert c.insert(10 * S, 1, tx(1))  # type: ignore[arg-type]  # exactly cache_time older
    assert not c.insert(10 * S - 1, 1, tx(1))  # type: ignore[arg-type]  # 1 ns more: refused


def test_pruning_is_strict() -> None:
    c = filled((0.0, 0), (10.0, 10))
    c.insert(10 * S, 1, tx(11))  # type: ignore[arg-type]  # 0 + 10 < 10 is false: 0 stays
    assert c.oldest_stamp() == 0
    c.insert(10 * S + 1, 1, tx(12))  # type: ignore[arg-type]  # prune vs 10 s: still not older
    assert c.oldest_stamp() == 0
    c.insert(11 * S, 1, tx(13))  # type: ignore[arg-type]  # prune vs 10 s + 1 ns: 0 goes
    assert c.oldest_stamp() == 10 * S


def test_empty_cache_is_no_data_with_empty_text() -> None:
    with pytest.raises(NoDataForExtrapolationException) as e:
        TimeCache().get(S)
    assert str(e.value) == ""
    with pytest.raises(NoDataForExtrapolationException):
        TimeCache().get(0)


def test_single_sample_answers_only_its_stamp_or_latest() -> None:
    c = filled((1.0, 5))
    assert x_at(c, 1.0) == 5
    assert c.get(0)[1][4] == 5
    with pytest.raises(NoDataForExtrapolationException) as e:
        c.get(S + 1)
    assert str(e.value) == (
        "Lookup would require extrapolation at time 1.000000, "
        "but only time 1.000000 is in the buffer"
    )


def test_forward_and_backward_texts_two_spaces() -> None:
    c = filled((1.0, 0), (3.0, 0))
    with pytest.raises(ForwardExtrapolationException) as f:
        c.get(3 * S + 500_000_000)
    assert str(f.value) == (
        "Lookup would require extrapolation into the future.  Requested time 3.500000 "
        "but the latest data is at time 3.000000"
    )
    with pytest.raises(BackwardExtrapolationException) as b:
        c.get(S - 1000)
    assert str(b.value) == (
        "Lookup would require extrapolation into the past.  Requested time 0.999999 "
        "but the earliest data is at time 1.000000"
    )
    assert isinstance(f.value, ExtrapolationException)


def test_no_extrapolation_even_by_one_ns() -> None:
    c = filled((1.0, 0), (2.0, 1))
    with pytest.raises(ForwardExtrapolationException):
        c.get(2 * S + 1)
    with pytest.raises(BackwardExtrapolationException) as b:
        c.get(S - 1)
    assert "Requested time 1.000000 but the earliest data is at time 1.000000" in str(b.value)
    assert x_at(c, 2.0) == 1


def test_interpolation_ratio_from_integer_ns() -> None:
    # stamps far from 0: float seconds would lose the 1 ns step; int ns does not
    base = 1_700_000_000 * S
    c = TimeCache()
    c.insert(base, 1, tx(0))  # type: ignore[arg-type]
    c.insert(base + 3, 1, tx(3))  # type: ignore[arg-type]
    assert c.get(base + 1)[1][4] == pytest.approx(1.0, abs=1e-12)


def test_slerp_interpolation_of_rotation() -> None:
    c = TimeCache()
    c.insert(S, 1, (0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0))
    h = math.sqrt(0.5)
    c.insert(2 * S, 1, (0.0, 0.0, h, h, 0.0, 0.0, 0.0))
    q = c.get(S + S // 2)[1][:4]
    assert q == pytest.approx((0.0, 0.0, math.sin(math.pi / 8), math.cos(math.pi / 8)))


def test_reparenting_returns_older_sample_without_interpolation() -> None:
    # base@3.5 parent odom(2), base@4.0 parent map(3): lookup at 3.75 -> odom, base@3.5
    c = TimeCache()
    c.insert(3 * S + S // 2, 2, tx(1))  # type: ignore[arg-type]
    c.insert(4 * S, 3, tx(9))  # type: ignore[arg-type]
    parent, sample = c.get(3 * S + 3 * S // 4)
    assert (parent, sample[4]) == (2, 1)
    assert c.latest_time_and_parent() == (4 * S, 3)


def test_introspection_helpers() -> None:
    c = TimeCache()
    assert (c.latest_stamp(), c.oldest_stamp(), len(c), c.latest_time_and_parent()) == (
        0,
        0,
        0,
        (0, 0),
    )
    c = filled((1.0, 0), (2.0, 0), parent=4)
    assert (c.latest_stamp(), c.oldest_stamp(), len(c)) == (2 * S, S, 2)
    assert c.latest_time_and_parent() == (2 * S, 4)
    c.clear()
    assert len(c) == 0


def test_static_cache_any_time_overwrite_and_survives_clear() -> None:
    s = StaticCache()
    s.insert(5 * S, 2, tx(1))  # type: ignore[arg-type]
    s.insert(1 * S, 3, tx(2))  # type: ignore[arg-type]  # any stamp, new parent: overwrite
    assert s.get(123) == (3, tx(2))
    assert s.get(0) == (3, tx(2))
    s.clear()
    assert s.get(7) == (3, tx(2))
    assert (s.latest_stamp(), s.oldest_stamp(), len(s), s.latest_time_and_parent()) == (
        0,
        0,
        1,
        (0, 3),
    )


@pytest.mark.parametrize(
    ("ns", "text"),
    [(0, "0.000000"), (1_500_000_000, "1.500000"), (1_700_000_000_123_456_789, "1700000000.123457"),
     (999, "0.000001"), (499, "0.000000")],
)  # fmt: skip
def test_display_time(ns: int, text: str) -> None:
    assert display_time(ns) == text


def test_batched_drop_is_invisible() -> None:
    """A cache owned by a buffer drops old samples in batches; every reader sees exactly the
    samples of a cache that drops them on each insert (tf2's rule, ``pending=None``), at every
    step: contents, oldest stamp, length, answers and error texts near the window's edge."""
    pending: set[TimeCache] = set()
    batched, eager = TimeCache(S, pending), TimeCache(S)
    for k in range(400):  # 10 ms apart: the 1 s window holds ~100, so ~3 batches are dropped
        stamp = 5 * S + k * S // 100
        assert batched.insert(stamp, 1, tx(k)) == eager.insert(stamp, 1, tx(k))  # type: ignore[arg-type]
        if k % 37 == 0:
            assert batched.oldest_stamp() == eager.oldest_stamp()
            assert len(batched) == len(eager)
        if k % 53 == 0:
            for t in (eager.oldest_stamp() - 1, eager.oldest_stamp(), stamp - S // 200):
                try:
                    want: object = eager.get(t)
                except ExtrapolationException as exc:
                    want = (type(exc), str(exc))
                try:
                    got: object = batched.get(t)
                except ExtrapolationException as exc:
                    got = (type(exc), str(exc))
                assert got == want
    assert batched in pending or batched.stamps == eager.stamps
    batched.prune()
    assert (batched.stamps, batched.parents, batched.data) == (
        eager.stamps, eager.parents, eager.data)
    assert len(eager) < 110  # the reference really dropped most of the 400
