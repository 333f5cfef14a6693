"""The single-lookup fast path (cached walk) is bit-identical to the general walk.

Reference: the same buffer contents in a BufferCore whose path cache is disabled, so every
lookup runs the general walk (``_walk``). Random trees mix dynamic and static edges, samples
re-parented between stamps, equal and opposite rotations, and query times inside, on and
outside the stored stamps (0 = latest); results are compared by their float bit patterns and
errors by type and text. Lookups are repeated after further inserts (re-parenting, new
frames) so stale cached paths are exercised too.
"""

from __future__ import annotations

import math
from typing import Any

from hypothesis import given

from _support.tf2_trees import apply as _apply
from _support.tf2_trees import msg as _msg
from _support.tf2_trees import scene as _scene
from posekit.tf2 import BufferCore, TransformException

S = 1_000_000_000


class _GeneralOnly(BufferCore):
    """Reference: never caches a path, so every lookup takes the general walk."""

    def _build_path(self, tid: int, sid: int) -> None:
        return None


def _bits(res: Any) -> tuple[Any, ...]:
    tr = res.transform
    floats = (
        tr.translation.x,
        tr.translation.y,
        tr.translation.z,
        tr.rotation.x,
        tr.rotation.y,
        tr.rotation.z,
        tr.rotation.w,
    )
    return (
        res.header.frame_id,
        res.child_frame_id,
        res.header.stamp.sec,
        res.header.stamp.nanosec,
        tuple(float.hex(f) for f in floats),
    )


def _outcome(core: BufferCore, target: str, source: str, t: int) -> tuple[Any, ...]:
    try:
        return ("ok", _bits(core.lookup_transform_core(target, source, t)))
    except TransformException as exc:
        return ("error", type(exc).__name__, str(exc))


@given(_scene(), _scene())
def test_fast_path_bit_identical_to_general_walk(
    scene: tuple[list[tuple[Any, bool]], list[int], int],
    later: tuple[list[tuple[Any, bool]], list[int], int],
) -> None:
    inserts, times, n = scene
    fast, general = BufferCore(), _GeneralOnly()
    _apply([fast, general], inserts)
    names = [f"f{i}" for i in range(n)]
    pairs = [(a, b) for a in names for b in names if a != b]
    for _ in range(2):  # the first round builds the paths, the second uses them
        for target, source in pairs:
            for t in times:
                assert _outcome(fast, target, source, t) == _outcome(general, target, source, t)
    # more data (re-parenting, new frames, static/dynamic switches) after paths are cached
    _apply([fast, general], later[0])
    names = [f"f{i}" for i in range(max(n, later[2]))]
    for target, source in [(a, b) for a in names for b in names if a != b]:
        for t in times:
            assert _outcome(fast, target, source, t) == _outcome(general, target, source, t)


