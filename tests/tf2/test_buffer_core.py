"""BufferCore against tf2's ROS 2 behaviour (docs/specs/tf2.md sections 1, 2, 5, 6, 7, 10, 14).

Expected values come from docs/specs/tf2.md's worked numbers, hand computation, or an independent
4x4-matrix model of the tree (numpy + scipy), never from posekit itself.
"""

from __future__ import annotations

import itertools
import logging
import math
from functools import cache
from typing import Any

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from posekit.msgs.builtin_interfaces import Time as TimeMsg
from posekit.msgs.geometry_msgs import TransformStamped
from posekit.tf2 import (
    BufferCore,
    ConnectivityException,
    ExtrapolationException,
    InvalidArgumentException,
    LookupException,
    NoDataForExtrapolationException,
    TimeoutException,
    TransformException,
)
from posekit.time import Duration, Time

S = 1_000_000_000


def ts(
    parent: str,
    child: str,
    sec: float,
    t: tuple[float, float, float] = (0.0, 0.0, 0.0),
    q: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 1.0),
) -> TransformStamped:
    m = TransformStamped()
    m.header.frame_id = parent
    m.child_frame_id = child
    m.header.stamp.sec, m.header.stamp.nanosec = divmod(round(sec * S), S)
    tr = m.transform
    tr.translation.x, tr.translation.y, tr.translation.z = t
    tr.rotation.x, tr.rotation.y, tr.rotation.z, tr.rotation.w = q
    return m


def yaw(angle: float) -> tuple[float, float, float, float]:
    return (0.0, 0.0, math.sin(angle / 2), math.cos(angle / 2))


def at(sec: float) -> Time:
    return Time(nanoseconds=round(sec * S))


def trans(m: TransformStamped) -> list[float]:
    v = m.transform.translation
    return [v.x, v.y, v.z]


def rot(m: TransformStamped) -> list[float]:
    q = m.transform.rotation
    return [q.x, q.y, q.z, q.w]


def stamp_ns(m: TransformStamped) -> int:
    return m.header.stamp.sec * S + m.header.stamp.nanosec


def spec_tree() -> BufferCore:
    """docs/specs/tf2.md section 10 tree: world->map, base->laser static; map->odom, odom->base
    dynamic."""
    b = BufferCore()
    b.set_transform_static(ts("world", "map", 0, (1, 0, 0)), "auth")
    b.set_transform(ts("map", "odom", 1, (0, 0, 0)), "auth")
    b.set_transform(ts("map", "odom", 2, (2, 0, 0), yaw(math.pi / 2)), "auth")
    b.set_transform(ts("map", "odom", 3, (4, 0, 0), yaw(math.pi)), "auth")
    b.set_transform(ts("odom", "base", 1.5, (0, 1, 0)), "auth")
    b.set_transform(ts("odom", "base", 3.5, (0, 3, 0)), "auth")
    b.set_transform_static(ts("base", "laser", 0, (0.1, 0, 0.2)), "auth")
    return b


# ---------------------------------------------------------------------------------------------
# section 10 golden values
# ---------------------------------------------------------------------------------------------
def test_golden_latest() -> None:
    r = spec_tree().lookup_transform_core("world", "laser", Time())
    assert stamp_ns(r) == 3 * S
    np.testing.assert_allclose(trans(r), [4.9, -2.5, 0.2], atol=1e-12)
    np.testing.assert_allclose(rot(r), [0, 0, 1, 0], atol=1e-12)
    assert (r.header.frame_id, r.child_frame_id) == ("world", "laser")


