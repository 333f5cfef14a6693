"""Each inlined hot kernel of the lookup engine equals its readable reference bit for bit.

Oracles: the references in ``posekit.tf2.path`` written with ``posekit.tf2._linear_math``
(tf2's LinearMath operations, themselves checked against scipy in test_linear_math.py):

* the accumulation inlined in the path walk (``path._chain``) against ``accumulate``
  (quatRotate + quaternion product), folded over the same edges;
* the interpolation inlined in ``TimeCache.get`` and in ``path._chain`` (with memoised
  slerp terms) against ``interpolate`` (``_linear_math.slerp`` + lerp);
* the unrolled matrix round trip ``canonical`` against ``_linear_math.canonical_quat``;
* ``inverse_compose`` (tf2's finalize) against ``quat_inverse`` / ``quat_rotate`` /
  ``quat_mul``.

Floats are compared by their IEEE bit patterns (so -0.0 differs from 0.0 and NaN equals
itself), on random inputs including non-unit quaternions, signed zeros and opposite signs.
"""

from __future__ import annotations

import math
import struct
from functools import reduce
from typing import Any

from hypothesis import given
from hypothesis import strategies as st

from posekit.tf2._linear_math import canonical_quat, quat_inverse, quat_mul, quat_rotate
from posekit.tf2.path import (
    Edge,
    _chain,
    accumulate,
    canonical,
    interpolate,
    inverse_compose,
)
from posekit.tf2.static_cache import StaticCache
from posekit.tf2.time_cache import TimeCache


def bits(values: Any) -> tuple[int, ...]:
    """The IEEE-754 bit patterns of a sequence of floats."""
    return tuple(struct.unpack("<q", struct.pack("<d", float(v)))[0] for v in values)


_component = st.one_of(
    st.sampled_from([0.0, -0.0, 0.5, -0.5, 1.0, -1.0, 0.3]),
    st.floats(-3.0, 3.0, allow_nan=False, allow_infinity=False),
)
_quat = st.tuples(_component, _component, _component, _component).filter(
    lambda q: sum(c * c for c in q) > 1e-12
)
_unit_quat = _quat.map(lambda q: canonical_quat(q))
_vec = st.tuples(
    *[st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False) | st.just(-0.0)] * 3
)
_sample = st.builds(lambda q, v: (*q, *v), _unit_quat, _vec)


def _static_edge(sample: tuple[float, ...]) -> Edge:
    cache = StaticCache()
    cache.insert(0, 1, sample)  # type: ignore[arg-type]
    return Edge(None, None, None, None, 1, cache)


@given(st.lists(_sample, min_size=1, max_size=6))
def test_inlined_accumulation_equals_accumulate(samples: list[tuple[float, ...]]) -> None:
    """The walk's inlined accumulation (child edge first) equals folding ``accumulate``."""
    chain = tuple(_static_edge(s) for s in samples)
    got = _chain(chain, 5)
    assert got is not None
    want = reduce(lambda acc, e: accumulate(e, acc), samples[1:], samples[0])  # type: ignore[arg-type,return-value]
    assert bits(got) == bits(want)


@given(_sample, _sample, st.integers(1, 999))
def test_inlined_interpolation_equals_reference(
    a: tuple[float, ...], b: tuple[float, ...], step: int
) -> None:
    """TimeCache.get and the path walk interpolate exactly as ``interpolate`` does, on the
    first evaluation (slerp terms computed) and on the second (terms memoised)."""
    t0, t1 = 10_000, 11_000
    t = t0 + step
    ratio = (t - t0) / (t1 - t0)
    want = interpolate(a, b, ratio)  # type: ignore[arg-type]
    cache = TimeCache()
    cache.insert(t0, 1, a)  # type: ignore[arg-type]
    cache.insert(t1, 1, b)  # type: ignore[arg-type]
    edge = Edge(cache.stamps, cache.parents, cache.data, cache._iv, 1, None)
    for _ in range(2):
        parent, got = cache.get(t)
        assert parent == 1
        assert bits(got) == bits(want)
        from_path = _chain((edge,), t)
        assert from_path is not None
        assert bits(from_path) == bits(want)


@given(_quat)
def test_unrolled_round_trip_equals_canonical_quat(q: tuple[float, float, float, float]) -> None:
    assert bits(canonical(q)) == bits(canonical_quat(q))


@given(_sample, st.one_of(st.none(), _sample))
def test_inverse_compose_equals_linear_math(
    target: tuple[float, ...], source: tuple[float, ...] | None
) -> None:
    """finalize: q = conj(q_t) * q_s, v = rotate(conj(q_t), v_s) + rotate(conj(q_t), -v_t)."""
    inv = quat_inverse(target[:4])  # type: ignore[arg-type]
    a = quat_rotate(inv, (-target[4], -target[5], -target[6]))
    got = inverse_compose(target, source)  # type: ignore[arg-type]
    if source is None:
        want = (*inv, *a)
    else:
        b = quat_rotate(inv, source[4:])  # type: ignore[arg-type]
        want = (*quat_mul(inv, source[:4]), b[0] + a[0], b[1] + a[1], b[2] + a[2])  # type: ignore[arg-type]
    assert bits(got) == bits(want)


def test_bits_tells_signed_zeros_apart() -> None:
    """The comparison used above is strict: it would catch a kernel that loses a sign."""
    assert bits([0.0]) != bits([-0.0])
    assert bits([math.nan]) == bits([math.nan])
