"""The compiled kernels (``posekit.tf2._accel``) give bit-identical results to pure Python.

Oracle: the pure-Python policy in ``posekit.tf2.path`` (itself checked against the reference
walk in test_fast_paths.py and against tf2's LinearMath in test_kernels.py), run on the same
random inputs. Compared bit for bit (IEEE patterns of every float, ints, the slerp memo each
leaves in the caches):

* ``evaluate`` on the cached path of every frame pair of random trees (dynamic and static
  edges, re-parented samples, signed zeros), at times inside, on and outside the stamps, with
  huge and negative times;
* ``sample_from_msg`` against ``BufferCore._checked_sample`` (tf2's checks and the matrix
  round trip) on random messages: where the compiled one answers it must agree, and it must
  answer every ordinary valid message;
* ``stamped`` against ``stamped_python``: equal messages of the same classes.

Where the extension was not built (no C compiler at install time) the module is skipped and
says so; ``posekit.tf2.path.accelerated`` then is False and everything runs in Python.
"""

from __future__ import annotations

import math
import struct
import subprocess
import sys
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from _support.tf2_trees import apply, scene
from posekit.msgs.geometry_msgs import TransformStamped
from posekit.tf2 import BufferCore, path
from posekit.tf2.buffer_core import MAX_GRAPH_DEPTH

accel = pytest.importorskip(
    "posekit.tf2._accel", reason="posekit.tf2._accel was not built (no C compiler at install)"
)


def bits(values: Any) -> tuple[Any, ...]:
    """Ints as they are, floats as IEEE-754 bit patterns, nested tuples and None kept."""
    if values is None:
        return (None,)
    out: list[Any] = []
    for v in values:
        if isinstance(v, float):
            out.append(("f", struct.unpack("<q", struct.pack("<d", v))[0]))
        elif isinstance(v, tuple):
            out.append(bits(v))
        else:
            out.append((type(v).__name__, v))
    return tuple(out)


def _memo(core: BufferCore) -> list[Any]:
    return [bits(iv) if iv is not None else None
            for cache in core._caches if cache is not None and not cache.is_static
            for iv in cache._iv]  # fmt: skip


def test_selected_automatically() -> None:
    assert path.accelerated
    assert path.evaluate is accel.evaluate
    assert path.stamped is accel.stamped
    assert path.sample_from_msg is accel.sample_from_msg


def test_pure_python_can_be_forced() -> None:
    code = ("from posekit.tf2 import path; "
            "print(path.accelerated, path.evaluate is path.evaluate_python)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, timeout=60,
                         env={"POSEKIT_PURE_PYTHON": "1", "PATH": "/usr/bin:/bin"})
    assert out.stdout.split() == ["False", "True"]


_EXTRA_TIMES = [1, -5, 2**62 + 3, -(2**63), 2**80, 10 * 10**9 + 2**53]


@given(scene(), scene())
def test_evaluate_bit_identical_to_python(
    first: tuple[list[tuple[Any, bool]], list[int], int],
    later: tuple[list[tuple[Any, bool]], list[int], int],
) -> None:
    compiled, python = BufferCore(), BufferCore()  # same data; each fills its own slerp memo
    apply([compiled, python], first[0])
    for stage in range(2):
        n = max(first[2], later[2])
        for tid in range(1, n + 1):
            for sid in range(1, n + 1):
                if tid == sid or tid >= len(compiled._caches) or sid >= len(compiled._caches):
                    continue
                pc = path.build_path(compiled._caches, tid, sid, MAX_GRAPH_DEPTH)
                pp = path.build_path(python._caches, tid, sid, MAX_GRAPH_DEPTH)
                assert (pc is None) == (pp is None)
                if pc is None or pp is None:
                    continue
                for t in [*first[1], *_EXTRA_TIMES]:
                    got = accel.evaluate(pc.mode, pc.up, pc.down, pc.check, t)
                    want = path.evaluate_python(pp.mode, pp.up, pp.down, pp.check, t)
                    if got is not None:  # the compiled one may only decline more often
                        assert bits(got) == bits(want)
                    elif abs(t) < 2**53:  # ...and only where its integers run out
                        assert want is None
        assert _memo(compiled) == _memo(python)
        if stage == 0:
            apply([compiled, python], later[0])