def test_golden_interpolated() -> None:
    b = spec_tree()
    r = b.lookup_transform_core("map", "odom", at(1.5))
    np.testing.assert_allclose(trans(r), [1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(rot(r), [0, 0, 0.38268343, 0.92387953], atol=1e-8)
    r = b.lookup_transform_core("world", "laser", at(2.25))
    np.testing.assert_allclose(trans(r), [1.84494247, -0.57730805, 0.2], atol=1e-8)
    np.testing.assert_allclose(rot(r), [0, 0, 0.83146961, 0.55557023], atol=1e-8)
    np.testing.assert_allclose(trans(b.lookup_transform_core("base", "odom", at(2.5))), [0, -2, 0])


def test_golden_full() -> None:
    r = spec_tree().lookup_transform_full_core("base", at(3.5), "base", at(1.5), "odom")
    np.testing.assert_allclose(trans(r), [0, -2, 0], atol=1e-12)
    assert stamp_ns(r) == 3_500_000_000


# ---------------------------------------------------------------------------------------------
# section 2: set_transform
# ---------------------------------------------------------------------------------------------
def messages(caplog: pytest.LogCaptureFixture) -> list[str]:
    return [r.getMessage() for r in caplog.records if r.name == "posekit.tf2"]


def test_self_transform_after_stripping(caplog: pytest.LogCaptureFixture) -> None:
    b = BufferCore()
    with caplog.at_level(logging.ERROR, "posekit.tf2"):
        assert b.set_transform(ts("/a", "a", 1), "node") is False
    assert messages(caplog) == [
        'TF_SELF_TRANSFORM: Ignoring transform from authority "node" with frame_id and  '
        'child_frame_id "a" because they are the same'
    ]
    assert b._getFrameStrings() == []


def test_missing_ids_log_each_reason(caplog: pytest.LogCaptureFixture) -> None:
    b = BufferCore()
    with caplog.at_level(logging.ERROR, "posekit.tf2"):
        assert not b.set_transform(ts("a", "", 1), "n")
        assert not b.set_transform(ts("", "c", 1), "n")
    assert messages(caplog) == [
        'TF_NO_CHILD_FRAME_ID: Ignoring transform from authority "n" because '
        "child_frame_id not set ",
        'TF_NO_FRAME_ID: Ignoring transform with child_frame_id "c"  from authority "n" because '
        "frame_id not set",
    ]
    assert b._getFrameStrings() == []


def test_nan_translation_rejected_with_values(caplog: pytest.LogCaptureFixture) -> None:
    b = BufferCore()
    with caplog.at_level(logging.ERROR, "posekit.tf2"):
        assert not b.set_transform(ts("a", "b", 1, (math.nan, 1, 2)), "n")
    assert messages(caplog) == [
        'TF_NAN_INPUT: Ignoring transform for child_frame_id "b" from authority "n" because of a '
        "nan value in the transform (nan 1.000000 2.000000) (0.000000 0.000000 0.000000 1.000000)"
    ]


@pytest.mark.parametrize(
    "q",
    [(0.0, 0.0, 0.0, 0.0), (0.0, 0.0, math.inf, 1.0), (0.0, 0.0, 1e-200, 1e-200),
     (math.nan, 0.0, 0.0, 1.0)],
)  # fmt: skip
def test_degenerate_quaternions_are_nan_input(
    q: tuple[float, float, float, float], caplog: pytest.LogCaptureFixture
) -> None:
    b = BufferCore()
    with caplog.at_level(logging.ERROR, "posekit.tf2"):
        assert not b.set_transform(ts("a", "b", 1, (0, 0, 0), q), "n")
    assert messages(caplog)[0].startswith('TF_NAN_INPUT: Ignoring transform for child_frame_id "b"')
    assert not b._frameExists("b")


def test_non_unit_quaternion_normalised_and_accepted() -> None:
    b = BufferCore()
    assert b.set_transform(ts("a", "b", 1, (0, 0, 0), (0, 0, 0, 5)), "n")
    assert rot(b.lookup_transform_core("a", "b", Time())) == [0, 0, 0, 1]
    assert b.set_transform(ts("a", "c", 1, (0, 0, 0), (0, 0, 3, 4)), "n")
    np.testing.assert_allclose(rot(b.lookup_transform_core("a", "c", Time())), [0, 0, 0.6, 0.8])


def test_stored_quaternion_sign_canonical() -> None:
    b = BufferCore()
    h = math.sqrt(0.5)
    b.set_transform(ts("a", "b", 1, (0, 0, 0), (0, 0, -h, -h)), "n")
    np.testing.assert_allclose(rot(b.lookup_transform_core("a", "b", at(1))), [0, 0, h, h])


def test_infinite_translation_accepted() -> None:
    b = BufferCore()
    assert b.set_transform(ts("a", "b", 1, (math.inf, 0, 0)), "n")
    assert trans(b.lookup_transform_core("a", "b", Time()))[0] == math.inf


def test_leading_slash_stripped_once_on_insert_rejected_on_lookup() -> None:
    b = BufferCore()
    assert b.set_transform(ts("/map", "//odom", 1), "n")
    assert b._getFrameStrings() == ["/odom", "map"]
    with pytest.raises(InvalidArgumentException) as e:
        b.lookup_transform_core("map", "/odom", Time())
    assert str(e.value) == (
        'Invalid argument "/odom" passed to lookupTransform argument source_frame - in tf2 '
        "frame_ids cannot start with a '/'"
    )


def test_frame_ids_child_first_then_parent() -> None:
    b = BufferCore()
    b.set_transform(ts("world", "map", 1), "n")
    b.set_transform(ts("map", "odom", 1), "n")
    assert b._getFrameStrings() == ["map", "world", "odom"]


def test_old_data_warning_and_false(caplog: pytest.LogCaptureFixture) -> None:
    b = BufferCore(Duration(seconds=10))
    b.set_transform(ts("a", "b", 20), "first")
    with caplog.at_level(logging.WARNING, "posekit.tf2"):
        assert b.set_transform(ts("a", "b", 9.5), "late") is False
    rec = [r for r in caplog.records if r.name == "posekit.tf2"]
    assert rec[0].levelno == logging.WARNING
    assert rec[0].getMessage() == (
        "TF_OLD_DATA ignoring data from the past for frame b at time 9.500000 according to "
        "authority late\nPossible reasons are listed at http://wiki.ros.org/tf/Errors%20explained"
    )
    assert "broadcaster: 'first'" in b.all_frames_as_yaml()


def test_default_cache_time_is_ten_seconds() -> None:
    assert BufferCore().cache_time == Duration(seconds=10)
    b = BufferCore()
    b.set_transform(ts("a", "b", 20), "n")
    assert b.set_transform(ts("a", "b", 10), "n")
    assert not b.set_transform(ts("a", "b", 9.999), "n")


def test_switching_kinds_replaces_cache() -> None:
    b = BufferCore()
    b.set_transform(ts("a", "b", 1, (1, 0, 0)), "n")
    b.set_transform(ts("a", "b", 2, (2, 0, 0)), "n")
    b.set_transform_static(ts("a", "b", 0, (7, 0, 0)), "n")
    assert trans(b.lookup_transform_core("a", "b", at(1.5))) == [7, 0, 0]  # history gone
    b.set_transform(ts("a", "b", 5, (5, 0, 0)), "n")
    with pytest.raises(ExtrapolationException):  # static value gone: one sample at 5 s
        b.lookup_transform_core("a", "b", at(4))


def test_static_resend_replaces_value_and_parent() -> None:
    b = BufferCore()
    b.set_transform_static(ts("a", "c", 0, (1, 0, 0)), "n")
    b.set_transform_static(ts("b", "c", 0, (2, 0, 0)), "n")
    assert trans(b.lookup_transform_core("b", "c", at(99))) == [2, 0, 0]
    assert b.all_frames_as_string() == "Frame c exists with parent b.\n"


def test_builtin_stamp_and_int_and_rclpy_like_times_are_equal() -> None:
    b = spec_tree()

    class RclpyTime:
        nanoseconds = 2_250_000_000

    results = [
        b.lookup_transform_core("world", "laser", t)
        for t in (at(2.25), TimeMsg(sec=2, nanosec=250_000_000), 2_250_000_000, RclpyTime())
    ]
    assert all(r == results[0] for r in results)
    with pytest.raises(TypeError):
        b.lookup_transform_core("world", "laser", 2.25)


# ---------------------------------------------------------------------------------------------
# section 5.1: identity shortcut and validation
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["nosuch", "", "/x", "map"])
def test_identity_shortcut_before_validation(name: str) -> None:
    b = spec_tree()
    r = b.lookup_transform_core(name, name, at(7))
    assert trans(r) == [0, 0, 0]
    assert rot(r) == [0, 0, 0, 1]
    assert stamp_ns(r) == 7 * S
    assert b.can_transform_core(name, name, Time()) == (True, "")


def test_identity_latest_stamp_is_frame_newest() -> None:
    b = spec_tree()
    assert stamp_ns(b.lookup_transform_core("odom", "odom", Time())) == 3 * S
    assert stamp_ns(b.lookup_transform_core("laser", "laser", Time())) == 0  # static
    assert stamp_ns(b.lookup_transform_core("world", "world", Time())) == 0  # root, no cache


@pytest.mark.parametrize(
    ("target", "source", "exc", "text"),
    [
        ("", "nosuch", InvalidArgumentException,
         'Invalid argument "" passed to lookupTransform argument target_frame - in tf2 frame_ids '
         "cannot be empty"),
        ("/world", "", InvalidArgumentException,
         "Invalid argument \"/world\" passed to lookupTransform argument target_frame - in tf2 "
         "frame_ids cannot start with a '/'"),
        ("nosuch", "", LookupException,
         '"nosuch" passed to lookupTransform argument target_frame does not exist. '),
        ("map", "nosuch", LookupException,
         '"nosuch" passed to lookupTransform argument source_frame does not exist. '),
        ("map", "", InvalidArgumentException,
         'Invalid argument "" passed to lookupTransform argument source_frame - in tf2 frame_ids '
         "cannot be empty"),
    ],
)  # fmt: skip
def test_validation_order_and_texts(target: str, source: str, exc: type, text: str) -> None:
    with pytest.raises(exc) as e:
        spec_tree().lookup_transform_core(target, source, Time())
    assert type(e.value) is exc
    assert str(e.value) == text


def test_full_validates_fixed_frame_last() -> None:
    b = spec_tree()
    with pytest.raises(LookupException) as e:
        b.lookup_transform_full_core("map", Time(), "odom", Time(), "nosuch")
    assert (
        str(e.value) == '"nosuch" passed to lookupTransform argument fixed_frame does not exist. '
    )
    with pytest.raises(LookupException) as e2:  # target checked before source and fixed
        b.lookup_transform_full_core("nosuch", Time(), "", Time(), "/x")
    assert "argument target_frame" in str(e2.value)
    with pytest.raises(InvalidArgumentException) as e3:
        b.lookup_transform_full_core("map", Time(), "", Time(), "/x")
    assert "argument source_frame" in str(e3.value)


# ---------------------------------------------------------------------------------------------
# section 5.2: latest common time
# ---------------------------------------------------------------------------------------------
def test_lct_ignores_edges_above_common_ancestor() -> None:
    b = BufferCore()
    b.set_transform(ts("root", "a", 1), "n")  # stale edge above the meeting point
    b.set_transform(ts("a", "b", 5), "n")
    b.set_transform(ts("a", "b", 8), "n")
    b.set_transform(ts("a", "c", 6), "n")
    b.set_transform(ts("a", "c", 9), "n")
    r = b.lookup_transform_core("b", "c", Time())
    assert stamp_ns(r) == 8 * S  # min(8, 9); root->a (1 s) ignored
    assert b.get_latest_common_time("b", "c") == Time(seconds=8)


def test_lct_static_edges_contribute_nothing_and_all_static_is_zero() -> None:
    b = BufferCore()
    b.set_transform_static(ts("a", "b", 50), "n")
    b.set_transform(ts("b", "c", 3), "n")
    b.set_transform_static(ts("a", "s", 70), "n")
    assert stamp_ns(b.lookup_transform_core("a", "c", Time())) == 3 * S
    assert stamp_ns(b.lookup_transform_core("s", "b", Time())) == 0
    assert b.get_latest_common_time("s", "b") == Time()


# A random forest of frames f1..f4 under lower-numbered parents: per frame nothing, a static
# edge, or dynamic samples (seconds, each with its own parent; the newest decides).
_lct_edge = st.one_of(
    st.none(),
    st.tuples(st.just("static"), st.integers(0, 5)),
    st.lists(st.tuples(st.integers(1, 9), st.integers(0, 5)), min_size=1, max_size=3,
             unique_by=lambda s: s[0]),
)


@given(st.lists(_lct_edge, min_size=4, max_size=4), st.integers(0, 4), st.integers(0, 4))
# f2 and f3 meet at f1, whose own edge (1 s) is older than both: it must not count
@example([[(1, 0)], [(5, 1)], [(6, 1)], None], 3, 2)
@example([[(1, 0)], [(5, 1)], [(6, 1)], None], 2, 3)
# f3 is under f2 under f1: each one an ancestor of the other in turn
@example([[(4, 0)], [(5, 1)], [(3, 2)], None], 1, 3)
@example([[(4, 0)], [(5, 1)], [(3, 2)], None], 3, 1)
# static edges only, and a frame with none above it
@example([("static", 0), ("static", 1), ("static", 1), None], 3, 2)
@example([None, None, None, [(2, 0)]], 0, 4)
# two trees
@example([[(1, 0)], None, [(2, 2)], None], 1, 3)
def test_lct_is_the_oldest_newest_stamp_below_the_common_ancestor(
    edges: list[Any], target_i: int, source_i: int
) -> None:
    # Oracle: tf2's definition written out on the newest parent of each frame: walk both
    # frames up to their first common ancestor; the answer is the smallest non-zero newest
    # stamp of the edges below it (0 if all are static, the frame's own newest stamp for
    # target == source), and no common ancestor is a plain TransformException.
    b = BufferCore()
    newest: dict[str, tuple[str, int]] = {}  # child -> (parent, newest stamp ns; 0 static)
    for i, edge in enumerate(edges, start=1):
        child = f"f{i}"
        if edge is None:
            continue
        if edge[0] == "static":
            parent = f"f{edge[1] % i}"
            b.set_transform_static(ts(parent, child, 0), "n")
            newest[child] = (parent, 0)
            continue
        for sec, p in sorted(edge):
            b.set_transform(ts(f"f{p % i}", child, sec), "n")
        sec, p = max(edge)
        newest[child] = (f"f{p % i}", sec * S)
    known = set(newest) | {parent for parent, _ in newest.values()}
    target, source = f"f{target_i}", f"f{source_i}"
    if target not in known or source not in known:
        return

    def up(frame: str) -> list[str]:
        chain = [frame]
        while chain[-1] in newest:
            chain.append(newest[chain[-1]][0])
        return chain

    if target == source:
        expected: int | None = newest[target][1] if target in newest else 0
    else:
        target_up, source_up = up(target), up(source)
        common = next((f for f in source_up if f in target_up), None)
        if common is None:
            expected = None
        else:
            below = (source_up[: source_up.index(common)]
                     + target_up[: target_up.index(common)])
            expected = min((newest[f][1] for f in below if newest[f][1]), default=0)
    if expected is None:
        with pytest.raises(TransformException):
            b.get_latest_common_time(target, source)
    else:
        assert b.get_latest_common_time(target, source) == Time(nanoseconds=expected)


def test_lct_without_overlap_fails_with_backward_text() -> None:
    b = BufferCore()
    b.set_transform(ts("world", "odom", 1), "n")
    b.set_transform(ts("world", "odom", 2), "n")
    b.set_transform(ts("odom", "b", 5.5), "n")
    b.set_transform(ts("odom", "b", 7), "n")
    with pytest.raises(ExtrapolationException) as e:
        b.lookup_transform_core("world", "b", Time())
    assert str(e.value) == (
        "Lookup would require extrapolation into the past.  Requested time 2.000000 but the "
        "earliest data is at time 5.500000, when looking up transform from frame [b] to frame "
        "[world]"
    )


def test_lct_uses_newest_parent_after_reparenting() -> None:
    b = BufferCore()
    b.set_transform(ts("odom", "base", 1), "n")
    b.set_transform(ts("map", "base", 4), "n")  # re-parented
    b.set_transform(ts("map", "x", 2), "n")
    b.set_transform(ts("map", "x", 6), "n")
    assert b.get_latest_common_time("map", "base") == Time(seconds=4)
    assert b.get_latest_common_time("x", "base") == Time(seconds=4)
    with pytest.raises(TransformException) as e:
        b.get_latest_common_time("odom", "x")
    assert type(e.value) is TransformException  # plain class, as tf2_py


def test_reparenting_lookup_between_samples_uses_older_parent() -> None:
    b = BufferCore()
    b.set_transform(ts("odom", "base", 3.5, (1, 0, 0)), "n")
    b.set_transform(ts("map", "base", 4.0, (5, 0, 0)), "n")
    assert trans(b.lookup_transform_core("odom", "base", at(3.75))) == [1, 0, 0]
    with pytest.raises(ConnectivityException):
        b.lookup_transform_core("map", "base", at(3.75))
    assert trans(b.lookup_transform_core("map", "base", at(4))) == [5, 0, 0]


# ---------------------------------------------------------------------------------------------
# section 5.3: the walk, error precedence, loops
# ---------------------------------------------------------------------------------------------
def test_broken_edge_above_meeting_point_does_not_matter() -> None:
    b = BufferCore()
    b.set_transform(ts("root", "a", 1), "n")  # no data at 5 s
    b.set_transform(ts("a", "b", 4, (1, 0, 0)), "n")
    b.set_transform(ts("a", "b", 6, (3, 0, 0)), "n")
    b.set_transform(ts("a", "c", 4, (0, 1, 0)), "n")
    b.set_transform(ts("a", "c", 6, (0, 1, 0)), "n")
    np.testing.assert_allclose(trans(b.lookup_transform_core("c", "b", at(5))), [2, -1, 0])
    with pytest.raises(ExtrapolationException):
        b.lookup_transform_core("root", "b", at(5))


def test_target_side_error_raised_first() -> None:
    b = BufferCore()
    b.set_transform(ts("a", "s", 1), "n")
    b.set_transform(ts("a", "s", 2), "n")  # source edge: past data at 10 s
    b.set_transform(ts("a", "t", 20), "n")
    b.set_transform(ts("a", "t", 21), "n")  # target edge: future
    with pytest.raises(ExtrapolationException) as e:
        b.lookup_transform_core("t", "s", at(10))
    assert str(e.value).startswith(
        "Lookup would require extrapolation into the past.  Requested time 10.000000 but the "
        "earliest data is at time 20.000000, when looking up"
    )


def test_source_error_when_target_walk_misses() -> None:
    b = BufferCore()
    b.set_transform(ts("a", "s", 1), "n")
    b.set_transform(ts("a", "s", 2), "n")
    b.set_transform_static(ts("a", "t", 0), "n")
    with pytest.raises(ExtrapolationException) as e:
        b.lookup_transform_core("t", "s", at(10))
    assert str(e.value) == (
        "Lookup would require extrapolation into the future.  Requested time 10.000000 but the "
        "latest data is at time 2.000000, when looking up transform from frame [s] to frame [t]"
    )


def test_connectivity_text() -> None:
    b = BufferCore()
    b.set_transform(ts("a", "b", 1), "n")
    b.set_transform(ts("c", "d", 1), "n")
    with pytest.raises(ConnectivityException) as e:
        b.lookup_transform_core("b", "d", at(1))
    assert str(e.value) == (
        "Could not find a connection between 'b' and 'd' because they are not part of the same "
        "tree.Tf has two or more unconnected trees."
    )
    with pytest.raises(ConnectivityException):
        b.lookup_transform_core("b", "d", Time())


def test_two_cycle_direct_lookup_works_and_loop_detected() -> None:
    b = BufferCore()
    b.set_transform(ts("a", "b", 1, (1, 0, 0)), "n")
    b.set_transform(ts("b", "a", 1, (5, 0, 0)), "n")
    b.set_transform(ts("x", "y", 1), "n")
    assert trans(b.lookup_transform_core("a", "b", at(1))) == [1, 0, 0]
    expected = (
        "The tf tree is invalid because it contains a loop.\n"
        "Frame b exists with parent a.\nFrame a exists with parent b.\n"
        "Frame y exists with parent x.\n"
        "\n"
    )
    for t in (Time(), at(1)):
        with pytest.raises(LookupException) as e:
            b.lookup_transform_core("y", "a", t)
        assert str(e.value) == expected


def test_chain_deeper_than_1000_is_refused_as_loop() -> None:
    b = BufferCore()
    for i in range(1001):
        b.set_transform_static(ts(f"f{i}", f"f{i + 1}", 0), "n")
    assert trans(b.lookup_transform_core("f1", "f1001", Time())) == [0, 0, 0]
    with pytest.raises(LookupException, match="contains a loop"):
        b.lookup_transform_core("f0", "f1001", at(1))


# ---------------------------------------------------------------------------------------------
# clear(), static frames
# ---------------------------------------------------------------------------------------------
def test_clear_keeps_statics_and_ids() -> None:
    b = spec_tree()
    b.clear()
    assert b._frameExists("odom")
    assert trans(b.lookup_transform_core("base", "laser", at(123))) == [0.1, 0, 0.2]
    with pytest.raises(ConnectivityException):
        b.lookup_transform_core("map", "base", Time())
    with pytest.raises(NoDataForExtrapolationException) as e:
        b.lookup_transform_core("map", "odom", at(2))
    assert str(e.value) == ", when looking up transform from frame [odom] to frame [map]"
    assert b.set_transform(ts("map", "odom", 0.001), "n")  # old stamps accepted again
    assert b.all_frames_as_string() == (
        "Frame map exists with parent world.\nFrame odom exists with parent map.\n"
        "Frame base exists with parent NO_PARENT.\nFrame laser exists with parent base.\n"
    )


def test_static_any_time_stamp_echo() -> None:
    b = BufferCore()
    b.set_transform_static(ts("a", "b", 5, (1, 2, 3)), "n")
    for sec in (0.5, 5, 1e6):
        r = b.lookup_transform_core("a", "b", at(sec))
        assert stamp_ns(r) == round(sec * S)
        assert trans(r) == [1, 2, 3]
    assert stamp_ns(b.lookup_transform_core("b", "a", Time())) == 0
    np.testing.assert_allclose(trans(b.lookup_transform_core("b", "a", Time())), [-1, -2, -3])


# ---------------------------------------------------------------------------------------------
# section 7: can_transform
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("target", "source", "text"),
    [
        ("nosuch", "map", 'Invalid frame ID "nosuch" passed to canTransform argument '
         "target_frame - frame does not exist"),
        ("map", "", 'Invalid frame ID "" passed to canTransform argument source_frame - in tf2 '
         "frame_ids cannot be empty"),
        ("/map", "x", "Invalid frame ID \"/map\" passed to canTransform argument target_frame - in "
         "tf2 frame_ids cannot start with a '/'"),
    ],
)  # fmt: skip
def test_can_transform_texts(target: str, source: str, text: str) -> None:
    assert spec_tree().can_transform_core(target, source, Time()) == (False, text)


