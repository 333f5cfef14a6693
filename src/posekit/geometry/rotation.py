"""3-D rotations (SO(3)), one or a batch of N, with scipy's ``Rotation`` API and ROS helpers.

Conventions (see ``docs/conventions.md``):

* Rotations are **active**: ``r.apply(v)`` rotates the vector ``v``; with ``R_a_b`` mapping
  frame-``b`` coordinates into frame ``a``.
* Quaternions are Hamilton, stored scalar-last ``(x, y, z, w)`` like ROS messages and scipy;
  every quaternion boundary has a keyword-only ``scalar_first=`` flag.
* ``r1 * r2`` applies ``r2`` first, then ``r1`` (as scipy and the lecture's ``q2 ⊗ q1``).
* Euler sequences: 3 letters, lowercase = extrinsic (fixed axes), uppercase = intrinsic
  (moving axes), as scipy. Angles in radians unless ``degrees=True``.
* Normalisation policy: finite non-unit quaternions are normalised silently (as scipy and
  ROS 2 tf2); NaN, inf and zero-norm quaternions raise :class:`InvalidQuaternionError`.

A single rotation keeps its quaternion as a tuple of Python floats and uses the scalar kernels
of :mod:`posekit.geometry._quat` (no numpy on the hot path); a batch keeps an ``(N, 4)`` array
and uses the vectorised kernels, which implement the same formulas.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING, Any

from posekit.geometry._lazy import lazy_module

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from posekit.geometry._parse import F64
else:
    np = lazy_module("numpy")

from posekit.geometry import _batch as vk
from posekit.geometry import _quat as sk
from posekit.geometry._parse import (
    check_finite,
    check_finite_array,
    parse_rows,
    parse_scalar_or_array,
)
from posekit.geometry.errors import (
    GimbalLockWarning,
    NonOrthonormalMatrixError,
    ShapeError,
    ZeroAxisError,
)

__all__ = ["Rotation", "compose_body", "compose_world"]

_GIMBAL_MSG = (
    "gimbal lock detected for sequence {seq!r}: the middle angle is at a singularity, so only "
    "the sum/difference of the outer angles is determined; the third angle was set to 0"
)


def _canonical(q: sk.Quat) -> sk.Quat:
    x, y, z, w = q
    if w > 0.0 or (w == 0.0 and (x > 0.0 or (x == 0.0 and (y > 0.0 or (y == 0.0 and z > 0.0))))):
        return q
    return (-x, -y, -z, -w)


def _canonical_batch(q: F64) -> F64:
    # Sign of the first non-zero component in (w, x, y, z) order decides the flip.
    order = q[:, [3, 0, 1, 2]]
    nonzero = order != 0.0
    first = np.argmax(nonzero, axis=1)
    lead = order[np.arange(len(q)), first]
    return np.where((lead < 0.0)[:, None], -q, q)


class Rotation:
    """One rotation or a batch of N rotations in 3-D (active, Hamilton quaternions).

    Build with the ``from_*`` class methods, :meth:`identity`, :meth:`random` or
    ``Rotation(quat)`` (same as :meth:`from_quat`). ``len()`` and indexing work on batches
    only; ``len()`` of a single rotation raises ``TypeError`` like scipy.

    Examples:
        A yaw of 90 degrees is the quaternion (0, 0, sin 45°, cos 45°); it turns x into y:

        >>> import numpy as np
        >>> from posekit.geometry import Rotation
        >>> yaw90 = Rotation.from_euler("z", 90, degrees=True)
        >>> yaw90.as_quat().round(6).tolist()                   # (x, y, z, w), as ROS
        [0.0, 0.0, 0.707107, 0.707107]
        >>> yaw90.as_quat(scalar_first=True).round(6).tolist()  # (w, x, y, z)
        [0.707107, 0.0, 0.0, 0.707107]
        >>> np.allclose(yaw90.apply([1.0, 0.0, 0.0]), [0.0, 1.0, 0.0])
        True

        ``a * b`` applies ``b`` first: a roll of 90° takes y to z, which the yaw keeps, and
        takes z to -y, which the yaw turns into x:

        >>> roll90 = Rotation.from_euler("x", 90, degrees=True)
        >>> np.allclose((yaw90 * roll90).apply([[0, 1, 0], [0, 0, 1]]), [[0, 0, 1], [1, 0, 0]])
        True
        >>> (yaw90 * roll90).as_quat().round(6).tolist()        # (0.5, 0.5, 0.5, 0.5)
        [0.5, 0.5, 0.5, 0.5]
    """

    __slots__ = ("_q", "_qs")

    _q: sk.Quat | None
    _qs: F64 | None

    def __init__(self, quat: npt.ArrayLike, *, scalar_first: bool = False) -> None:
        other = Rotation.from_quat(quat, scalar_first=scalar_first)
        self._q = other._q
        self._qs = other._qs

    # -- private constructors -------------------------------------------------------------
    @classmethod
    def _single(cls, q: sk.Quat) -> Rotation:
        r = object.__new__(cls)
        r._q = q
        r._qs = None
        return r

    @classmethod
    def _many(cls, qs: F64) -> Rotation:
        r = object.__new__(cls)
        r._q = None
        r._qs = qs
        return r

    def _rows(self) -> F64:
        """The quaternions as an ``(N, 4)`` array (``(1, 4)`` for a single rotation)."""
        if self._qs is not None:
            return self._qs
        assert self._q is not None
        return np.array([self._q])

    # -- construction -----------------------------------------------------------------------
    @classmethod
    def from_quat(cls, quat: npt.ArrayLike, *, scalar_first: bool = False) -> Rotation:
        """From quaternion(s), shape ``(4,)`` or ``(N, 4)``.

        Args:
            quat: ``(x, y, z, w)`` rows, or ``(w, x, y, z)`` rows with ``scalar_first=True``.
                Finite non-unit quaternions are normalised.
            scalar_first: True if ``w`` comes first (pytransform3d, transforms3d, Eigen's
                constructor order).

        Raises:
            InvalidQuaternionError: NaN, inf or zero norm.
            ShapeError: not ``(4,)`` or ``(N, 4)``.
        """
        try:  # one item: four numbers (list, tuple or (4,) array); anything else is a batch
            items: Any = quat
            x, y, z, w = items
            x, y, z, w = float(x), float(y), float(z), float(w)
        except (TypeError, ValueError):
            pass
        else:
            if scalar_first:
                x, y, z, w = y, z, w, x
            n = math.sqrt(x * x + y * y + z * z + w * w)
            if n == 1.0:
                return cls._single((x, y, z, w))
            if 1e-100 < n < 1e100:  # no under/overflow in the squares
                return cls._single((x / n, y / n, z / n, w / n))
            return cls._single(sk.quat_normalize_xyzw(x, y, z, w))  # exact, or raises
        p = parse_rows(quat, 4, "quaternion")
        if isinstance(p, tuple):
            if scalar_first:
                return cls._single(sk.quat_normalize_xyzw(p[1], p[2], p[3], p[0]))
            return cls._single(sk.quat_normalize_xyzw(p[0], p[1], p[2], p[3]))
        if scalar_first:
            p = p[:, [1, 2, 3, 0]]
        return cls._many(vk.normalize(p))

    @classmethod
    def identity(cls, num: int | None = None) -> Rotation:
        """The identity rotation, or a batch of ``num`` identities."""
        if num is None:
            return cls._single((0.0, 0.0, 0.0, 1.0))
        q = np.zeros((num, 4))
        q[:, 3] = 1.0
        return cls._many(q)

    @classmethod
    def random(
        cls, num: int | None = None, rng: np.random.Generator | int | None = None
    ) -> Rotation:
        """Uniformly distributed random rotation(s) (normalised 4-D Gaussian samples).

        Args:
            num: batch size, or None for a single rotation.
            rng: a numpy ``Generator`` or a seed.
        """
        gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
        q = gen.standard_normal((1 if num is None else num, 4))
        q = vk.normalize(q)
        if num is None:
            return cls._single(tuple(q[0].tolist()))
        return cls._many(q)

    @classmethod
    def from_matrix(cls, matrix: npt.ArrayLike, *, atol: float = 1e-6) -> Rotation:
        """From rotation matrix(ces), shape ``(3, 3)`` or ``(N, 3, 3)``.

        Args:
            matrix: proper orthonormal matrices (``R Rᵀ = I``, ``det R = +1``), active
                convention: ``R @ v`` rotates ``v``.
            atol: largest accepted entry of ``|R Rᵀ - I|`` (and ``|det R - 1|``). Within it,
                the quaternion extracted from the matrix is normalised (a nearby rotation).

        Raises:
            NonOrthonormalMatrixError: beyond ``atol``, a reflection, or NaN/inf entries.
            ShapeError: not ``(3, 3)`` or ``(N, 3, 3)``.
        """
        m = np.asarray(matrix, dtype=np.float64)
        if m.shape == (3, 3):
            rows = m.tolist()
            r0, r1, r2 = rows
            m3: sk.Mat3 = (
                (r0[0], r0[1], r0[2]),
                (r1[0], r1[1], r1[2]),
                (r2[0], r2[1], r2[2]),
            )
            cls._check_orthonormal_single(m3, atol)
            return cls._single(sk.matrix_to_quat_xyzw(m3))
        if m.ndim == 3 and m.shape[1:] == (3, 3):
            cls._check_orthonormal_batch(m, atol)
            return cls._many(vk.from_matrix(m))
        raise ShapeError(f"matrix must have shape (3, 3) or (N, 3, 3), got shape {m.shape}")

    @staticmethod
    def _check_orthonormal_single(m: sk.Mat3, atol: float) -> None:
        worst = 0.0
        for a in range(3):
            ra = m[a]
            for b in range(a, 3):
                rb = m[b]
                dot = ra[0] * rb[0] + ra[1] * rb[1] + ra[2] * rb[2]
                err = abs(dot - (1.0 if a == b else 0.0))
                if not err <= worst:
                    worst = err  # NaN lands here and fails the final test
        (a0, a1, a2), (b0, b1, b2), (c0, c1, c2) = m
        det = a0 * (b1 * c2 - b2 * c1) - a1 * (b0 * c2 - b2 * c0) + a2 * (b0 * c1 - b1 * c0)
        if not (worst <= atol and abs(det - 1.0) <= atol):
            raise NonOrthonormalMatrixError(
                f"not a rotation matrix: max |R Rᵀ - I| = {worst:.3g}, det = {det:.6g} "
                f"(tolerance {atol:g}); matrix = {[list(r) for r in m]}"
            )

    @staticmethod
    def _check_orthonormal_batch(m: F64, atol: float) -> None:
        err, det = vk.orthonormality(m)
        bad = ~((err <= atol) & (np.abs(det - 1.0) <= atol))
        if bad.any():
            idx = int(np.flatnonzero(bad)[0])
            raise NonOrthonormalMatrixError(
                f"{int(bad.sum())} of {len(m)} matrices are not rotations (tolerance {atol:g});"
                f" first at index {idx}: max |R Rᵀ - I| = {err[idx]:.3g}, det = {det[idx]:.6g}"
            )

    @classmethod
    def from_euler(cls, seq: str, angles: npt.ArrayLike, degrees: bool = False) -> Rotation:
        """From Euler angles.

        Args:
            seq: 1 to 3 axis letters; lowercase = extrinsic (rotations about the fixed frame's
                axes, applied left to right), uppercase = intrinsic (about the moving body's
                axes). ``'xyz'`` is ROS roll-pitch-yaw; ``'ZYX'`` is the same rotation with
                the angles listed yaw, pitch, roll.
            angles: shape ``(3,)`` or ``(N, 3)``, in the order the sequence names the axes.
                As scipy, shorter sequences take fewer angles: ``'x'`` a number (one
                rotation), ``(N,)`` or ``(N, 1)`` (a batch); ``'xy'`` ``(2,)`` or ``(N, 2)``.
            degrees: angles in degrees instead of radians.

        Raises:
            UnknownSequenceError, ShapeError, NonFiniteError.
        """
        if isinstance(seq, str) and len(seq) in (1, 2):
            seq, angles = _pad_euler_sequence(seq, angles)
        try:  # one item: three numbers (list, tuple or (3,) array); anything else is a batch
            items: Any = angles
            a, b, c = items
            a, b, c = float(a), float(b), float(c)
        except (TypeError, ValueError):
            pass
        else:
            if not math.isfinite(a + b + c):
                check_finite((a, b, c), "Euler angles")
            if degrees:
                a, b, c = math.radians(a), math.radians(b), math.radians(c)
            return cls._single(sk.quat_from_euler_xyzw(seq, a, b, c))
        sk.euler_params(seq)
        p = parse_rows(angles, 3, "Euler angles")
        if isinstance(p, tuple):
            check_finite(p, "Euler angles")
            a, b, c = p
            if degrees:
                a, b, c = math.radians(a), math.radians(b), math.radians(c)
            return cls._single(sk.quat_from_euler_xyzw(seq, a, b, c))
        check_finite_array(p, "Euler angles")
        if degrees:
            p = np.radians(p)
        return cls._many(vk.from_euler(seq, p))

    @classmethod
    def from_rpy(cls, roll: npt.ArrayLike, pitch: npt.ArrayLike, yaw: npt.ArrayLike) -> Rotation:
        """From ROS roll/pitch/yaw (rad) about the *fixed* x, y, z axes (tf2 ``setRPY``).

        ``R = Rz(yaw) Ry(pitch) Rx(roll)``, identical to ``from_euler('xyz', [roll, pitch,
        yaw])``. Scalars give one rotation, equal-length 1-D sequences a batch.

        Examples:
            A roll of π/2 is the quaternion (sin π/4, 0, 0, cos π/4); intrinsic ``'ZYX'``
            with the angles listed yaw, pitch, roll is the same convention:

            >>> import math
            >>> from posekit.geometry import Rotation
            >>> Rotation.from_rpy(math.pi / 2, 0.0, 0.0).as_quat().round(6).tolist()
            [0.707107, 0.0, 0.0, 0.707107]
            >>> r = Rotation.from_euler("ZYX", [0.3, 0.2, 0.1])    # yaw, pitch, roll
            >>> [round(a, 12) for a in r.as_rpy()]
            [0.1, 0.2, 0.3]
        """
        r = parse_scalar_or_array(roll, "roll")
        p = parse_scalar_or_array(pitch, "pitch")
        y = parse_scalar_or_array(yaw, "yaw")
        if isinstance(r, float) and isinstance(p, float) and isinstance(y, float):
            check_finite((r, p, y), "roll/pitch/yaw")
            return cls._single(sk.quat_from_rpy_xyzw(r, p, y))
        try:
            stacked = np.stack(np.broadcast_arrays(r, p, y), axis=1)
        except ValueError as exc:
            raise ShapeError(f"roll, pitch and yaw have incompatible lengths: {exc}") from None
        return cls.from_euler("xyz", stacked)

    @classmethod
    def from_rotvec(cls, rotvec: npt.ArrayLike, degrees: bool = False) -> Rotation:
        """From rotation vector(s) ``axis * angle`` (OpenCV ``rvec``), ``(3,)`` or ``(N, 3)``."""
        p = parse_rows(rotvec, 3, "rotation vector")
        if isinstance(p, tuple):
            check_finite(p, "rotation vector")
            if degrees:
                p = (math.radians(p[0]), math.radians(p[1]), math.radians(p[2]))
            return cls._single(sk.quat_from_rotvec_xyzw(p[0], p[1], p[2]))
        check_finite_array(p, "rotation vector")
        if degrees:
            p = np.radians(p)
        return cls._many(vk.from_rotvec(p))

    @classmethod
    def from_mrp(cls, mrp: npt.ArrayLike) -> Rotation:
        """From Modified Rodrigues Parameters ``axis * tan(angle / 4)``, ``(3,)`` or ``(N, 3)``.

        As scipy: any finite vector is a rotation (norm 1 is half a turn).
        """
        p = parse_rows(mrp, 3, "MRP")
        rows = np.array([p]) if isinstance(p, tuple) else p
        check_finite_array(rows, "MRP")
        n2 = np.einsum("ij,ij->i", rows, rows)
        q = np.empty((len(rows), 4))
        q[:, :3] = 2.0 * rows / (1.0 + n2)[:, None]
        q[:, 3] = (1.0 - n2) / (1.0 + n2)
        q = vk.normalize(q)
        if isinstance(p, tuple):
            return cls._single(tuple(q[0].tolist()))
        return cls._many(q)

    @classmethod
    def from_axis_angle(
        cls, axis: npt.ArrayLike, angle: npt.ArrayLike, degrees: bool = False
    ) -> Rotation:
        """Rotation by ``angle`` about ``axis`` (right-hand rule); the axis is normalised.

        Args:
            axis: ``(3,)`` or ``(N, 3)``, any non-zero length.
            angle: scalar or ``(N,)``; radians unless ``degrees=True``.
            degrees: ``angle`` in degrees instead of radians.

        Raises:
            ZeroAxisError: an axis of zero (or non-finite) length.
        """
        p = parse_rows(axis, 3, "axis")
        a = parse_scalar_or_array(angle, "angle")
        if isinstance(p, tuple) and isinstance(a, float):
            n = math.hypot(p[0], p[1], p[2])
            if not 0.0 < n < math.inf:
                raise ZeroAxisError(f"rotation axis {p!r} has zero or non-finite length")
            check_finite((a,), "angle")
            if degrees:
                a = math.radians(a)
            u = (p[0] / n, p[1] / n, p[2] / n)
            return cls._single(sk.quat_from_axis_angle_xyzw(u, a))
        ax = np.atleast_2d(np.asarray(p, dtype=np.float64))
        ang = np.atleast_1d(np.asarray(a, dtype=np.float64))
        n = np.linalg.norm(ax, axis=1)
        bad = ~((n > 0.0) & np.isfinite(n))
        if bad.any():
            idx = int(np.flatnonzero(bad)[0])
            raise ZeroAxisError(f"rotation axis at index {idx} has zero or non-finite length")
        check_finite_array(ang[:, None], "angle")
        if degrees:
            ang = np.radians(ang)
        try:
            axes, ang2 = np.broadcast_arrays(ax / n[:, None], ang[:, None])
        except ValueError:
            raise ShapeError(
                f"axis batch of {len(ax)} and angle batch of {len(ang)} do not match"
            ) from None
        h = 0.5 * ang2[:, 0]
        q = np.empty((len(h), 4))
        q[:, :3] = axes * np.sin(h)[:, None]
        q[:, 3] = np.cos(h)
        return cls._many(q)

    @classmethod
    def concatenate(cls, rotations: Sequence[Rotation]) -> Rotation:
        """One batch holding all given rotations (singles and batches) in order."""
        if not rotations:
            return cls._many(np.zeros((0, 4)))
        return cls._many(np.concatenate([r._rows() for r in rotations], axis=0))

    # -- single / batch protocol ---------------------------------------------------------
    @property
    def single(self) -> bool:
        """True for one rotation, False for a batch (even a batch of length 1)."""
        return self._q is not None

    def __len__(self) -> int:
        if self._qs is None:
            raise TypeError("a single Rotation has no len(); check .single first")
        return len(self._qs)

    def __bool__(self) -> bool:
        return True

    def __getitem__(self, index: Any) -> Rotation:
        if self._qs is None:
            raise TypeError("a single Rotation is not subscriptable")
        sel = self._qs[index]
        if sel.ndim == 1:
            return Rotation._single(tuple(sel.tolist()))
        return Rotation._many(np.array(sel))

    def __iter__(self) -> Iterator[Rotation]:
        if self._qs is None:
            raise TypeError("a single Rotation is not iterable")
        for row in self._qs.tolist():
            yield Rotation._single(tuple(row))

    def __repr__(self) -> str:
        if self._q is not None:
            return f"Rotation.from_quat({list(self._q)!r})  # (x, y, z, w)"
        assert self._qs is not None
        return f"Rotation(batch of {len(self._qs)})"

    # -- outputs ------------------------------------------------------------------------
    def as_quat(self, canonical: bool = False, *, scalar_first: bool = False) -> F64:
        """Unit quaternion(s), ``(4,)`` or ``(N, 4)``.

        Args:
            canonical: choose the sign with ``w > 0`` (for ``w == 0``, the first non-zero of
                x, y, z positive), resolving the double cover ``q ≡ -q``.
            scalar_first: return ``(w, x, y, z)`` instead of ``(x, y, z, w)``.
        """
        if self._q is not None:
            q = _canonical(self._q) if canonical else self._q
            if scalar_first:
                return np.array((q[3], q[0], q[1], q[2]))
            return np.array(q)
        assert self._qs is not None
        qs = _canonical_batch(self._qs) if canonical else self._qs.copy()
        if scalar_first:
            return np.ascontiguousarray(qs[:, [3, 0, 1, 2]])
        return qs

    def as_quat_tuple(self, *, scalar_first: bool = False) -> tuple[float, float, float, float]:
        """The quaternion of a single rotation as plain floats (no numpy; fastest output)."""
        if self._q is None:
            raise TypeError("as_quat_tuple() needs a single rotation; use as_quat() for batches")
        if scalar_first:
            return (self._q[3], self._q[0], self._q[1], self._q[2])
        return self._q

    def as_matrix(self) -> F64:
        """Rotation matrix(ces), ``(3, 3)`` or ``(N, 3, 3)``; ``R @ v`` == ``apply(v)``."""
        if self._q is not None:
            return np.array(sk.quat_to_matrix_xyzw(self._q))
        assert self._qs is not None
        return vk.to_matrix(self._qs)

    def as_euler(self, seq: str, degrees: bool = False, *, warn: bool = True) -> F64:
        """Euler angles ``(3,)`` or ``(N, 3)`` in the order ``seq`` names the axes.

        Ranges: first and third angles in [-π, π]; the middle angle in [-π/2, π/2] for
        Tait-Bryan sequences (three different axes) and [0, π] for proper Euler sequences.

        Gimbal lock (middle angle within 1e-7 rad of ±π/2, resp. 0 or π): the **third** angle
        of ``seq`` is set to 0 and the first carries the combined rotation; a
        :class:`GimbalLockWarning` is emitted unless ``warn=False``. Use
        :meth:`as_euler_checked` to get the lock flags without warnings.
        """
        if self._q is not None:
            a, b, c, lock = sk.quat_to_euler_xyzw(seq, self._q)
            if lock and warn:
                warnings.warn(_GIMBAL_MSG.format(seq=seq), GimbalLockWarning, stacklevel=2)
            if degrees:
                return np.array((math.degrees(a), math.degrees(b), math.degrees(c)))
            return np.array((a, b, c))
        angles, locked = self.as_euler_checked(seq, degrees)
        if warn and bool(np.any(locked)):
            warnings.warn(_GIMBAL_MSG.format(seq=seq), GimbalLockWarning, stacklevel=2)
        return angles

    def as_euler_checked(
        self, seq: str, degrees: bool = False
    ) -> tuple[F64, bool | npt.NDArray[np.bool_]]:
        """Like :meth:`as_euler` but returns ``(angles, locked)`` and never warns.

        ``locked`` is a bool for a single rotation, an ``(N,)`` bool array for a batch.
        """
        if self._q is not None:
            a, b, c, lock = sk.quat_to_euler_xyzw(seq, self._q)
            if degrees:
                a, b, c = math.degrees(a), math.degrees(b), math.degrees(c)
            return np.array((a, b, c)), lock
        assert self._qs is not None
        angles, locked = vk.to_euler(seq, self._qs)
        if degrees:
            angles = np.degrees(angles)
        return angles, locked

    def as_rpy(self) -> tuple[float, float, float] | tuple[F64, F64, F64]:
        """ROS ``(roll, pitch, yaw)`` in rad about fixed x, y, z (tf2 ``getRPY``).

        Pitch is in [-π/2, π/2]. At pitch = ±π/2 yaw is set to 0 (like tf2), without a warning.
        Floats for a single rotation, three ``(N,)`` arrays for a batch.
        """
        if self._q is not None:
            return sk.quat_to_rpy_xyzw(self._q)
        assert self._qs is not None
        angles, _ = vk.to_euler("xyz", self._qs)
        return angles[:, 0].copy(), angles[:, 1].copy(), angles[:, 2].copy()

    def as_rotvec(self, degrees: bool = False) -> F64:
        """Rotation vector(s) ``axis * angle`` with angle in [0, π], ``(3,)`` or ``(N, 3)``."""
        if self._q is not None:
            out = np.array(sk.quat_to_rotvec_xyzw(self._q))
        else:
            assert self._qs is not None
            out = vk.to_rotvec(self._qs)
        return np.degrees(out) if degrees else out

    def as_mrp(self) -> F64:
        """Modified Rodrigues Parameters ``axis * tan(angle / 4)``, ``(3,)`` or ``(N, 3)``.

        With the angle in [0, π] (the shorter way round: norm at most 1), as scipy.
        """
        q = self._rows()
        sign = np.where(q[:, 3] < 0.0, -1.0, 1.0)
        out = sign[:, None] * q[:, :3] / (1.0 + sign * q[:, 3])[:, None]
        return out[0] if self._q is not None else out

    def as_axis_angle(self, degrees: bool = False) -> tuple[F64, float | F64]:
        """``(unit axis, angle)`` with angle in [0, π]; the identity reports axis (1, 0, 0)."""
        if self._q is not None:
            x, y, z, w = self._q
            if w < 0.0:
                x, y, z, w = -x, -y, -z, -w
            s = math.sqrt(x * x + y * y + z * z)
            angle = 2.0 * math.atan2(s, w)
            axis = np.array((x / s, y / s, z / s)) if s > 0.0 else np.array((1.0, 0.0, 0.0))
            return axis, (math.degrees(angle) if degrees else angle)
        assert self._qs is not None
        q = np.where(self._qs[:, 3:4] < 0.0, -self._qs, self._qs)
        s = np.linalg.norm(q[:, :3], axis=1)
        angles = 2.0 * np.arctan2(s, q[:, 3])
        axes = np.tile(np.array((1.0, 0.0, 0.0)), (len(q), 1))
        nz = s > 0.0
        axes[nz] = q[nz, :3] / s[nz, None]
        return axes, (np.degrees(angles) if degrees else angles)

    def magnitude(self) -> float | F64:
        """Rotation angle(s) in rad, in [0, π]."""
        if self._q is not None:
            x, y, z, w = self._q
            return 2.0 * math.atan2(math.sqrt(x * x + y * y + z * z), abs(w))
        assert self._qs is not None
        q = self._qs
        return np.asarray(
            2.0 * np.arctan2(np.linalg.norm(q[:, :3], axis=1), np.abs(q[:, 3])), dtype=np.float64
        )

    # -- algebra ------------------------------------------------------------------------
    def __mul__(self, other: Rotation) -> Rotation:
        """Composition ``self * other``: apply ``other`` first, then ``self``.

        ``R_a_c = R_a_b * R_b_c``. Batches compose element-wise; a single broadcasts against a
        batch.
        """
        if not isinstance(other, Rotation):
            return NotImplemented
        if self._q is not None and other._q is not None:
            return Rotation._single(sk.quat_multiply_xyzw(self._q, other._q))
        a, b = self._rows(), other._rows()
        if len(a) != len(b) and not (self._q is not None or other._q is not None):
            raise ShapeError(f"cannot compose batches of {len(a)} and {len(b)} rotations")
        return Rotation._many(vk.multiply(a, b))

    def inv(self) -> Rotation:
        """Inverse rotation(s) (quaternion conjugate)."""
        if self._q is not None:
            return Rotation._single(sk.quat_conjugate_xyzw(self._q))
        assert self._qs is not None
        q = self._qs * np.array((-1.0, -1.0, -1.0, 1.0))
        return Rotation._many(q)

    def __pow__(self, n: float, modulus: None = None) -> Rotation:
        """The rotation(s) ``n`` times over: the same axis, ``n`` times the angle.

        As scipy: the angle is that of :meth:`as_rotvec` (in [0, π]); ``n = -1`` is
        :meth:`inv`, ``n = 0`` the identity.
        """
        if modulus is not None:
            raise NotImplementedError("modular exponentiation is not defined for rotations")
        n = float(n)
        if n == 0.0:
            return Rotation.identity(None if self._q is not None else len(self))
        if n == 1.0:
            return self
        if n == -1.0:
            return self.inv()
        return Rotation.from_rotvec(n * self.as_rotvec())

    def mean(self, weights: npt.ArrayLike | None = None) -> Rotation:
        """The chordal L2 mean of the rotation(s), as scipy's ``mean``.

        The rotation whose matrix is nearest to theirs in the weighted sum of squared
        Frobenius distances.

        Args:
            weights: ``(N,)`` non-negative weights (default: equal).

        Raises:
            ShapeError: weights of another length than the batch.
            ValueError: a negative weight.
        """
        q = self._rows()
        if weights is None:
            w = np.ones(len(q))
        else:
            w = np.asarray(weights, dtype=np.float64).reshape(-1)
            if w.shape != (len(q),):
                raise ShapeError(f"{w.size} weights for {len(q)} rotations")
            if (w < 0.0).any():
                raise ValueError("weights must be non-negative")
        # The eigenvector of the largest eigenvalue of sum(w q q^T) (Markley et al., 2007).
        _, vectors = np.linalg.eigh(np.einsum("i,ij,ik->jk", w, q, q))
        return Rotation.from_quat(vectors[:, -1])

    @classmethod
    def align_vectors(
        cls, a: npt.ArrayLike, b: npt.ArrayLike, weights: npt.ArrayLike | None = None
    ) -> tuple[Rotation, float]:
        """The rotation ``R`` that best takes vectors ``b`` onto vectors ``a`` (scipy's).

        Minimises ``sum(w_i * |a_i - R b_i|^2)`` (Kabsch: one SVD); a single pair gives the
        smallest rotation taking the direction of ``b`` to that of ``a``.

        Args:
            a: ``(3,)`` or ``(N, 3)`` vectors in the target frame.
            b: the same number of vectors in the source frame.
            weights: ``(N,)`` non-negative weights (default: equal).

        Returns:
            ``(R, rssd)``: the single rotation and the root of the weighted sum of squared
            distances left.

        Raises:
            ShapeError: ``a`` and ``b`` (or the weights) of different lengths.
            ValueError: a negative weight; a single pair with a zero vector.
        """
        pa, pb = parse_rows(a, 3, "vectors a"), parse_rows(b, 3, "vectors b")
        va = np.array([pa]) if isinstance(pa, tuple) else np.asarray(pa)
        vb = np.array([pb]) if isinstance(pb, tuple) else np.asarray(pb)
        if va.shape != vb.shape:
            raise ShapeError(f"vectors a {va.shape} and b {vb.shape} differ in shape")
        check_finite_array(va, "vectors a")
        check_finite_array(vb, "vectors b")
        w = np.ones(len(va)) if weights is None else np.asarray(weights, np.float64).reshape(-1)
        if w.shape != (len(va),):
            raise ShapeError(f"{w.size} weights for {len(va)} vector pairs")
        if (w < 0.0).any():
            raise ValueError("weights must be non-negative")
        if len(va) == 1:  # the smallest rotation between the two directions
            na, nb = np.linalg.norm(va[0]), np.linalg.norm(vb[0])
            if na == 0.0 or nb == 0.0:
                raise ValueError("cannot align a zero vector")
            ua, ub = va[0] / na, vb[0] / nb
            axis = np.cross(ub, ua)
            s, c = np.linalg.norm(axis), float(np.dot(ub, ua))
            if s > 1e-12:
                rotation = cls.from_rotvec(axis / s * math.atan2(s, c))
            elif c > 0.0:
                rotation = cls.identity()
            else:  # opposite: half a turn about any axis normal to b
                normal = np.cross(ub, np.eye(3)[int(np.argmin(np.abs(ub)))])
                rotation = cls.from_rotvec(normal / np.linalg.norm(normal) * math.pi)
            residual = w[0] * float(np.sum((va[0] - rotation.apply(vb[0])) ** 2))
            return rotation, math.sqrt(max(residual, 0.0))
        h = np.einsum("i,ij,ik->jk", w, va, vb)
        u, sigma, vt = np.linalg.svd(h)
        d = np.sign(np.linalg.det(u @ vt)) or 1.0
        matrix = u @ np.diag([1.0, 1.0, d]) @ vt
        rotation = cls.from_matrix(matrix, atol=1e-6)
        residual = float(np.einsum("i,ij->", w, va**2) + np.einsum("i,ij->", w, vb**2))
        residual -= 2.0 * float(sigma[0] + sigma[1] + d * sigma[2])
        return rotation, math.sqrt(max(residual, 0.0))

    def apply(self, vectors: npt.ArrayLike, inverse: bool = False) -> F64:
        """Rotate vector(s): ``(3,)`` or ``(N, 3)``; the lecture's ``p' = q p q⁻¹``.

        A single rotation rotates every vector; a batch of N pairs with N vectors or
        broadcasts over one vector. ``inverse=True`` applies the inverse rotation.
        """
        p = parse_rows(vectors, 3, "vectors")
        if self._q is not None:
            q = sk.quat_conjugate_xyzw(self._q) if inverse else self._q
            if isinstance(p, tuple):
                return np.array(sk.quat_rotate_vector_xyzw(q, (p[0], p[1], p[2])))
            return vk.rotate(np.array([q]), p)
        assert self._qs is not None
        qs = self._qs * np.array((-1.0, -1.0, -1.0, 1.0)) if inverse else self._qs
        v = np.array([p]) if isinstance(p, tuple) else p
        if len(v) != len(qs) and len(v) != 1:
            raise ShapeError(f"cannot apply {len(qs)} rotations to {len(v)} vectors")
        return vk.rotate(qs, v)

    def slerp(self, other: Rotation, t: npt.ArrayLike) -> Rotation:
        """Spherical linear interpolation along the shortest arc (tf2's formula).

        ``t = 0`` gives ``self``, ``t = 1`` gives ``other`` (up to the sign of the
        quaternion). A scalar ``t`` with two single rotations gives a single rotation; an
        ``(M,)`` array of ``t`` (or batch inputs) gives a batch.
        """
        tt = parse_scalar_or_array(t, "t")
        if self._q is not None and other._q is not None and isinstance(tt, float):
            return Rotation._single(
                sk.quat_normalize_xyzw(*sk.quat_slerp_xyzw(self._q, other._q, tt))
            )
        a, b = self._rows(), other._rows()
        n = max(len(a), len(b), 1 if isinstance(tt, float) else len(tt))
        tarr = np.broadcast_to(np.asarray(tt, dtype=np.float64), (n,))
        return Rotation._many(vk.normalize(vk.slerp(a, b, tarr)))

    def approx_equal(
        self, other: Rotation, atol: float = 1e-8, degrees: bool = False
    ) -> bool | npt.NDArray[np.bool_]:
        """True where the two rotations differ by at most ``atol`` (rad, or degrees).

        Compares rotations, not quaternion components, so ``q`` and ``-q`` are equal.
        """
        diff = (self.inv() * other).magnitude()
        tol = math.radians(atol) if degrees else atol
        if isinstance(diff, float):
            return diff <= tol
        return np.asarray(diff <= tol)

    # -- the lecture's two composition rules ---------------------------------------------
    def rotated_about_world(self, rotation: Rotation) -> Rotation:
        """This orientation turned by ``rotation`` about *fixed world* axes.

        ``O_final = O_rot ⊗ O_init``.
        """
        return rotation * self

    def rotated_about_body(self, rotation: Rotation) -> Rotation:
        """This orientation turned by ``rotation`` about its *own (body)* axes.

        ``O_final = O_init ⊗ O_rot``.
        """
        return self * rotation


def compose_world(O_rot: Rotation, O_init: Rotation) -> Rotation:
    """Rotate orientation ``O_init`` about a world (fixed) axis: ``O_rot ⊗ O_init``."""
    return O_rot * O_init


def compose_body(O_init: Rotation, O_rot: Rotation) -> Rotation:
    """Rotate orientation ``O_init`` about its own body axis: ``O_init ⊗ O_rot``."""
    return O_init * O_rot


def _pad_euler_sequence(seq: str, angles: npt.ArrayLike) -> tuple[str, npt.ArrayLike]:
    """Extend a 1- or 2-axis sequence to 3 axes with zero angles (the same rotation)."""
    axes = "xyz" if seq.islower() else "XYZ"
    if any(ch not in axes for ch in seq) or (len(seq) == 2 and seq[0] == seq[1]):
        sk.euler_params(seq)  # raises UnknownSequenceError with the full explanation
    padded = seq
    while len(padded) < 3:
        padded += next(ch for ch in axes if ch != padded[-1])
    arr = np.asarray(angles, dtype=np.float64)
    k = len(seq)
    # As scipy (1.17): one rotation takes a scalar or (k,), N rotations (N, k); so a batch
    # of one-axis angles is (N, 1), and (N,) with N != 1 is refused (older scipy read it as
    # N rotations).
    if k == 1 and arr.shape in ((), (1,)):
        return padded, (float(arr.reshape(-1)[0]), 0.0, 0.0)
    if k == 2 and arr.shape == (2,):
        return padded, (float(arr[0]), float(arr[1]), 0.0)
    if arr.ndim != 2 or arr.shape[1] != k:
        single = "() or (1,)" if k == 1 else "(2,)"
        raise ShapeError(
            f"Euler sequence {seq!r} takes angles of shape {single} for one rotation or "
            f"(N, {k}) for N, got {arr.shape}"
        )
    return padded, np.concatenate([arr, np.zeros((len(arr), 3 - k))], axis=1)
