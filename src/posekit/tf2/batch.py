"""Vectorised tf2 lookups: many stamps, one (target, source) pair, numpy throughout.

Semantics are those of a loop of single lookups (same caches, same rules, same slerp/lerp,
same canonical quaternion sign); only the arithmetic is done on arrays. The walk is taken
once for all stamps: every edge is evaluated for the whole stamp array (``searchsorted`` on
the cache's stamps, then tf2's interpolation). Stamps that fail anywhere on that walk, and
trees whose parents change between the stamps (re-parenting), are handed to the exact
single-lookup code, so results and errors are always those of ``lookup_transform``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from posekit.tf2.exceptions import TransformException
from posekit.tf2.time_cache import display_time

if TYPE_CHECKING:
    from posekit.tf2.buffer_core import LockedView

__all__ = ["canonical_quats", "lookup_transforms_locked"]

F64 = npt.NDArray[np.float64]
I64 = npt.NDArray[np.int64]
B = npt.NDArray[np.bool_]


_CHUNK = 16384


class _Fallback(Exception):  # noqa: N818 - internal control flow, never escapes
    """The stamps do not share one path (re-parenting or a loop): use single lookups."""


# A batch of transforms is 7 columns (qx, qy, qz, qw, tx, ty, tz); a column is a 1-D array,
# or a float when the value is the same for every stamp (static edges). Columns keep every
# operation a flat, contiguous numpy loop.
Cols = tuple[Any, Any, Any, Any, Any, Any, Any]


def _accum(e: Cols, acc: Cols) -> Cols:
    """tf2 accum: v = quatRotate(q_e, v) + t_e; q = q_e * q (same term order as the scalar walk)."""
    qx, qy, qz, qw, ex, ey, ez = e
    ax, ay, az, aw, sx, sy, sz = acc
    px = qw * sx + qy * sz - qz * sy
    py = qw * sy + qz * sx - qx * sz
    pz = qw * sz + qx * sy - qy * sx
    pw = -qx * sx - qy * sy - qz * sz
    return (
        qw * ax + qx * aw + qy * az - qz * ay,
        qw * ay + qy * aw + qz * ax - qx * az,
        qw * az + qz * aw + qx * ay - qy * ax,
        qw * aw - qx * ax - qy * ay - qz * az,
        px * qw - pw * qx - py * qz + pz * qy + ex,
        py * qw - pw * qy - pz * qx + px * qz + ey,
        pz * qw - pw * qz - px * qy + py * qx + ez,
    )


def _rotate(q: tuple[Any, Any, Any, Any], v: tuple[Any, Any, Any]) -> tuple[Any, Any, Any]:
    qx, qy, qz, qw = q
    vx, vy, vz = v
    px = qw * vx + qy * vz - qz * vy
    py = qw * vy + qz * vx - qx * vz
    pz = qw * vz + qx * vy - qy * vx
    pw = -qx * vx - qy * vy - qz * vz
    return (
        px * qw - pw * qx - py * qz + pz * qy,
        py * qw - pw * qy - pz * qx + px * qz,
        pz * qw - pw * qz - px * qy + py * qx,
    )


def canonical_quats(q: F64) -> F64:
    """tf2's setRotation/getRotation round trip on (N,4) xyzw: unit norm, canonical sign."""
    return _canonical_rows(np.ascontiguousarray(q.T)).T.copy()


def _canonical_rows(q: F64) -> F64:
    """canonical_quats on a (4, N) array of rows x, y, z, w (contiguous rows); returns (4, N)."""
    x, y, z, w = q[0], q[1], q[2], q[3]
    out = np.empty_like(q)
    with np.errstate(invalid="ignore", divide="ignore"):
        s = 2.0 / (x * x + y * y + z * z + w * w)
        xs, ys, zs = x * s, y * s, z * s
        wx, wy, wz = w * xs, w * ys, w * zs
        xx, xy, xz = x * xs, x * ys, x * zs
        yy, yz, zz = y * ys, y * zs, z * zs
        m = (
            (1.0 - (yy + zz), xy - wz, xz + wy),
            (xy + wz, 1.0 - (xx + zz), yz - wx),
            (xz - wy, yz + wx, 1.0 - (xx + yy)),
        )
        trace = m[0][0] + m[1][1] + m[2][2]
        pos = trace > 0.0
        sq = np.sqrt(trace + 1.0)
        sc = 0.5 / sq
        out[3] = sq * 0.5
        out[0] = (m[2][1] - m[1][2]) * sc
        out[1] = (m[0][2] - m[2][0]) * sc
        out[2] = (m[1][0] - m[0][1]) * sc
        if not pos.all():
            d0, d1, d2 = m[0][0], m[1][1], m[2][2]
            big = np.where(d0 < d1, np.where(d1 < d2, 2, 1), np.where(d0 < d2, 2, 0))
            for i in range(3):
                sel = ~pos & (big == i)
                if not sel.any():
                    continue
                j, k = (i + 1) % 3, (i + 2) % 3
                sq = np.sqrt(m[i][i][sel] - m[j][j][sel] - m[k][k][sel] + 1.0)
                sc = 0.5 / sq
                out[i, sel] = sq * 0.5
                out[3, sel] = (m[k][j][sel] - m[j][k][sel]) * sc
                out[j, sel] = (m[j][i][sel] + m[i][j][sel]) * sc
                out[k, sel] = (m[k][i][sel] + m[i][k][sel]) * sc
    return out