def test_can_transform_walk_messages() -> None:
    b = spec_tree()
    assert b.can_transform_core("world", "laser", at(2.25)) == (True, "")
    ok, msg = b.can_transform_core("world", "laser", at(5))
    assert not ok
    assert msg == (
        "Lookup would require extrapolation into the future.  Requested time 5.000000 but the "
        "latest data is at time 3.500000, when looking up transform from frame [laser] to frame "
        "[world]"
    )
    assert b.can_transform_full_core("base", at(3.5), "base", at(1.5), "odom") == (True, "")
    ok, msg = b.can_transform_full_core("base", at(3.5), "base", at(1.5), "nosuch")
    assert msg.endswith("canTransform argument fixed_frame - frame does not exist")


def test_python_surface_exception_classes() -> None:
    for cls in (ConnectivityException, LookupException, ExtrapolationException,
                InvalidArgumentException, TimeoutException):  # fmt: skip
        assert cls.__bases__ == (TransformException,)
    assert issubclass(NoDataForExtrapolationException, ExtrapolationException)


# ---------------------------------------------------------------------------------------------
# combinatorial trees (tf2 buffer_core_test "Permuter"): topologies x times x source x target
# ---------------------------------------------------------------------------------------------
TOPOLOGIES: dict[str, list[tuple[str, str]]] = {
    "i": [("a", "b"), ("b", "c"), ("c", "d")],
    "v": [("a", "b"), ("a", "c")],
    "y": [("a", "b"), ("b", "c"), ("b", "d")],
    "ring_45": [("root", f"r{k}") for k in range(8)],
}
SAMPLE_SECONDS = (1.0, 2.0, 3.0, 4.0)
QUERY_SECONDS = (0.0, 1.0, 1.5, 2.25, 4.0)


