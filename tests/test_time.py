"""posekit.time against rclpy's documented semantics (integer nanoseconds, messages, arithmetic),
and the stamp conversions against exact integer / rational arithmetic (``fractions``)."""

from __future__ import annotations

from fractions import Fraction

import pytest

from posekit.msgs.builtin_interfaces import Duration as DurationMsg
from posekit.msgs.builtin_interfaces import Time as TimeMsg
from posekit.time import (
    NS_PER_S,
    ClockType,
    Duration,
    Time,
    stamp_from_ns,
    stamp_from_seconds,
    stamp_to_ns,
    stamp_to_seconds,
)


def test_time_zero_default_means_latest() -> None:
    t = Time()
    assert t.nanoseconds == 0
    assert t.clock_type == ClockType.SYSTEM_TIME
    assert t.to_msg() == TimeMsg(sec=0, nanosec=0)


@pytest.mark.parametrize(
    ("kwargs", "ns"),
    [
        ({"seconds": 1}, 1_000_000_000),
        ({"seconds": 1.5}, 1_500_000_000),
        ({"nanoseconds": 7}, 7),
        ({"seconds": 2, "nanoseconds": 5}, 2_000_000_005),
    ],
)
def test_time_construction_is_integer_ns(kwargs: dict[str, float], ns: int) -> None:
    t = Time(**kwargs)  # type: ignore[arg-type]
    assert t.nanoseconds == ns
    assert isinstance(t.nanoseconds, int)


def test_float_seconds_round_to_nearest_ns_of_the_exact_double() -> None:
    seconds = 1_700_000_000.123456789  # the double nearest to this literal
    exact = Fraction(seconds) * 1_000_000_000
    assert Time(seconds=seconds).nanoseconds == round(exact)


def test_large_float_seconds_keep_sub_microsecond_part() -> None:
    # 1.7e9 s as a double has ~238 ns resolution: int(seconds * 1e9) would be off by up to 119 ns
    seconds = 1_700_000_000.25
    assert Time(seconds=seconds).nanoseconds == 1_700_000_000_250_000_000


def test_negative_time_rejected() -> None:
    with pytest.raises(ValueError, match="negative"):
        Time(nanoseconds=-1)


def test_to_msg_from_msg_round_trip() -> None:
    t = Time(seconds=12, nanoseconds=345_678_901)
    msg = t.to_msg()
    assert (msg.sec, msg.nanosec) == (12, 345_678_901)
    back = Time.from_msg(msg)
    assert back.nanoseconds == t.nanoseconds
    assert back.clock_type == ClockType.ROS_TIME  # rclpy's from_msg default
    assert t.seconds_nanoseconds() == (12, 345_678_901)


def test_from_msg_duck_typed() -> None:
    class Stamp:
        sec = 3
        nanosec = 4

    assert Time.from_msg(Stamp()).nanoseconds == 3_000_000_004
    assert Duration.from_msg(DurationMsg(sec=-2, nanosec=500_000_000)).nanoseconds == -1_500_000_000


def test_comparisons_same_clock() -> None:
    a, b = Time(seconds=1), Time(seconds=2)
    assert a < b
    assert a <= b
    assert b > a
    assert b >= a
    assert a != b
    assert a == Time(nanoseconds=1_000_000_000)
    with pytest.raises(TypeError, match="unhashable"):  # as Jazzy's: key by .nanoseconds
        hash(a)


def test_comparing_different_clocks_raises() -> None:
    with pytest.raises(TypeError):
        _ = Time(seconds=1, clock_type=ClockType.ROS_TIME) < Time(seconds=2)
    with pytest.raises(TypeError):
        _ = Time(seconds=1) < 5  # type: ignore[operator]


def test_time_duration_arithmetic() -> None:
    t = Time(seconds=10)
    d = Duration(seconds=2, nanoseconds=1)
    assert (t + d).nanoseconds == 12_000_000_001
    assert (d + t).nanoseconds == 12_000_000_001
    assert (t - d).nanoseconds == 7_999_999_999
    diff = Time(seconds=3) - Time(seconds=1)
    assert isinstance(diff, Duration)
    assert diff.nanoseconds == 2_000_000_000
    assert (t - d).clock_type == t.clock_type
    with pytest.raises(ValueError, match="negative"):
        _ = Time(seconds=1) - Duration(seconds=2)


