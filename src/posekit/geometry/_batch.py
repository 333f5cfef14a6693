"""Vectorised quaternion kernels on ``(N, 4)`` float64 arrays in (x, y, z, w) order.

The batch counterparts of :mod:`posekit.geometry._quat`: same formulas, same branch rules,
so a batch result equals a loop of singles to rounding. Inputs are assumed validated and
unit-norm (the public classes do that); outputs are fresh arrays.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from posekit.geometry._lazy import lazy_module

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    F64 = npt.NDArray[np.float64]
    Bools = npt.NDArray[np.bool_]
else:
    np = lazy_module("numpy")

from posekit.geometry._quat import GIMBAL_EPS, euler_params
from posekit.geometry.errors import InvalidQuaternionError

__all__ = [
    "from_euler",
    "from_matrix",
    "from_rotvec",
    "multiply",
    "normalize",
    "orthonormality",
    "rotate",
    "slerp",
    "to_euler",
    "to_matrix",
    "to_matrix_numpy",
    "to_rotvec",
    "wrap",
]



#: Rows per block: elementwise passes over one block stay in the CPU cache, which beats
#: whole-array passes (each a trip to main memory) by 2-4x for large batches.
BLOCK = 8192


_MATRIX_BLOCK = 4096
_SQRT2 = 2.0**0.5


def _blocks(n: int) -> list[tuple[int, int]]:
    return [(s, min(s + BLOCK, n)) for s in range(0, n, BLOCK)]


def normalize(q: F64) -> F64:
    """Unit copies of an ``(N, 4)`` array; raise on NaN/inf/zero rows (naming the first)."""
    n2 = np.einsum("ij,ij->i", q, q)
    # two reductions instead of a mask; NaN makes both comparisons fail
    if len(n2) and not (n2.min() > 0.0 and n2.max() < np.inf):
        # slow path: norms without under/overflow (1e-200 or 1e200 components are fine)
        norm = np.hypot(np.hypot(q[:, 0], q[:, 1]), np.hypot(q[:, 2], q[:, 3]))
        bad = ~((norm > 0.0) & np.isfinite(norm))
        if bad.any():
            idx = int(np.flatnonzero(bad)[0])
            raise InvalidQuaternionError(
                f"{int(bad.sum())} of {len(q)} quaternions encode no rotation (NaN, inf or "
                f"zero norm); first bad one at index {idx}: {q[idx].tolist()}"
            )
        return np.asarray(q / norm[:, None], dtype=np.float64)
    out = np.empty_like(q)
    for s, e in _blocks(len(q)):
        np.divide(q[s:e], np.sqrt(n2[s:e])[:, None], out=out[s:e])
    return out


def multiply(a: F64, b: F64) -> F64:
    """Row-wise Hamilton product ``a ⊗ b`` (a single row broadcasts against many)."""
    n = max(a.shape[0], b.shape[0])
    a = np.broadcast_to(a, (n, 4))
    b = np.broadcast_to(b, (n, 4))
    out = np.empty((n, 4))
    for s, e in _blocks(n):
        ab, bb = a[s:e], b[s:e]
        ax, ay, az, aw = ab[:, 0], ab[:, 1], ab[:, 2], ab[:, 3]
        bx, by, bz, bw = bb[:, 0], bb[:, 1], bb[:, 2], bb[:, 3]
        o = out[s:e]
        o[:, 0] = aw * bx + ax * bw + ay * bz - az * by
        o[:, 1] = aw * by - ax * bz + ay * bw + az * bx
        o[:, 2] = aw * bz + ax * by - ay * bx + az * bw
        o[:, 3] = aw * bw - ax * bx - ay * by - az * bz
    return out


def rotate(q: F64, v: F64) -> F64:
    """Rotate vectors ``v`` (``(N, 3)``) by unit quaternions ``q`` (rows broadcast).

    ``v' = v + w t + u × t`` with ``t = 2 u × v`` (the expanded ``q v q⁻¹``).
    """
    n = max(q.shape[0], v.shape[0])
    q = np.broadcast_to(q, (n, 4))
    v = np.broadcast_to(v, (n, 3))
    out = np.empty((n, 3))
    for s, e in _blocks(n):
        qb, vb = q[s:e], v[s:e]
        x, y, z, w = qb[:, 0], qb[:, 1], qb[:, 2], qb[:, 3]
        vx, vy, vz = vb[:, 0], vb[:, 1], vb[:, 2]
        tx = 2.0 * (y * vz - z * vy)
        ty = 2.0 * (z * vx - x * vz)
        tz = 2.0 * (x * vy - y * vx)
        o = out[s:e]
        o[:, 0] = vx + w * tx + (y * tz - z * ty)
        o[:, 1] = vy + w * ty + (z * tx - x * tz)
        o[:, 2] = vz + w * tz + (x * ty - y * tx)
    return out


def _load_accel() -> Any:
    import os

    if os.environ.get("POSEKIT_PURE_PYTHON", "") not in ("", "0"):
        return None
    try:
        from posekit.geometry import _accel  # type: ignore[attr-defined]
    except ImportError:
        return None
    return _accel


#: the optional compiled kernels (None where the extension was not built)
_accel = _load_accel()


def to_matrix(q: F64) -> F64:
    """``(N, 3, 3)`` rotation matrices of unit quaternions (compiled where available; the
    same IEEE operations in the same order as :func:`to_matrix_numpy`)."""
    if _accel is not None and q.dtype == np.float64 and q.flags.c_contiguous:
        m = np.empty((q.shape[0], 3, 3))
        _accel.quat_to_matrix(q, m)
        return m
    return to_matrix_numpy(q)


def to_matrix_numpy(q: F64) -> F64:
    """``(N, 3, 3)`` rotation matrices of unit quaternions, in numpy.

    Per block: copy the components into contiguous rows scaled by √2 (so every product comes
    out already doubled), form the 9 products and 9 entries in reused buffers, and write the
    block with one transposing copy: about 20 numpy calls per block, all in cache.
    """
    n = q.shape[0]
    m = np.empty((n, 3, 3))
    flat = m.reshape(n, 9)
    size = min(n, _MATRIX_BLOCK)
    qt_buf = np.empty((4, size))
    p_buf = np.empty((9, size))
    o_buf = np.empty((9, size))
    for s in range(0, n, _MATRIX_BLOCK):
        e = min(s + _MATRIX_BLOCK, n)
        width = e - s
        qt = qt_buf[:, :width]
        np.multiply(q[s:e].T, _SQRT2, out=qt)
        x, y, z, w = qt
        p = p_buf[:, :width]
        np.multiply(qt[:3], qt[:3], out=p[:3])  # 2xx 2yy 2zz
        np.multiply(x, qt[1:3], out=p[3:5])  # 2xy 2xz
        np.multiply(y, z, out=p[5])  # 2yz
        np.multiply(w, qt[:3], out=p[6:9])  # 2wx 2wy 2wz
        xx, yy, zz, xy, xz, yz, wx, wy, wz = p
        o = o_buf[:, :width]
        np.add(yy, zz, out=o[0])
        np.subtract(1.0, o[0], out=o[0])
        np.subtract(xy, wz, out=o[1])
        np.add(xz, wy, out=o[2])
        np.add(xy, wz, out=o[3])
        np.add(xx, zz, out=o[4])
        np.subtract(1.0, o[4], out=o[4])
        np.subtract(yz, wx, out=o[5])
        np.subtract(xz, wy, out=o[6])
        np.add(yz, wx, out=o[7])
        np.add(xx, yy, out=o[8])
        np.subtract(1.0, o[8], out=o[8])
        flat[s:e] = o.T
    return m


def from_matrix(m: F64) -> F64:
    """Unit quaternions of ``(N, 3, 3)`` rotation matrices, same branch rule as the scalar path.

    Branch: ``w`` if the trace is positive, else the largest diagonal element (first on
    ties). Each branch's unnormalised quaternion is a sum/difference of matrix entries whose
    large component is positive; one normalisation finishes it (no per-branch sqrt).
    """
    n = m.shape[0]
    q = np.empty((n, 4))
    for s, e in _blocks(n):
        f = m[s:e].reshape(e - s, 9)
        m00, m01, m02, m10, m11, m12, m20, m21, m22 = f.T
        trace = m00 + m11 + m22
        branch = np.argmax(f[:, [0, 4, 8]], axis=1)
        branch[trace > 0.0] = 3
        s01, s02, s12 = m01 + m10, m02 + m20, m12 + m21
        d21, d02, d10 = m21 - m12, m02 - m20, m10 - m01
        qb = q[s:e]
        np.choose(branch, (1.0 + m00 - m11 - m22, s01, s02, d21), out=qb[:, 0])
        np.choose(branch, (s01, 1.0 - m00 + m11 - m22, s12, d02), out=qb[:, 1])
        np.choose(branch, (s02, s12, 1.0 - m00 - m11 + m22, d10), out=qb[:, 2])
        np.choose(branch, (d21, d02, d10, 1.0 + trace), out=qb[:, 3])
        qb /= np.sqrt(np.einsum("ij,ij->i", qb, qb))[:, None]
    return q


def orthonormality(m: F64) -> tuple[F64, F64]:
    """Per matrix: ``max |R Rᵀ - I|`` (over the 6 distinct entries) and ``det R``."""
    n = m.shape[0]
    err = np.empty(n)
    det = np.empty(n)
    for s, e in _blocks(n):
        r0, r1, r2 = m[s:e, 0], m[s:e, 1], m[s:e, 2]
        d00 = np.abs(np.einsum("ij,ij->i", r0, r0) - 1.0)
        d11 = np.abs(np.einsum("ij,ij->i", r1, r1) - 1.0)
        d22 = np.abs(np.einsum("ij,ij->i", r2, r2) - 1.0)
        d01 = np.abs(np.einsum("ij,ij->i", r0, r1))
        d02 = np.abs(np.einsum("ij,ij->i", r0, r2))
        d12 = np.abs(np.einsum("ij,ij->i", r1, r2))
        # fmax would drop NaN; maximum propagates it so NaN matrices fail the check
        np.maximum(np.maximum(np.maximum(d00, d11), np.maximum(d22, d01)),
                   np.maximum(d02, d12), out=err[s:e])
        a0, a1, a2 = r0[:, 0], r0[:, 1], r0[:, 2]
        b0, b1, b2 = r1[:, 0], r1[:, 1], r1[:, 2]
        c0, c1, c2 = r2[:, 0], r2[:, 1], r2[:, 2]
        det[s:e] = a0 * (b1 * c2 - b2 * c1) - a1 * (b0 * c2 - b2 * c0) + a2 * (b0 * c1 - b1 * c0)
    return err, det


def wrap(a: F64) -> F64:
    """Wrap angles to [-π, π] (values already inside are untouched, like the scalar path)."""
    out = a.copy()
    outside = (a < -np.pi) | (a > np.pi)
    if outside.any():
        v = a[outside]
        out[outside] = v - 2.0 * np.pi * np.ceil((v - np.pi) / (2.0 * np.pi))
    return out


def from_euler(seq: str, angles: F64) -> F64:
    """Quaternions of ``(N, 3)`` Euler angles (rad) in the sequence's order; ``w >= 0``.

    Same closed form as the scalar ``quat_from_euler_xyzw``.
    """
    i, j, k, extrinsic, proper, e = euler_params(seq)
    a, b, c = angles[:, 0], angles[:, 1], angles[:, 2]
    if not extrinsic:
        a, c = c, a
    q = np.empty((angles.shape[0], 4))
    hb = 0.5 * b
    cb, sb = np.cos(hb), np.sin(hb)
    if proper:
        hs, hd = 0.5 * (a + c), 0.5 * (c - a)
        q[:, 3] = cb * np.cos(hs)
        q[:, i] = cb * np.sin(hs)
        q[:, j] = sb * np.cos(hd)
        q[:, k] = e * sb * np.sin(hd)
    else:
        ha, hc = 0.5 * a, 0.5 * c
        ca, sa = np.cos(ha), np.sin(ha)
        cc, sc = np.cos(hc), np.sin(hc)
        q[:, 3] = ca * cb * cc + e * sa * sb * sc
        q[:, i] = sa * cb * cc - e * ca * sb * sc
        q[:, j] = ca * sb * cc + e * sa * cb * sc
        q[:, k] = ca * cb * sc - e * sa * sb * cc
    q[q[:, 3] < 0.0] *= -1.0
    return q


def to_euler(seq: str, q: F64) -> tuple[F64, Bools]:
    """``(N, 3)`` Euler angles (rad) and the gimbal-lock mask (see ``quat_to_euler_xyzw``)."""
    i, j, k, extrinsic, proper, parity = euler_params(seq)
    n = q.shape[0]
    out = np.empty((n, 3))
    locked = np.empty(n, dtype=np.bool_)
    # columns that receive the extrinsic first/third angle
    c_first, c_third = (0, 2) if extrinsic else (2, 0)
    for s, e in _blocks(n):
        qb = q[s:e]
        w, qi, qj = qb[:, 3], qb[:, i], qb[:, j]
        qk = qb[:, k] if parity > 0 else -qb[:, k]
        if proper:
            a, b, c, d = w, qi, qj, qk
        else:
            a, b, c, d = w - qj, qi + qk, qj + w, qk - qi
        middle = np.arctan2(np.hypot(c, d), np.hypot(a, b))
        middle *= 2.0  # in [0, π]
        half_sum = np.arctan2(b, a)
        half_diff = np.arctan2(d, c)
        o = out[s:e]
        first, third = o[:, c_first], o[:, c_third]
        np.subtract(half_sum, half_diff, out=first)
        np.add(half_sum, half_diff, out=third)
        lock0 = middle <= GIMBAL_EPS
        lock_pi = middle >= np.pi - GIMBAL_EPS
        lk = np.logical_or(lock0, lock_pi, out=locked[s:e])
        if lk.any():
            if extrinsic:
                first[lock0] = 2.0 * half_sum[lock0]
                first[lock_pi] = -2.0 * half_diff[lock_pi]
                third[lk] = 0.0
            else:
                third[lock0] = 2.0 * half_sum[lock0]
                third[lock_pi] = 2.0 * half_diff[lock_pi]
                first[lk] = 0.0
        if not proper:
            if parity < 0:
                np.negative(third, out=third)
            middle -= np.pi / 2.0
        o[:, 1] = middle
        for col in (first, third):
            big = np.abs(col) > np.pi
            if big.any():
                v = col[big]
                col[big] = v - np.copysign(2.0 * np.pi, v)
    return out, locked


def from_rotvec(r: F64) -> F64:
    """Quaternions of ``(N, 3)`` rotation vectors (rad)."""
    angle = np.sqrt(np.einsum("ij,ij->i", r, r))
    small = angle < 1e-6
    a2 = angle * angle
    with np.errstate(invalid="ignore", divide="ignore"):
        scale = np.where(small, 0.5 - a2 / 48.0 + a2 * a2 / 3840.0, np.sin(0.5 * angle) / angle)
    q = np.empty((r.shape[0], 4))
    q[:, :3] = r * scale[:, None]
    q[:, 3] = np.cos(0.5 * angle)
    return q


def to_rotvec(q: F64) -> F64:
    """``(N, 3)`` rotation vectors (angle in [0, π]) of unit quaternions."""
    q = np.where(q[:, 3:4] < 0.0, -q, q)
    s = np.sqrt(np.einsum("ij,ij->i", q[:, :3], q[:, :3]))
    angle = 2.0 * np.arctan2(s, q[:, 3])
    a2 = angle * angle
    with np.errstate(invalid="ignore", divide="ignore"):
        scale = np.where(angle < 1e-3, 2.0 + a2 / 12.0 + 7.0 * a2 * a2 / 2880.0, angle / s)
    return np.asarray(q[:, :3] * scale[:, None], dtype=np.float64)


def slerp(q1: F64, q2: F64, t: F64) -> F64:
    """Row-wise tf2-formula slerp (shortest arc); rows broadcast, ``t`` has shape ``(N,)``."""
    dot = np.sum(q1 * q2, axis=-1)
    n = np.sqrt(np.sum(q1 * q1, axis=-1) * np.sum(q2 * q2, axis=-1))
    theta = np.arccos(np.minimum(np.abs(dot) / n, 1.0))
    zero = theta == 0.0
    with np.errstate(invalid="ignore", divide="ignore"):
        d = 1.0 / np.sin(theta)
        s0 = np.sin((1.0 - t) * theta) * d
        s1 = np.sin(t * theta) * d
    s1 = np.where(dot < 0.0, -s1, s1)
    s0 = np.where(zero, 1.0, s0)
    s1 = np.where(zero, 0.0, s1)
    out = q1 * s0[..., None] + q2 * s1[..., None]
    return np.asarray(np.broadcast_to(out, (t.shape[0], 4)), dtype=np.float64).copy()