def edge_motion(
    topology: str, index: int
) -> tuple[np.ndarray, float, float, np.ndarray, np.ndarray, bool]:
    rng = np.random.default_rng(abs(hash((topology, index))) % 2**32)
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    if topology == "ring_45":  # spokes at 45 degree steps around z, 1 m out
        k = index
        return (np.array([0, 0, 1.0]), k * math.pi / 4, 0.1 * (k % 3),
                np.array([math.cos(k * math.pi / 4), math.sin(k * math.pi / 4), 0]),
                np.array([0.0, 0.0, 0.05 * k]), k % 3 == 0)  # fmt: skip
    return (
        axis,
        rng.uniform(-2, 2),
        rng.uniform(-0.5, 0.5),
        rng.normal(size=3),
        rng.normal(size=3),
        index == 1,
    )


def edge_matrix(topology: str, index: int, sec: float) -> np.ndarray:
    axis, phase, rate, t0, t1, static = edge_motion(topology, index)
    if static:
        sec = 0.0
    m = np.eye(4)
    m[:3, :3] = Rotation.from_rotvec(axis * (phase + rate * sec)).as_matrix()
    m[:3, 3] = t0 + t1 * sec
    return m


@cache
def topology_buffer(topology: str) -> BufferCore:
    b = BufferCore()
    for i, (parent, child) in enumerate(TOPOLOGIES[topology]):
        static = edge_motion(topology, i)[5]
        for sec in (0.0,) if static else SAMPLE_SECONDS:
            m = edge_matrix(topology, i, sec)
            q = Rotation.from_matrix(m[:3, :3]).as_quat()
            msg = ts(parent, child, sec, tuple(m[:3, 3]), tuple(q))  # type: ignore[arg-type]
            (b.set_transform_static if static else b.set_transform)(msg, "perm")
    return b


