"""lookup_transforms (vectorised) must equal a loop of single lookups, errors included."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from posekit.msgs.geometry_msgs import TransformStamped
from posekit.tf2 import (
    BufferCore,
    ConnectivityException,
    ExtrapolationException,
    InvalidArgumentException,
)

S = 1_000_000_000


def ts(parent: str, child: str, ns: int, t: tuple[float, ...], yaw: float) -> TransformStamped:
    m = TransformStamped()
    m.header.frame_id = parent
    m.child_frame_id = child
    m.header.stamp.sec, m.header.stamp.nanosec = divmod(ns, S)
    m.transform.translation.x, m.transform.translation.y, m.transform.translation.z = t
    m.transform.rotation.x = 0.3 * math.sin(yaw / 2)
    m.transform.rotation.z = math.sin(yaw / 2)
    m.transform.rotation.w = math.cos(yaw / 2)
    return m


def y_tree() -> BufferCore:
    """a -> b -> {c, d}; b->c static, others dynamic with 50 samples 1.00 .. 1.98 s."""
    b = BufferCore()
    for i in range(50):
        ns = S + i * 20_000_000
        b.set_transform(ts("a", "b", ns, (i * 0.1, 1, 0), 0.05 * i), "n")
        b.set_transform(ts("b", "d", ns + 7, (0, -i * 0.05, 2), -0.11 * i + 3), "n")
    b.set_transform_static(ts("b", "c", 0, (0.5, 0, 0), 2.5), "n")
    return b


TREE = y_tree()
FRAMES = ["a", "b", "c", "d"]


def singles(b: BufferCore, target: str, source: str, times: np.ndarray) -> tuple[np.ndarray, ...]:
    v = np.empty((len(times), 3))
    q = np.empty((len(times), 4))
    for i, t in enumerate(times):
        r = b.lookup_transform_core(target, source, int(t))
        tr, ro = r.transform.translation, r.transform.rotation
        v[i] = (tr.x, tr.y, tr.z)
        q[i] = (ro.x, ro.y, ro.z, ro.w)
    return v, q


stamps = st.lists(st.integers(S + 7, S + 49 * 20_000_000), min_size=1, max_size=40)


@given(st.sampled_from(FRAMES), st.sampled_from(FRAMES), stamps)
def test_batch_equals_singles(target: str, source: str, times: list[int]) -> None:
    arr = np.array(times, dtype=np.int64)
    v, q = TREE.lookup_transforms(target, source, arr)
    ev, eq = singles(TREE, target, source, arr)
    np.testing.assert_allclose(v, ev, atol=1e-12, rtol=0)
    np.testing.assert_allclose(q, eq, atol=1e-12, rtol=0)


def test_exact_stamps_latest_and_zero_entries() -> None:
    ab = S + np.arange(50, dtype=np.int64) * 20_000_000  # a->b stamps; b->d are 7 ns later
    arr = np.concatenate([ab[1:], ab[:-1] + 7, [0]])
    for target, source in [("a", "d"), ("c", "d"), ("d", "c")]:
        v, q = TREE.lookup_transforms(target, source, arr)
        ev, eq = singles(TREE, target, source, arr)
        np.testing.assert_allclose(v, ev, atol=1e-12, rtol=0)
        np.testing.assert_allclose(q, eq, atol=1e-12, rtol=0)


def test_many_stamps_across_chunks() -> None:
    arr = np.linspace(S + 7, S + 49 * 20_000_000, 20_001).astype(np.int64)
    v, q = TREE.lookup_transforms("c", "d", arr)
    pick = np.arange(0, len(arr), 997)
    ev, eq = singles(TREE, "c", "d", arr[pick])
    np.testing.assert_allclose(v[pick], ev, atol=1e-12, rtol=0)
    np.testing.assert_allclose(q[pick], eq, atol=1e-12, rtol=0)
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-12)


def test_first_failing_stamp_is_named() -> None:
    arr = np.array([S + 10**8, 5 * S, S // 2], dtype=np.int64)
    with pytest.raises(ExtrapolationException) as e:
        TREE.lookup_transforms("a", "d", arr)
    single = pytest.raises(ExtrapolationException)
    with single as s:
        TREE.lookup_transform_core("a", "d", 5 * S)
    assert (
        str(e.value) == f"{s.value} (first failing stamp: times_ns[1] = {5 * S}, used 5.000000 s)"
    )
    assert e.value.index == 1  # type: ignore[attr-defined]
    assert e.value.stamp_ns == 5 * S  # type: ignore[attr-defined]


def test_connectivity_and_validation() -> None:
    b = y_tree()
    b.set_transform_static(ts("x", "y", 0, (0, 0, 0), 0), "n")
    with pytest.raises(ConnectivityException, match=r"times_ns\[0\]"):
        b.lookup_transforms("a", "y", np.array([S + 10**8]))
    with pytest.raises(ConnectivityException, match=r"times_ns\[1\]"):
        b.lookup_transforms("a", "y", np.array([S, 0]))
    with pytest.raises(InvalidArgumentException):
        b.lookup_transforms("", "y", np.array([S]))
    with pytest.raises(TypeError):
        b.lookup_transforms("a", "d", np.array([1.5]))
    with pytest.raises(ValueError, match="1-D"):
        b.lookup_transforms("a", "d", np.zeros((2, 2), dtype=np.int64))


def test_identity_and_empty() -> None:
    v, q = TREE.lookup_transforms("nosuch", "nosuch", np.array([1, 2, 3]))
    assert v.shape == (3, 3)
    np.testing.assert_array_equal(q, np.tile([0, 0, 0, 1.0], (3, 1)))
    v, q = TREE.lookup_transforms("a", "d", np.array([], dtype=np.int64))
    assert (v.shape, q.shape) == ((0, 3), (0, 4))


def test_reparenting_inside_batch_equals_singles() -> None:
    b = BufferCore()
    for i in range(10):
        b.set_transform(ts("odom", "base", S + i * S // 10, (i, 0, 0), 0.1 * i), "n")
    b.set_transform(ts("map", "base", 2 * S, (9, 9, 0), 1.0), "n")
    b.set_transform(ts("map", "base", 3 * S, (8, 9, 0), 1.2), "n")
    b.set_transform_static(ts("map", "odom", 0, (1, 0, 0), 0.5), "n")
    arr = np.linspace(S, 3 * S, 41).astype(np.int64)
    v, q = b.lookup_transforms("map", "base", arr)
    ev, eq = singles(b, "map", "base", arr)
    np.testing.assert_allclose(v, ev, atol=1e-12, rtol=0)
    np.testing.assert_allclose(q, eq, atol=1e-12, rtol=0)


def test_stale_edge_above_meeting_point_and_failing_target_edge() -> None:
    b = BufferCore()
    b.set_transform(ts("root", "a", S, (0, 0, 0), 0), "n")  # stale: only at 1 s
    for k in (4, 6):
        b.set_transform(ts("a", "s", k * S, (k, 0, 0), 0.1 * k), "n")
        b.set_transform(ts("a", "t", k * S, (0, k, 0), -0.1 * k), "n")
    arr = np.array([4 * S, 5 * S, 6 * S])
    v, _ = b.lookup_transforms("t", "s", arr)
    ev, _ = singles(b, "t", "s", arr)
    np.testing.assert_allclose(v, ev, atol=1e-12, rtol=0)
    # target = a is on the source path and its own edge (to root) has no data at 5 s: fine
    v, _ = b.lookup_transforms("a", "s", arr)
    np.testing.assert_allclose(v[:, 0], [4, 5, 6], atol=1e-12)


def test_duplicates_at_oldest_and_middle_stamps_sorted_and_shuffled() -> None:
    b = BufferCore()
    for ns, x, yaw in [(S, 1, 0.1), (S, 2, 0.2), (S + S // 2, 7, 0.7), (S + S // 2, 8, 0.8),
                       (2 * S, 5, 0.5)]:  # fmt: skip
        b.set_transform(ts("p", "c", ns, (x, 0, 0), yaw), "n")
    arr = np.array([S, S, S + S // 4, S + S // 2, S + 3 * S // 4, 2 * S, 2 * S], dtype=np.int64)
    rng = np.random.default_rng(3)
    for times in (arr, rng.permutation(arr)):
        v, q = b.lookup_transforms("p", "c", times)
        ev, eq = singles(b, "p", "c", times)
        np.testing.assert_allclose(v, ev, atol=1e-12, rtol=0)
        np.testing.assert_allclose(q, eq, atol=1e-12, rtol=0)
    v, _ = b.lookup_transforms("p", "c", arr)
    np.testing.assert_allclose(v[:4, 0], [1, 1, 4.5, 8])  # docs/specs/tf2.md 3.1 duplicate model
