"""The path between two frames, and how it is evaluated (tf2's ``walkToTopParent``, cached).

tf2 answers a lookup by walking from the source and from the target up to their common
ancestor, accumulating each edge's parent_T_child (``TransformAccum``), and combining the two
halves. :meth:`posekit.tf2.BufferCore._walk` is that walk, written to be read; it is the
reference for every value and every error. This module is the fast way to the same answer:

* **The path is one object.** A :class:`FramePath` lists the edges a lookup from ``source``
  to ``target`` visits (each an :class:`Edge`: the cache's sample lists and the parent the
  edge must have), built once from the newest parents and cached per (target, source) pair.
  The buffer empties its path cache whenever the tree's structure can change (a cache is
  created or replaced, frames are forgotten).
* **Evaluating it is a policy.** :func:`evaluate` answers a single lookup (scalar floats),
  ``posekit.tf2.batch`` evaluates the same walk for many stamps on numpy columns, and
  ``can_transform`` asks whether evaluation succeeds. Every policy declines (returns
  ``None``) whenever the path does not apply at the asked time: a sample with another parent,
  a time outside the common cases, anything that could raise. The caller then runs the
  reference walk, which decides. Evaluation only reads (plus the slerp memo that
  :meth:`TimeCache.get` fills too), so declining is always safe.
* **Hot kernels are inlined next to their reference.** :func:`accumulate` (one edge appended
  to a chain), :func:`interpolate` (tf2's lerp + slerp between two samples) and
  :func:`canonical` (tf2's ``Matrix3x3`` round trip of a quaternion) are written plainly in
  terms of :mod:`posekit.tf2._linear_math`; :func:`evaluate_python` and ``TimeCache.get`` use
  inlined copies of them. ``tests/tf2/test_kernels.py`` checks each inlined copy against its
  reference bit for bit, on random inputs.

Where a C compiler was present at install time, :mod:`posekit.tf2._accel` provides
:func:`evaluate`, :func:`stamped` and :func:`sample_from_msg` with the same IEEE operations
in the same order (``tests/tf2/test_accel.py`` compares them with the Python versions bit
for bit); it is selected at import, and ``POSEKIT_PURE_PYTHON=1`` turns it off.
"""

from __future__ import annotations

import math
import os
from bisect import bisect_right
from collections.abc import Callable, Sequence
from typing import Any, NamedTuple

from posekit.msgs.builtin_interfaces import Time as TimeMsg
from posekit.msgs.geometry_msgs import Quaternion, Transform, TransformStamped, Vector3
from posekit.msgs.std_msgs import Header
from posekit.tf2._linear_math import quat_mul, quat_rotate, slerp
from posekit.tf2.static_cache import StaticCache
from posekit.tf2.time_cache import Sample, TimeCache, slerp_terms

__all__ = [
    "DOWN",
    "FULL",
    "UP",
    "Edge",
    "FramePath",
    "Result",
    "accelerated",
    "accumulate",
    "build_path",
    "canonical",
    "evaluate",
    "evaluate_python",
    "interpolate",
    "latest_up",
    "result_python",
    "sample_from_msg",
    "stamped",
    "stamped_python",
]

_sqrt = math.sqrt
_sin = math.sin
_NS = 1_000_000_000

#: Walk shapes: the target is an ancestor of the source (or the top of its tree), the source
#: is an ancestor of the target, or both walk up to a common top.
UP = 0
DOWN = 1
FULL = 2

#: A finished lookup: (stamp sec, stamp nanosec, qx, qy, qz, qw, vx, vy, vz), the quaternion
#: after tf2's matrix round trip.
Result = tuple[int, int, float, float, float, float, float, float, float]


class Edge(NamedTuple):
    """One edge of a path: child frame -> ``parent``, at evaluation time.

    For a dynamic edge, the child's :class:`TimeCache` lists (mutated in place by inserts,
    never replaced while the path is cached); for a static edge, ``stamps`` is None and the
    values are read from ``static``.
    """

    stamps: list[int] | None
    # list[int], list[Sample] and list[slerp terms or None] of a dynamic edge, else None;
    # typed Any so the hot loop needs no narrowing
    parents: Any
    samples: Any
    slerp_memo: Any
    parent: int
    static: StaticCache | None