def world_matrix(topology: str, frame: str, sec: float) -> np.ndarray:
    edges = TOPOLOGIES[topology]
    for i, (parent, child) in enumerate(edges):
        if child == frame:
            return world_matrix(topology, parent, sec) @ edge_matrix(topology, i, sec)
    return np.eye(4)


def path_has_dynamic(topology: str, a: str, b: str) -> bool:
    """Whether an edge below the meeting point of a and b is dynamic (then time 0 = 4 s)."""

    def chain(f: str) -> list[tuple[int, str, str]]:  # (edge index, child, parent) up to root
        for i, (p, c) in enumerate(TOPOLOGIES[topology]):
            if c == f:
                return [(i, c, p), *chain(p)]
        return []

    ca, cb = chain(a), chain(b)
    on_a = {a} | {p for _, _, p in ca}
    on_b = {b} | {p for _, _, p in cb}
    common = on_a & on_b
    below = [i for i, c, _ in ca if c not in common] + [i for i, c, _ in cb if c not in common]
    return any(not edge_motion(topology, i)[5] for i in below)


CASES = [
    (topo, sec, s, t)
    for topo, edges in TOPOLOGIES.items()
    for frames in [sorted({f for e in edges for f in e})]
    for sec, s, t in itertools.product(QUERY_SECONDS, frames, frames)
]