def test_evaluate_answers_the_common_case() -> None:
    """Not vacuous: a 4-edge chain between samples is answered, and equals Python."""
    core = BufferCore()
    for e in range(4):
        for k in range(3):
            q = (0.0, 0.0, math.sin(0.1 * k + e), math.cos(0.1 * k + e))
            core.set_transform(_msg(f"f{e}", f"f{e + 1}", 10**10 + k * 10**8, q, (1.0, -0.0, e)),
                               "t")
    for tid, sid in ((1, 5), (5, 1), (3, 5), (2, 4)):
        p = path.build_path(core._caches, core._ids[f"f{tid - 1}"], core._ids[f"f{sid - 1}"],
                            MAX_GRAPH_DEPTH)
        assert p is not None
        t = 10**10 + 123_456_789
        got = accel.evaluate(p.mode, p.up, p.down, p.check, t)
        assert got is not None
        assert bits(got) == bits(path.evaluate_python(p.mode, p.up, p.down, p.check, t))


def _msg(parent: Any, child: Any, ns: int, q: Any, v: Any, sec: Any = None,
         nanosec: Any = None) -> TransformStamped:
    m = TransformStamped()
    m.header.frame_id = parent
    m.child_frame_id = child
    m.header.stamp.sec, m.header.stamp.nanosec = divmod(ns, 10**9)
    if sec is not None:
        m.header.stamp.sec = sec
    if nanosec is not None:
        m.header.stamp.nanosec = nanosec
    r = m.transform.rotation
    r.x, r.y, r.z, r.w = q
    tr = m.transform.translation
    tr.x, tr.y, tr.z = v
    return m


_float = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 1.0, -1.0, 0.5, 1e-200, 1e200, math.inf, math.nan]),
    st.integers(-3, 3),
)
_name = st.sampled_from(["a", "b", "/a", "", "base_link", "//x"])
_sec = st.one_of(st.none(), st.sampled_from([-(2**31), 2**31 - 1, 2**31, -1, 1.5, True]))
_nanosec = st.one_of(st.none(), st.sampled_from([0, 2**32 - 1, 2**32, -1]))


@given(st.tuples(_float, _float, _float, _float), st.tuples(_float, _float, _float), _name,
       _name, st.integers(0, 2**62), _sec, _nanosec)
def test_sample_from_msg_agrees_with_the_checked_conversion(
    q: Any, v: Any, parent: str, child: str, ns: int, sec: Any, nanosec: Any
) -> None:
    m = _msg(parent, child, ns, q, v, sec, nanosec)
    got = accel.sample_from_msg(m)
    if got is None:
        return  # declined: BufferCore runs the checked conversion itself
    want = BufferCore()._checked_sample(m, "test")
    assert want is not None
    assert bits(got) == bits(want)


@given(st.tuples(*[st.floats(-10, 10)] * 4).filter(lambda q: sum(c * c for c in q) > 1e-6),
       st.tuples(*[st.floats(-1e6, 1e6)] * 3), st.integers(0, 2**62 - 1))
def test_sample_from_msg_answers_every_ordinary_message(q: Any, v: Any, ns: int) -> None:
    m = _msg("odom", "base_link", ns % (2**31 * 10**9), q, v)
    got = accel.sample_from_msg(m)
    assert got is not None
    assert bits(got) == bits(BufferCore()._checked_sample(m, "test"))


@given(st.tuples(st.integers(-(2**31), 2**31), st.integers(0, 10**9 - 1),
                 *[st.floats(allow_nan=True)] * 7))
def test_stamped_equals_python(result: Any) -> None:
    got = accel.stamped("map", "base", result)
    want = path.stamped_python("map", "base", result)
    for a, b in ((got, want), (got.header, want.header), (got.header.stamp, want.header.stamp),
                 (got.transform, want.transform), (got.transform.rotation,
                                                    want.transform.rotation),
                 (got.transform.translation, want.transform.translation)):
        assert type(a) is type(b)
    for msg in (got, want):
        tr = msg.transform
        assert bits((msg.header.stamp.sec, msg.header.stamp.nanosec, tr.rotation.x,
                     tr.rotation.y, tr.rotation.z, tr.rotation.w, tr.translation.x,
                     tr.translation.y, tr.translation.z)) == bits(result)
    assert (got.header.frame_id, got.child_frame_id) == (want.header.frame_id,
                                                          want.child_frame_id)
    got.transform.translation.x = 7.0  # a fresh message: editing it touches nothing shared
    assert accel.stamped("map", "base", result).transform.translation.x is result[6]


def test_stamped_refuses_a_wrong_result() -> None:
    with pytest.raises(TypeError):
        accel.stamped("a", "b", (1, 2))