class FramePath:
    """The walk from ``source_id`` to ``target_id``: its shape and edges.

    ``up`` holds the source's edges in walk order (child first); for ``DOWN`` and ``FULL``
    paths ``down`` holds the target's. ``check`` is an edge that must merely evaluate (the
    target's own edge on an ``UP`` path whose target is not the top, where tf2's walk looks
    it up before it stops; the source's edge on a ``DOWN`` path likewise). ``memo`` is None or
    (buffer version, requested time, :data:`Result`) of the last answer given.
    """

    __slots__ = ("check", "down", "memo", "mode", "source_id", "target_id", "up")

    def __init__(
        self,
        mode: int,
        up: tuple[Edge, ...],
        down: tuple[Edge, ...],
        check: Edge | None,
        target_id: int,
        source_id: int,
    ) -> None:
        self.mode = mode
        self.up = up
        self.down = down
        self.check = check
        self.target_id = target_id
        self.source_id = source_id
        self.memo: tuple[int, int, Result] | None = None


def _newest_edge(caches: Sequence[TimeCache | StaticCache | None], frame: int) -> Edge | None:
    """The edge from ``frame`` to its newest parent, None without data or parent."""
    cache = caches[frame]
    if cache is None:
        return None
    parent = cache.latest_time_and_parent()[1]
    if parent == 0:
        return None
    if isinstance(cache, TimeCache):
        return Edge(cache.stamps, cache.parents, cache.data, cache._iv, parent, None)
    return Edge(None, None, None, None, parent, cache)


def build_path(caches: Sequence[TimeCache | StaticCache | None], tid: int, sid: int,
               max_depth: int) -> FramePath | None:
    """The path from the newest parents, or None where no cached path can serve the pair.

    None for an edge without data or a walk longer than ``max_depth``: the reference walk
    decides.
    """
    up: list[Edge] = []
    frame = sid
    while True:
        if len(up) >= max_depth:
            return None
        if caches[frame] is None:
            top = frame
            break
        e = _newest_edge(caches, frame)
        if e is None:
            return None
        if frame == tid:  # target is an ancestor: its own edge must only evaluate
            return FramePath(UP, tuple(up), (), e, tid, sid)
        up.append(e)
        frame = e.parent
    if top == tid:
        return FramePath(UP, tuple(up), (), None, tid, sid)
    down: list[Edge] = []
    frame = tid
    while frame != top:
        if len(down) >= max_depth:
            return None
        e = _newest_edge(caches, frame)
        if e is None:
            return None
        if frame == sid:  # source is an ancestor of the target
            return FramePath(DOWN, tuple(up), tuple(down), e, tid, sid)
        down.append(e)
        frame = e.parent
    return FramePath(FULL, tuple(up), tuple(down), None, tid, sid)


def latest_up(chain: tuple[Edge, ...]) -> int:
    """tf2's latest common time when the target is an ancestor of the source, else -1.

    The oldest of the chain's newest non-zero stamps (0 if none), provided every edge's newest
    sample has the cached parent, which is when getLatestCommonTime walks exactly this chain.
    """
    common = -1
    for stamps, parents, _, _, expected, static in chain:
        if stamps is None:
            if static is None or static.parent != expected:
                return -1
        elif not stamps or parents is None or parents[-1] != expected:
            return -1
        else:
            stamp = stamps[-1]
            if stamp != 0 and (common < 0 or stamp < common):
                common = stamp
    return common if common >= 0 else 0


# ----------------------------------------------------------------------------------------------
# reference kernels (readable; the inlined copies below must equal them bit for bit)
# ----------------------------------------------------------------------------------------------
def accumulate(edge: Sample, chain: Sample) -> Sample:
    """tf2 ``TransformAccum::accum``: the edge parent_T_child appended to the chain.

    The chain child_T_source becomes parent_T_source: ``v = quatRotate(q_e, v) + t_e``, ``q =
    q_e * q``.
    """
    q_e, t_e = edge[:4], edge[4:]
    v = quat_rotate(q_e, chain[4:])
    q = quat_mul(q_e, chain[:4])
    return (q[0], q[1], q[2], q[3], v[0] + t_e[0], v[1] + t_e[1], v[2] + t_e[2])