@pytest.mark.parametrize(("topology", "sec", "source", "target"), CASES)
def test_permuter(topology: str, sec: float, source: str, target: str) -> None:
    b = topology_buffer(topology)
    r = b.lookup_transform_core(target, source, at(sec))
    used = sec
    if sec == 0.0:
        if source == target:  # identity: the frame's own newest stamp (static/root: 0)
            own = [i for i, (_, c) in enumerate(TOPOLOGIES[topology]) if c == source]
            dyn = bool(own) and not edge_motion(topology, own[0])[5]
        else:
            dyn = path_has_dynamic(topology, source, target)
        used = SAMPLE_SECONDS[-1] if dyn else 0.0
        assert stamp_ns(r) == round(used * S)
    expected = np.linalg.inv(world_matrix(topology, target, used)) @ world_matrix(
        topology, source, used
    )
    np.testing.assert_allclose(trans(r), expected[:3, 3], atol=1e-9)
    got = Rotation.from_quat(rot(r))
    assert got.approx_equal(Rotation.from_matrix(expected[:3, :3]), atol=1e-9)


# ---------------------------------------------------------------------------------------------
# hypothesis properties
# ---------------------------------------------------------------------------------------------
frames_i = st.sampled_from(["a", "b", "c", "d"])
seconds = st.floats(1.0, 4.0)