def _gathers(older: Any, newer: Any, n: int) -> tuple[Callable[[Any], Any], Callable[[Any], Any]]:
    """Functions picking each stamp's older and newer sample from a per-sample row.

    Gathers dominate the cost of :func:`_edge`. Sorted stamps (the usual case: a trajectory)
    give non-decreasing indices, where np.repeat with per-sample counts is a run of memcpy's.
    """
    if older.shape[0] > 1 and bool((older[1:] >= older[:-1]).all()):
        c_old = np.bincount(older, minlength=n)
        c_new = np.bincount(newer, minlength=n)

        def g_old(row: Any) -> Any:
            return np.repeat(row, c_old)

        def g_new(row: Any) -> Any:
            return np.repeat(row, c_new)

        return g_old, g_new

    def take_old(row: Any) -> Any:
        return row.take(older)

    def take_new(row: Any) -> Any:
        return row.take(newer)

    return take_old, take_new


def _edge(cache: Any, t: I64) -> tuple[int, Cols, B | None] | None:
    """One edge at every stamp, or None if no stamp has data.

    The edge is (parent id, columns, ok mask or None = all ok). Raises _Fallback if the parent
    differs between successful stamps.
    """
    if cache.is_static:
        p, s = cache.get(0)
        return p, s, None
    n = len(cache)
    if n == 0:
        return None
    stamps, parents, data, theta_iv, inv_sin_iv, flip_iv = cache.arrays()
    newest = int(stamps[-1])
    oldest = int(stamps[0])
    latest = t == 0
    if n == 1:
        ok = latest | (t == oldest)
        if not ok.any():
            return None
        return int(parents[0]), tuple(float(c) for c in data[:, 0]), ok  # type: ignore[return-value]
    in_range = (t >= oldest) & (t <= newest)
    if in_range.all():
        ok = None
        tt = t
    else:
        okm = latest | in_range
        if not okm.any():
            return None
        ok = okm
        tt = np.where(okm & ~latest, t, newest)
    older = np.searchsorted(stamps, tt, side="right") - 1
    at_oldest = tt == oldest
    if at_oldest.any():
        older[at_oldest] = 0  # exact hit on the oldest stamp: its first-inserted sample
    newer = np.minimum(older + 1, n - 1)
    g_old, g_new = _gathers(older, newer, n)
    p_old = g_old(parents)
    p_ok = p_old if ok is None else p_old[ok]
    parent = int(p_ok[0])
    if (p_ok != parent).any():
        raise _Fallback
    # interpolate unless an exact hit on newest/oldest or re-parented between the brackets
    keep = (tt == newest) | at_oldest | (g_new(parents) != p_old)
    s0 = g_old(stamps)
    span = g_new(stamps) - s0
    span[keep] = 1
    r = (tt - s0).astype(np.float64) / span.astype(np.float64)
    r[keep] = 0.0
    u = 1.0 - r
    a = [g_old(row) for row in data]
    b = [g_new(row) for row in data]
    theta = g_old(theta_iv)
    use_a = keep | (theta == 0.0)
    d = g_old(inv_sin_iv)
    w0 = np.sin(u * theta)
    w1s = np.sin(r * theta)
    np.negative(w1s, out=w1s, where=g_old(flip_iv))
    cols = []
    any_a = use_a.any()
    with np.errstate(invalid="ignore"):  # d = inf where theta == 0; those rows take a
        for k in range(4):
            q = (a[k] * w0 + b[k] * w1s) * d
            cols.append(np.where(use_a, a[k], q) if any_a else q)
    for k in range(4, 7):
        cols.append(u * a[k] + r * b[k])
    return parent, tuple(cols), ok