def interpolate(a: Sample, b: Sample, ratio: float) -> Sample:
    """tf2's interpolation of two samples (``TimeCache::interpolate``).

    tf2 ``slerp`` of the rotations, component-wise lerp ``(1 - ratio) * a + ratio * b`` of the
    translations.
    """
    u = 1.0 - ratio
    q = slerp(a[:4], b[:4], ratio)
    return (q[0], q[1], q[2], q[3], u * a[4] + ratio * b[4], u * a[5] + ratio * b[5],
            u * a[6] + ratio * b[6])  # fmt: skip


def canonical(q: tuple[float, float, float, float]) -> tuple[float, float, float, float]:
    """tf2 ``Transform::setRotation`` then ``getRotation``: unit norm, canonical sign.

    Inlined (every getRotation branch unrolled); reference
    :func:`posekit.tf2._linear_math.canonical_quat`.
    """
    x, y, z, w = q
    d = x * x + y * y + z * z + w * w
    s = 2.0 / d
    xs, ys, zs = x * s, y * s, z * s
    wx, wy, wz = w * xs, w * ys, w * zs
    xx, xy, xz = x * xs, x * ys, x * zs
    yy, yz, zz = y * ys, y * zs, z * zs
    trace = (1.0 - (yy + zz)) + (1.0 - (xx + zz)) + (1.0 - (xx + yy))
    if trace > 0.0:
        s = _sqrt(trace + 1.0)
        qw = s * 0.5
        s = 0.5 / s
        return (
            ((yz + wx) - (yz - wx)) * s,
            ((xz + wy) - (xz - wy)) * s,
            ((xy + wz) - (xy - wz)) * s,
            qw,
        )
    m00 = 1.0 - (yy + zz)
    m11 = 1.0 - (xx + zz)
    m22 = 1.0 - (xx + yy)
    m01, m10 = xy - wz, xy + wz
    m02, m20 = xz + wy, xz - wy
    m12, m21 = yz - wx, yz + wx
    i = (2 if m11 < m22 else 1) if m00 < m11 else (2 if m00 < m22 else 0)
    if i == 0:
        s = _sqrt(m00 - m11 - m22 + 1.0)
        h = s * 0.5
        s = 0.5 / s
        return h, (m10 + m01) * s, (m20 + m02) * s, (m21 - m12) * s
    if i == 1:
        s = _sqrt(m11 - m22 - m00 + 1.0)
        h = s * 0.5
        s = 0.5 / s
        return (m01 + m10) * s, h, (m21 + m12) * s, (m02 - m20) * s
    s = _sqrt(m22 - m00 - m11 + 1.0)
    h = s * 0.5
    s = 0.5 / s
    return (m02 + m20) * s, (m12 + m21) * s, h, (m10 - m01) * s



def inverse_compose(target_chain: Sample, source_chain: Sample | None) -> Sample:
    """tf2 ``TransformAccum::finalize`` for a walk with a target half.

    With ``inv = conj(q_t)``, ``v = rotate(inv, v_s) + rotate(inv, -v_t)`` and ``q = inv *
    q_s``; a None source chain (the source is the top) gives the inverse of the target chain.
    """
    tqx, tqy, tqz, tqw, vx, vy, vz = target_chain
    sx, sy, sz = (0.0, 0.0, 0.0) if source_chain is None else source_chain[4:]
    ix, iy, iz, iw = -tqx, -tqy, -tqz, tqw
    out = []
    for ux, uy, uz in ((-vx, -vy, -vz), (sx, sy, sz)):
        px = iw * ux + iy * uz - iz * uy
        py = iw * uy + iz * ux - ix * uz
        pz = iw * uz + ix * uy - iy * ux
        pw = -ix * ux - iy * uy - iz * uz
        out.append((
            px * iw - pw * ix - py * iz + pz * iy,
            py * iw - pw * iy - pz * ix + px * iz,
            pz * iw - pw * iz - px * iy + py * ix,
        ))  # fmt: skip
    (ax, ay, az), (bx, by, bz) = out
    if source_chain is None:
        return (ix, iy, iz, iw, ax, ay, az)
    qx, qy, qz, qw = source_chain[:4]
    return (
        iw * qx + ix * qw + iy * qz - iz * qy,
        iw * qy + iy * qw + iz * qx - ix * qz,
        iw * qz + iz * qw + ix * qy - iy * qx,
        iw * qw - ix * qx - iy * qy - iz * qz,
        bx + ax,
        by + ay,
        bz + az,
    )