def as_matrix(m: TransformStamped) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3] = Rotation.from_quat(rot(m)).as_matrix()
    out[:3, 3] = trans(m)
    return out


@given(frames_i, frames_i, seconds)
def test_lookup_inverse_composes_to_identity(a: str, b_: str, sec: float) -> None:
    b = topology_buffer("y")
    t = Time(nanoseconds=round(sec * S))
    m = as_matrix(b.lookup_transform_core(a, b_, t)) @ as_matrix(b.lookup_transform_core(b_, a, t))
    np.testing.assert_allclose(m, np.eye(4), atol=1e-9)


@given(frames_i, frames_i, frames_i, seconds)
def test_two_hops_equal_direct(a: str, mid: str, c: str, sec: float) -> None:
    b = topology_buffer("i")
    t = Time(nanoseconds=round(sec * S))
    two = as_matrix(b.lookup_transform_core(a, mid, t)) @ as_matrix(
        b.lookup_transform_core(mid, c, t)
    )
    np.testing.assert_allclose(two, as_matrix(b.lookup_transform_core(a, c, t)), atol=1e-9)


@given(st.sampled_from(SAMPLE_SECONDS), st.integers(0, 2))
def test_interpolation_at_stored_stamp_returns_stored_value(sec: float, edge: int) -> None:
    b = topology_buffer("i")
    parent, child = TOPOLOGIES["i"][edge]
    r = b.lookup_transform_core(parent, child, at(sec))
    np.testing.assert_allclose(as_matrix(r), edge_matrix("i", edge, sec), atol=1e-12)