def lookup_transforms_locked(
    core: LockedView, target: str, source: str, times: I64
) -> tuple[F64, F64]:
    """T_target_source at each stamp (lock held): translations (N,3), quaternions (N,4) xyzw."""
    n = times.shape[0]
    if target == source:
        return np.zeros((n, 3)), np.tile(np.array([0.0, 0.0, 0.0, 1.0]), (n, 1))
    tid = core.frame_id(target, "lookupTransform argument target_frame")
    sid = core.frame_id(source, "lookupTransform argument source_frame")
    t = times
    zero = t == 0
    if n and zero.any():
        try:
            lct = core.latest_common_time(tid, sid)  # raises like a single lookup at 0
        except TransformException as exc:
            raise _named(exc, int(np.argmax(zero)), 0, 0) from None
        t = np.where(zero, lct, t)
    v = np.zeros((n, 3))
    q = np.zeros((n, 4))
    suspect = np.zeros(n, dtype=bool)
    # Chunks keep every temporary small enough to stay in cache and in malloc's arena (whole
    # 1e5-element temporaries are mmap'ed and page-faulted afresh, ~2-3x slower). Each chunk
    # checks its own path, so stamps on either side of a re-parenting stay vectorised.
    for lo in range(0, n, _CHUNK):
        hi = min(lo + _CHUNK, n)
        try:
            cv, cq, cs = _walk(core, tid, sid, t[lo:hi])
        except _Fallback:
            suspect[lo:hi] = True
            continue
        if cs.any():
            cq[:, cs] = np.array([[0.0], [0.0], [0.0], [1.0]])
        v[lo:hi] = cv
        q[lo:hi] = _canonical_rows(cq).T
        suspect[lo:hi] = cs
    for i in np.flatnonzero(suspect):
        try:
            raw, _ = core.lookup_raw(target, source, int(times[i]))
        except TransformException as exc:
            raise _named(exc, int(i), int(times[i]), int(t[i])) from None
        q[i] = canonical_quats(np.array([raw[:4]]))[0]
        v[i] = raw[4:]
    return v, q


def _named(exc: TransformException, index: int, stamp: int, used: int) -> TransformException:
    """tf2's exception and text, naming the first failing element of the batch."""
    out = type(exc)(
        f"{exc} (first failing stamp: times_ns[{index}] = {stamp}, used {display_time(used)} s)"
    )
    out.index = index  # type: ignore[attr-defined]
    out.stamp_ns = stamp  # type: ignore[attr-defined]
    return out


def _walk(core: LockedView, tid: int, sid: int, t: I64) -> tuple[F64, F64, B]:
    """Vectorised walkToTopParent; returns (translations, raw quaternions (4, N), suspect mask)."""
    n = t.shape[0]
    cache_of = core.cache
    max_depth = core.max_depth
    suspect = np.zeros(n, dtype=bool)
    fail = (np.zeros((n, 3)), np.zeros((4, n)), np.ones(n, dtype=bool))
    src: Cols | None = None
    frame, top, depth = sid, sid, 0
    while frame != 0:
        cache = cache_of(frame)
        if cache is None:
            top = frame
            break
        edge = _edge(cache, t)
        if edge is None:
            top = frame
            suspect[:] = True
            break
        parent, e, ok = edge
        if ok is not None:
            suspect |= ~ok
        if frame == tid:
            return _finish(src, None, n, suspect)
        src = e if src is None else _accum(e, src)
        top = frame
        frame = parent
        depth += 1
        if depth > max_depth:
            raise _Fallback
    tgt: Cols | None = None
    frame, depth = tid, 0
    while frame != top:
        cache = cache_of(frame)
        if cache is None:
            break
        edge = _edge(cache, t)
        if edge is None:
            return fail
        parent, e, ok = edge
        if ok is not None:
            suspect |= ~ok
        if frame == sid:
            return _finish(None, tgt, n, suspect)
        tgt = e if tgt is None else _accum(e, tgt)
        frame = parent
        depth += 1
        if depth > max_depth:
            raise _Fallback
    if frame != top:
        return fail
    return _finish(src, tgt, n, suspect)


def _finish(src: Cols | None, tgt: Cols | None, n: int, suspect: B) -> tuple[F64, F64, B]:
    """tf2 TransformAccum.finalize on columns: inv(target chain) * source chain."""
    if src is None:
        src = (0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0)
    if tgt is None:
        res = src
    else:
        inv = (-tgt[0], -tgt[1], -tgt[2], tgt[3])
        ax, ay, az = _rotate(inv, (-tgt[4], -tgt[5], -tgt[6]))
        bx, by, bz = _rotate(inv, (src[4], src[5], src[6]))
        ix, iy, iz, iw = inv
        qx, qy, qz, qw = src[0], src[1], src[2], src[3]
        res = (
            iw * qx + ix * qw + iy * qz - iz * qy,
            iw * qy + iy * qw + iz * qx - ix * qz,
            iw * qz + iz * qw + ix * qy - iy * qx,
            iw * qw - ix * qx - iy * qy - iz * qz,
            bx + ax,
            by + ay,
            bz + az,
        )
    q = np.empty((4, n))  # rows x, y, z, w: contiguous for the canonicalisation
    v = np.empty((n, 3))
    for k in range(4):
        q[k] = res[k]
    for k in range(3):
        v[:, k] = res[4 + k]
    return v, q, suspect