def test_duration() -> None:
    d = Duration(seconds=-1.5)
    assert d.nanoseconds == -1_500_000_000
    assert d.to_msg() == DurationMsg(sec=-2, nanosec=500_000_000)  # nanosec always in [0, 1e9)
    assert Duration() == Duration(nanoseconds=0)
    assert Duration(seconds=1) > Duration(nanoseconds=999_999_999)
    assert Duration(seconds=0.25).to_seconds() == 0.25
    assert str(Duration(seconds=1.5)) == "1500000000 nanoseconds"
    assert str(Duration(nanoseconds=2**63 - 1)) == "Infinite"
    with pytest.raises(TypeError):
        _ = Duration(seconds=1) < 3  # type: ignore[operator]


@pytest.mark.parametrize("ns", [0, 1, 999_999_999, 1_000_000_000, 1_700_000_000_123_456_789])
def test_stamp_ns_round_trip_splits_whole_seconds(ns: int) -> None:
    msg = stamp_from_ns(ns)
    assert (msg.sec, msg.nanosec) == (ns // NS_PER_S, ns % NS_PER_S)
    assert 0 <= msg.nanosec < NS_PER_S
    assert stamp_to_ns(msg) == ns
    assert stamp_from_ns(ns) == Time(nanoseconds=ns).to_msg()  # the same split as rclpy's


def test_stamp_to_ns_is_duck_typed_and_exact() -> None:
    class Stamp:
        sec, nanosec = 2**40, 999_999_999

    assert stamp_to_ns(Stamp()) == 2**40 * NS_PER_S + 999_999_999


def test_stamp_seconds_round_to_the_nearest_nanosecond() -> None:
    for t in (0.0, 1e-9, 0.1, 2.5, 12.3456789012, 1_700_000_000.25):
        msg = stamp_from_seconds(t)
        exact = Fraction(t) * NS_PER_S  # the double's exact value, in ns
        assert abs(Fraction(stamp_to_ns(msg)) - exact) <= Fraction(1, 2) + abs(exact) * Fraction(
            1, 2**52)
    assert stamp_to_seconds(TimeMsg(sec=1, nanosec=500_000_000)) == 1.5
    assert stamp_to_seconds(TimeMsg(sec=3, nanosec=1)) == 3.0 + 1e-9
    with pytest.raises(ValueError, match="negative"):
        stamp_from_seconds(-0.5)


def test_duration_has_no_arithmetic_of_its_own_as_in_jazzy() -> None:
    # Jazzy's Duration defines none of these; code written against posekit must run there
    d = Duration(seconds=1)
    for op in (lambda: d + d, lambda: d - d, lambda: d * 2, lambda: 2 * d, lambda: -d,
               lambda: abs(d), lambda: d / 2, lambda: hash(d)):
        with pytest.raises(TypeError):
            op()


def test_jazzy_limits_and_errors() -> None:
    with pytest.raises(OverflowError, match="too large to store in C time point"):
        Time(seconds=2**64)
    with pytest.raises(OverflowError):
        Time(nanoseconds=2**63)
    with pytest.raises(OverflowError, match="too large to store in C duration"):
        Duration(seconds=-(2**63))
    with pytest.raises(ValueError, match="Seconds value must not be negative"):
        Time(seconds=-1)
    with pytest.raises(ValueError, match="Nanoseconds value must not be negative"):
        Time(seconds=1, nanoseconds=-1)
    with pytest.raises(TypeError, match="Clock type must be a ClockType enum"):
        Time(clock_type="x")  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="Clock type must be a ClockType enum"):
        Time(clock_type=1)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"Must pass a builtin_interfaces\.msg\.Time object"):
        Time.from_msg(5)
    with pytest.raises(TypeError, match=r"Must pass a builtin_interfaces\.msg\.Duration"):
        Duration.from_msg(5)
    with pytest.raises(OverflowError, match="Addition leads to overflow"):
        _ = Time(nanoseconds=2**63 - 1) + Duration(nanoseconds=1)
    with pytest.raises(TypeError, match="Can't subtract times with different clock types"):
        _ = Time(clock_type=ClockType.ROS_TIME) - Time()