def test_result_message_equals_normally_built_message() -> None:
    r: Any = spec_tree().lookup_transform_core("world", "laser", at(2.25))
    rebuilt = TransformStamped()
    rebuilt.header.frame_id = "world"
    rebuilt.header.stamp.sec, rebuilt.header.stamp.nanosec = 2, 250_000_000
    rebuilt.child_frame_id = "laser"
    (
        rebuilt.transform.translation.x,
        rebuilt.transform.translation.y,
        rebuilt.transform.translation.z,
    ) = trans(r)
    q = rebuilt.transform.rotation
    q.x, q.y, q.z, q.w = rot(r)
    assert r == rebuilt
    assert repr(r) == repr(rebuilt)


def test_full_lookup_resolves_each_half_and_stamps_target_time() -> None:
    b = spec_tree()
    # target half (laser <- world) at time 0 resolves to 3.0 s (min of odom 3.0, base 3.5)
    r = b.lookup_transform_full_core("laser", Time(), "odom", at(1.5), "world")
    assert stamp_ns(r) == 3 * S
    t_world_odom_15 = as_matrix(b.lookup_transform_core("world", "odom", at(1.5)))
    t_laser_world_3 = as_matrix(b.lookup_transform_core("laser", "world", at(3)))
    np.testing.assert_allclose(as_matrix(r), t_laser_world_3 @ t_world_odom_15, atol=1e-12)


def test_frame_names_in_id_order() -> None:
    assert spec_tree().get_all_frame_names() == ["map", "world", "odom", "base", "laser"]