# ----------------------------------------------------------------------------------------------
# the scalar policy in Python (the same arithmetic as _accel.evaluate)
# ----------------------------------------------------------------------------------------------
def _chain(chain: tuple[Edge, ...], t: int) -> Sample | None:
    """The edges of ``chain`` at ``t`` accumulated (child first), or None to decline.

    Inlined per edge: TimeCache.get's bracket search and :func:`interpolate` (with the
    per-interval slerp terms memoised in the cache), then :func:`accumulate`.
    """
    sqx = sqy = sqz = sx = sy = sz = 0.0
    sqw = 1.0
    first = True
    for stamps, parents, data, ivs, expected, static in chain:
        if stamps is None:
            if static is None or static.parent != expected:
                return None
            qx, qy, qz, qw, ex, ey, ez = static.sample
        elif stamps and stamps[0] < t < stamps[-1]:
            i = bisect_right(stamps, t) - 1
            if parents[i] != expected:
                return None
            if parents[i + 1] != expected:  # re-parented in between: no interpolation
                qx, qy, qz, qw, ex, ey, ez = data[i]
            else:
                s0 = stamps[i]
                r = (t - s0) / (stamps[i + 1] - s0)
                u = 1.0 - r
                x1, y1, z1, w1, ax, ay, az = data[i]
                x2, y2, z2, w2, bx, by, bz = data[i + 1]
                iv = ivs[i]
                if iv is None:
                    iv = slerp_terms(x1, y1, z1, w1, x2, y2, z2, w2)
                    ivs[i] = iv
                theta, d, flip = iv
                ex = u * ax + r * bx
                ey = u * ay + r * by
                ez = u * az + r * bz
                if theta == 0.0:
                    qx, qy, qz, qw = x1, y1, z1, w1
                else:
                    s0f = _sin(u * theta)
                    s1f = -_sin(r * theta) if flip else _sin(r * theta)
                    qx = (x1 * s0f + x2 * s1f) * d
                    qy = (y1 * s0f + y2 * s1f) * d
                    qz = (z1 * s0f + z2 * s1f) * d
                    qw = (w1 * s0f + w2 * s1f) * d
        elif stamps and t == stamps[-1]:
            if parents[-1] != expected:
                return None
            qx, qy, qz, qw, ex, ey, ez = data[-1]
        else:
            return None
        if first:
            sqx, sqy, sqz, sqw, sx, sy, sz = qx, qy, qz, qw, ex, ey, ez
            first = False
        else:
            px = qw * sx + qy * sz - qz * sy
            py = qw * sy + qz * sx - qx * sz
            pz = qw * sz + qx * sy - qy * sx
            pw = -qx * sx - qy * sy - qz * sz
            sx = px * qw - pw * qx - py * qz + pz * qy + ex
            sy = py * qw - pw * qy - pz * qx + px * qz + ey
            sz = pz * qw - pw * qz - px * qy + py * qx + ez
            sqx, sqy, sqz, sqw = (
                qw * sqx + qx * sqw + qy * sqz - qz * sqy,
                qw * sqy + qy * sqw + qz * sqx - qx * sqz,
                qw * sqz + qz * sqw + qx * sqy - qy * sqx,
                qw * sqw - qx * sqx - qy * sqy - qz * sqz,
            )
    return sqx, sqy, sqz, sqw, sx, sy, sz


