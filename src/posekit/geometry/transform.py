"""Rigid transforms in 3-D (SE(3)): a rotation plus a translation, one or a batch of N.

Naming: ``T_a_b`` maps coordinates in frame ``b`` into frame ``a`` (``p_a = T_a_b.apply(p_b)``),
which is also "the pose of frame ``b`` expressed in frame ``a``" and what tf2's
``lookup_transform(target=a, source=b)`` returns. Inner indices cancel when chaining:
``T_a_c = T_a_b * T_b_c``. As a 4×4 homogeneous matrix ``[[R, t], [0, 1]]``.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

from posekit.geometry._lazy import lazy_module

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from posekit.geometry._parse import F64
else:
    np = lazy_module("numpy")

from posekit.geometry import _quat as sk
from posekit.geometry._parse import (
    check_finite,
    check_finite_array,
    parse_rows,
    parse_scalar_or_array,
)
from posekit.geometry.errors import NonOrthonormalMatrixError, ShapeError
from posekit.geometry.rotation import Rotation

__all__ = ["Transform"]


class Transform:
    """SE(3) transform(s) ``T_a_b``: rotation ``R_a_b`` and translation ``t_a_b`` (metres).

    ``t_a_b`` is the origin of frame ``b`` expressed in frame ``a``. Build with
    ``Transform(rotation, translation)``, :meth:`from_matrix`, :meth:`identity`; chain with
    ``*``; invert with :meth:`inv`; map points with :meth:`apply`.

    Examples:
        The robot at (1, 2) in ``odom`` facing +y, a camera 0.5 m ahead and 0.2 m up: frames
        cancel in ``T_odom_cam = T_odom_base * T_base_cam``, and the camera's origin is
        ``t_odom_base + R_odom_base @ t_base_cam = (1, 2, 0) + (0, 0.5, 0.2)``:

        >>> import numpy as np
        >>> from posekit.geometry import Rotation, Transform
        >>> T_odom_base = Transform(Rotation.from_euler("z", 90, degrees=True), [1.0, 2.0, 0.0])
        >>> T_base_cam = Transform(Rotation.identity(), [0.5, 0.0, 0.2])
        >>> (T_odom_base * T_base_cam).translation.round(6).tolist()
        [1.0, 2.5, 0.2]

        A point 1 m ahead of the robot, in ``odom``; and the inverse, ``T_base_odom``, whose
        translation is ``-R^T t = -Rz(-90°) (1, 2, 0) = (-2, 1, 0)``:

        >>> T_odom_base.apply([1.0, 0.0, 0.0]).round(6).tolist()
        [1.0, 3.0, 0.0]
        >>> np.allclose(T_odom_base.inv().translation, [-2.0, 1.0, 0.0])
        True
    """

    __slots__ = ("_r", "_t", "_ts")

    _r: Rotation
    _t: sk.Vec3 | None
    _ts: F64 | None

    def __init__(
        self, rotation: Rotation | None = None, translation: npt.ArrayLike = (0.0, 0.0, 0.0)
    ) -> None:
        """Args:
        rotation: single or batch :class:`Rotation` (default identity).
        translation: ``(3,)`` or ``(N, 3)`` metres (default zero). A single rotation with
            N translations (or vice versa) broadcasts to a batch of N.
        """
        rot = Rotation.identity() if rotation is None else rotation
        if not isinstance(rot, Rotation):
            raise TypeError(f"rotation must be a posekit Rotation, got {type(rot).__name__}")
        p = parse_rows(translation, 3, "translation")
        if isinstance(p, tuple):
            check_finite(p, "translation")
            if rot.single:
                self._r, self._t, self._ts = rot, (p[0], p[1], p[2]), None
                return
            self._r, self._t = rot, None
            self._ts = np.tile(np.array(p), (len(rot), 1))
            return
        check_finite_array(p, "translation")
        if rot.single:
            rot = Rotation._many(np.tile(rot._rows(), (len(p), 1)))
        elif len(rot) != len(p):
            raise ShapeError(f"{len(rot)} rotations but {len(p)} translations")
        self._r, self._t, self._ts = rot, None, p

    @classmethod
    def _single(cls, r: Rotation, t: sk.Vec3) -> Transform:
        out = object.__new__(cls)
        out._r, out._t, out._ts = r, t, None
        return out

    @classmethod
    def _many(cls, r: Rotation, ts: F64) -> Transform:
        out = object.__new__(cls)
        out._r, out._t, out._ts = r, None, ts
        return out

    def _trows(self) -> F64:
        if self._ts is not None:
            return self._ts
        return np.array([self._t])

    # -- construction -----------------------------------------------------------------------
    @classmethod
    def identity(cls, num: int | None = None) -> Transform:
        """The identity transform, or a batch of ``num`` identities."""
        if num is None:
            return cls._single(Rotation.identity(), (0.0, 0.0, 0.0))
        return cls._many(Rotation.identity(num), np.zeros((num, 3)))

    @classmethod
    def from_translation(cls, translation: npt.ArrayLike) -> Transform:
        """A pure translation (identity rotation)."""
        return cls(None, translation)

    @classmethod
    def from_rotation(cls, rotation: Rotation) -> Transform:
        """A pure rotation (zero translation)."""
        if rotation.single:
            return cls(rotation)
        return cls(rotation, np.zeros((len(rotation), 3)))

    @classmethod
    def from_xyz_rpy(cls, xyz: npt.ArrayLike, rpy: npt.ArrayLike) -> Transform:
        """``T_parent_child`` of a URDF ``<origin xyz=... rpy=...>`` or an SDF ``<pose>``.

        ``xyz`` is the translation (m); ``rpy`` the fixed-axis roll, pitch, yaw (rad,
        ``R = Rz(yaw) Ry(pitch) Rx(roll)``, :meth:`Rotation.from_rpy`). ``.as_matrix()``
        gives the 4x4 homogeneous matrix.

        Examples:
            >>> import math
            >>> from posekit.geometry import Transform
            >>> T = Transform.from_xyz_rpy((1.0, 2.0, 3.0), (0.0, 0.0, math.pi / 2))
            >>> T.apply((1.0, 0.0, 0.0)).round(12).tolist()
            [1.0, 3.0, 3.0]
        """
        roll, pitch, yaw = (float(v) for v in np.asarray(rpy, dtype=np.float64).reshape(3))
        return cls(Rotation.from_rpy(roll, pitch, yaw), xyz)

    @classmethod
    def from_matrix(cls, matrix: npt.ArrayLike, *, atol: float = 1e-6) -> Transform:
        """From homogeneous matrix(ces) ``(4, 4)`` or ``(N, 4, 4)`` ``[[R, t], [0, 0, 0, 1]]``.

        Raises:
            ShapeError: wrong shape.
            NonOrthonormalMatrixError: ``R`` is not a rotation, or the last row is not
                ``(0, 0, 0, 1)`` (within ``atol``).
        """
        m = np.asarray(matrix, dtype=np.float64)
        if m.shape == (4, 4):
            if not np.allclose(m[3], (0.0, 0.0, 0.0, 1.0), rtol=0.0, atol=atol):
                raise NonOrthonormalMatrixError(
                    f"last row of a homogeneous transform must be (0, 0, 0, 1), got {m[3].tolist()}"
                )
            t = m[:3, 3].tolist()
            check_finite(tuple(t), "translation")
            return cls._single(Rotation.from_matrix(m[:3, :3], atol=atol), (t[0], t[1], t[2]))
        if m.ndim == 3 and m.shape[1:] == (4, 4):
            if not np.allclose(m[:, 3], (0.0, 0.0, 0.0, 1.0), rtol=0.0, atol=atol):
                raise NonOrthonormalMatrixError(
                    "last row of every homogeneous transform must be (0, 0, 0, 1)"
                )
            ts = np.ascontiguousarray(m[:, :3, 3])
            check_finite_array(ts, "translation")
            return cls._many(Rotation.from_matrix(m[:, :3, :3], atol=atol), ts)
        raise ShapeError(f"matrix must have shape (4, 4) or (N, 4, 4), got shape {m.shape}")

    @classmethod
    def random(
        cls, num: int | None = None, rng: np.random.Generator | int | None = None, *,
        scale: float = 1.0,
    ) -> Transform:
        """Random transform(s): uniform rotation, translation ~ N(0, scale²) per axis."""
        gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
        r = Rotation.random(num, gen)
        t = gen.standard_normal((1 if num is None else num, 3)) * scale
        if num is None:
            return cls._single(r, (float(t[0, 0]), float(t[0, 1]), float(t[0, 2])))
        return cls._many(r, t)

    # -- protocol -------------------------------------------------------------------------
    @property
    def single(self) -> bool:
        """True for one transform, False for a batch."""
        return self._t is not None

    @property
    def rotation(self) -> Rotation:
        """The rotation part ``R_a_b`` (single or batch)."""
        return self._r

    @property
    def translation(self) -> F64:
        """The translation ``t_a_b`` (metres): ``(3,)`` or ``(N, 3)`` copy."""
        if self._t is not None:
            return np.array(self._t)
        assert self._ts is not None
        return self._ts.copy()

    def translation_tuple(self) -> tuple[float, float, float]:
        """Translation of a single transform as plain floats (no numpy)."""
        if self._t is None:
            raise TypeError("translation_tuple() needs a single transform")
        return self._t

    def __len__(self) -> int:
        if self._ts is None:
            raise TypeError("a single Transform has no len(); check .single first")
        return len(self._ts)

    def __bool__(self) -> bool:
        return True

    def __getitem__(self, index: Any) -> Transform:
        if self._ts is None:
            raise TypeError("a single Transform is not subscriptable")
        r = self._r[index]
        if r.single:
            t = self._ts[index].tolist()
            return Transform._single(r, (t[0], t[1], t[2]))
        return Transform._many(r, np.array(self._ts[index]))

    def __iter__(self) -> Iterator[Transform]:
        if self._ts is None:
            raise TypeError("a single Transform is not iterable")
        for i in range(len(self._ts)):
            yield self[i]

    def __repr__(self) -> str:
        if self._t is not None:
            q = self._r.as_quat_tuple()
            return f"Transform(translation={list(self._t)!r}, quat_xyzw={list(q)!r})"
        assert self._ts is not None
        return f"Transform(batch of {len(self._ts)})"

    # -- outputs ------------------------------------------------------------------------
    def as_matrix(self) -> F64:
        """Homogeneous matrix(ces) ``(4, 4)`` or ``(N, 4, 4)``."""
        if self._t is not None:
            m = np.eye(4)
            m[:3, :3] = self._r.as_matrix()
            m[:3, 3] = self._t
            return m
        assert self._ts is not None
        out = np.zeros((len(self._ts), 4, 4))
        out[:, :3, :3] = self._r.as_matrix()
        out[:, :3, 3] = self._ts
        out[:, 3, 3] = 1.0
        return out

    # -- algebra --------------------------------------------------------------------------
    def __mul__(self, other: Transform) -> Transform:
        """Chain ``T_a_c = T_a_b * T_b_c``: ``(R1 R2, R1 t2 + t1)`` (apply ``other`` first)."""
        if not isinstance(other, Transform):
            return NotImplemented
        qa, qb = self._r._q, other._r._q
        if self._t is not None and other._t is not None and qa is not None and qb is not None:
            rt = sk.quat_rotate_vector_xyzw(qa, other._t)
            t = self._t
            return Transform._single(
                Rotation._single(sk.quat_multiply_xyzw(qa, qb)),
                (rt[0] + t[0], rt[1] + t[1], rt[2] + t[2]),
            )
        r = self._r * other._r
        ts = self._r.apply(other._trows()) + self._trows()
        return Transform._many(r, np.asarray(ts, dtype=np.float64))

    def inv(self) -> Transform:
        """Inverse ``T_b_a`` of ``T_a_b``: ``(Rᵀ, -Rᵀ t)``."""
        rinv = self._r.inv()
        if self._t is not None and rinv._q is not None:
            x, y, z = sk.quat_rotate_vector_xyzw(rinv._q, self._t)
            return Transform._single(rinv, (-x, -y, -z))
        return Transform._many(rinv, -rinv.apply(self._trows()))

    def apply(self, points: npt.ArrayLike, inverse: bool = False) -> F64:
        """Map point(s) ``p_b`` (``(3,)`` or ``(N, 3)``, metres) to ``p_a = R p_b + t``.

        ``inverse=True`` maps the other way, ``p_b = Rᵀ (p_a - t)``.
        """
        if inverse:
            return self.inv().apply(points)
        p = parse_rows(points, 3, "points")
        q = self._r._q
        if self._t is not None and q is not None and isinstance(p, tuple):
            x, y, z = sk.quat_rotate_vector_xyzw(q, (p[0], p[1], p[2]))
            t = self._t
            return np.array((x + t[0], y + t[1], z + t[2]))
        return np.asarray(self._r.apply(p) + self._trows(), dtype=np.float64)

    def interpolate(self, other: Transform, t: npt.ArrayLike) -> Transform:
        """tf2-style interpolation: lerp of translations, shortest-arc slerp of rotations.

        ``t = 0`` gives ``self``, ``t = 1`` gives ``other``; ``t`` scalar or ``(M,)``.
        No screw motion (matches tf2's buffer interpolation, not pytransform3d's ScLERP).
        """
        tt = parse_scalar_or_array(t, "t")
        if self._t is not None and other._t is not None and isinstance(tt, float):
            a, b = self._t, other._t
            s = 1.0 - tt
            return Transform._single(
                self._r.slerp(other._r, tt),
                (s * a[0] + tt * b[0], s * a[1] + tt * b[1], s * a[2] + tt * b[2]),
            )
        r = self._r.slerp(other._r, tt)
        tarr = np.broadcast_to(np.asarray(tt, dtype=np.float64), (len(r),))[:, None]
        ts = (1.0 - tarr) * self._trows() + tarr * other._trows()
        return Transform._many(r, np.ascontiguousarray(ts))

    def approx_equal(
        self, other: Transform, atol: float = 1e-8, *, rot_atol: float | None = None
    ) -> bool | npt.NDArray[np.bool_]:
        """True where translations differ by at most ``atol`` (m, max-norm) and rotations by
        at most ``rot_atol`` (rad, default ``atol``)."""
        rok = self._r.approx_equal(other._r, atol if rot_atol is None else rot_atol)
        if self._t is not None and other._t is not None:
            dt = max(abs(a - b) for a, b in zip(self._t, other._t, strict=True))
            return bool(rok) and dt <= atol
        d = np.abs(self._trows() - other._trows()).max(axis=1)
        return np.asarray(np.logical_and(rok, d <= atol))

    def distance(self, other: Transform) -> tuple[float, float]:
        """(translation distance in m, rotation angle in rad) between two single transforms."""
        if self._t is None or other._t is None:
            raise TypeError("distance() needs single transforms")
        d = math.dist(self._t, other._t)
        ang = (self._r.inv() * other._r).magnitude()
        assert isinstance(ang, float)
        return d, ang