def test_fast_path_is_taken_on_a_chain() -> None:
    """The benchmark's shape (a dynamic chain) is served by a cached path, not the fallback."""
    core = BufferCore()
    for i in range(4):
        for k in range(3):
            yaw = 0.1 * k + i
            q = (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))
            core.set_transform(
                _msg(f"f{i}", f"f{i + 1}", 10 * S + k * S // 10, q, (1.0, 0, 0)), "t"
            )
    reference = _GeneralOnly()
    for i in range(4):
        for k in range(3):
            yaw = 0.1 * k + i
            q = (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))
            msg = _msg(f"f{i}", f"f{i + 1}", 10 * S + k * S // 10, q, (1.0, 0, 0))
            reference.set_transform(msg, "t")
    t = 10 * S + S // 7
    for target, source in (("f0", "f4"), ("f4", "f0"), ("f2", "f4")):
        core.lookup_transform_core(target, source, t)
        assert (target, source) in core._paths
        for when in (t, 0):
            want = _outcome(reference, target, source, when)
            assert want[0] == "ok"
            assert _outcome(core, target, source, when) == want
        assert (target, source) in core._paths  # still cached: the fast path served it


@given(_scene(), _scene())
def test_memoised_answers_equal_the_general_walk(
    scene: tuple[list[tuple[Any, bool]], list[int], int],
    later: tuple[list[tuple[Any, bool]], list[int], int],
) -> None:
    """A cached path remembers its last answer; asking the same question again on unchanged
    data returns it, and any insert (here: further data on the same frames) forgets it."""
    inserts, times, n = scene
    fast, general = BufferCore(), _GeneralOnly()
    _apply([fast, general], inserts)
    names = [f"f{i}" for i in range(max(n, later[2]))]
    pairs = [(a, b) for a in names for b in names if a != b]

    def check_all(order: list[int]) -> None:
        for target, source in pairs:
            for t in order:
                want = _outcome(general, target, source, t)
                for _ in range(3):  # build the path, evaluate it, then answer from the memo
                    assert _outcome(fast, target, source, t) == want

    check_all(times)
    _apply([fast, general], later[0])
    check_all(times[::-1])  # first the question each memo holds, on changed data


def test_memo_is_forgotten_on_every_change() -> None:
    """Insert, clear() and forget_frames() each drop the remembered answer; a caller editing
    the returned message does not change the next answer."""
    core = BufferCore()
    for k in range(3):
        core.set_transform(_msg("a", "b", 10 * S + k * S, (0.0, 0.0, 0.0, 1.0), (k, 0, 0)), "t")
    t = 10 * S + S // 2
    for _ in range(3):
        got = core.lookup_transform_core("a", "b", t)
    assert got.transform.translation.x == 0.5
    got.transform.translation.x = 99.0
    got.header.stamp.sec = 0
    again = core.lookup_transform_core("a", "b", t)
    assert again.transform.translation.x == 0.5
    assert again.header.stamp.sec == 10
    # a sample inserted between the two used ones changes the interpolation at t
    core.set_transform(_msg("a", "b", t - S // 4, (0.0, 0.0, 0.0, 1.0), (5.0, 0, 0)), "t")
    # now between (10.25 s, x=5) and (11 s, x=1): 5 + (1 - 5) * 0.25 / 0.75
    assert math.isclose(core.lookup_transform_core("a", "b", t).transform.translation.x, 11 / 3)
    latest = core.lookup_transform_core("a", "b", 0)
    assert latest.transform.translation.x == 2.0
    core.set_transform(_msg("a", "b", 13 * S, (0.0, 0.0, 0.0, 1.0), (7.0, 0, 0)), "t")
    assert core.lookup_transform_core("a", "b", 0).transform.translation.x == 7.0
    core.clear()
    try:
        core.lookup_transform_core("a", "b", 0)
    except TransformException:
        pass
    else:
        raise AssertionError("lookup after clear() must fail")
    core.set_transform(_msg("a", "b", 20 * S, (0.0, 0.0, 0.0, 1.0), (1.0, 0, 0)), "t")
    core.set_transform(_msg("b", "c", 20 * S, (0.0, 0.0, 0.0, 1.0), (1.0, 0, 0)), "t")
    assert core.lookup_transform_core("a", "c", 0).transform.translation.x == 2.0
    assert core.lookup_transform_core("a", "c", 0).transform.translation.x == 2.0
    core.forget_frames(["c"])
    try:
        core.lookup_transform_core("a", "c", 0)
    except TransformException:
        pass
    else:
        raise AssertionError("lookup of a forgotten frame must fail")


class _EagerDrop(_GeneralOnly):
    """Reference for the batched drop: old samples leave at every insert, as in tf2."""

    def set_transform(self, transform: Any, authority: str) -> bool:
        ok = super().set_transform(transform, authority)
        with self._lock:
            self._prune_pending()
        return ok


def test_cached_paths_never_see_samples_older_than_the_window() -> None:
    """The window's old samples are dropped in batches; lookups through cached paths (which
    read the cache lists directly) answer and fail exactly as with a drop at every insert."""
    fast, reference = BufferCore(1 * S), _EagerDrop(1 * S)
    for k in range(300):
        for core in (fast, reference):
            for parent, child in (("a", "b"), ("b", "c")):
                q = (0.0, 0.0, math.sin(0.01 * k), math.cos(0.01 * k))
                core.set_transform(_msg(parent, child, 5 * S + k * S // 100, q, (k, 1.0, 0.0)),
                                   "t")
        if k % 7 == 0 and k > 2:
            cache = reference._caches[reference._ids["c"]]
            assert cache is not None
            oldest = cache.oldest_stamp()
            for t in (oldest - 1, oldest, oldest + S // 300, 0):
                for target, source in (("a", "c"), ("c", "a")):
                    want = _outcome(reference, target, source, t)
                    assert _outcome(fast, target, source, t) == want
    assert ("a", "c") in fast._paths  # answered by the cached path throughout