def _evaluates(edge: Edge, t: int) -> bool:
    """Whether TimeCache.get(t) certainly succeeds on this edge (static edges always do)."""
    stamps = edge.stamps
    return stamps is None or bool(stamps and stamps[0] < t <= stamps[-1])


def raw_python(mode: int, up: tuple[Edge, ...], down: tuple[Edge, ...], check: Edge | None,
               t: int) -> Sample | None:
    """The walk's raw T_target_source at ``t`` (before the matrix round trip), or None."""
    if check is not None and not _evaluates(check, t):
        return None
    if mode == UP:
        return _chain(up, t)
    # the reference walks the source half first (its failures come first), then the target's
    a = _chain(up, t)
    if a is None:
        return None
    b = _chain(down, t)
    if b is None:
        return None
    if mode == DOWN:
        return inverse_compose(b, None)
    if not down:  # target is the top
        return a
    return inverse_compose(b, a)


def result_python(stamp_ns: int, raw: Sample) -> Result:
    """The finished values of a lookup at ``stamp_ns``.

    The stamp split as builtin_interfaces/Time, the raw quaternion through :func:`canonical`.
    """
    sec, nanosec = divmod(stamp_ns, _NS)
    qx, qy, qz, qw = canonical((raw[0], raw[1], raw[2], raw[3]))
    return sec, nanosec, qx, qy, qz, qw, raw[4], raw[5], raw[6]


def evaluate_python(mode: int, up: tuple[Edge, ...], down: tuple[Edge, ...],
                    check: Edge | None, t: int) -> Result | None:
    """The scalar policy: the finished result of a path at ``t``, or None to decline."""
    raw = raw_python(mode, up, down, check, t)
    return None if raw is None else result_python(t, raw)


_new = object.__new__


def stamped_python(target: str, source: str, r: Result) -> TransformStamped:
    """A fresh TransformStamped from a :data:`Result`, field by field.

    This skips the dataclass ``__init__`` chain, which costs more than a tree walk; tests check
    it equals the normally built message.
    """
    sec, nanosec, qx, qy, qz, qw, vx, vy, vz = r
    stamp = _new(TimeMsg)
    stamp.sec = sec
    stamp.nanosec = nanosec
    header = _new(Header)
    header.stamp = stamp
    header.frame_id = target
    vec = _new(Vector3)
    vec.x = vx
    vec.y = vy
    vec.z = vz
    rot = _new(Quaternion)
    rot.x = qx
    rot.y = qy
    rot.z = qz
    rot.w = qw
    tr = _new(Transform)
    tr.translation = vec
    tr.rotation = rot
    msg = _new(TransformStamped)
    msg.header = header
    msg.child_frame_id = source
    msg.transform = tr
    return msg


def _no_sample(msg: Any) -> None:
    """Pure Python: every message goes through BufferCore's checked conversion."""
    return None


def _load_accel() -> Any:
    if os.environ.get("POSEKIT_PURE_PYTHON", "") not in ("", "0"):
        return None
    try:
        from posekit.tf2 import _accel  # type: ignore[attr-defined]
    except ImportError:
        return None
    try:
        _accel.configure(TimeMsg, Header, Vector3, Quaternion, Transform, TransformStamped)
    except TypeError:  # the message classes are not slots dataclasses any more
        return None
    return _accel


_accel_module = _load_accel()

#: Whether the compiled kernels are in use.
accelerated: bool = _accel_module is not None

evaluate: Callable[[int, tuple[Edge, ...], tuple[Edge, ...], Edge | None, int], Result | None]
stamped: Callable[[str, str, Result], TransformStamped]
#: (stamp ns, parent, child, sample) of a message that passes tf2's checks in the common way,
#: or None: the caller then runs its checked conversion (which logs and rejects, or
#: converts ints and numpy scalars, strips a leading '/', ...).
sample_from_msg: Callable[[Any], tuple[int, str, str, Sample] | None]
if _accel_module is not None:
    evaluate = _accel_module.evaluate
    stamped = _accel_module.stamped
    sample_from_msg = _accel_module.sample_from_msg
else:
    evaluate = evaluate_python
    stamped = stamped_python
    sample_from_msg = _no_sample
