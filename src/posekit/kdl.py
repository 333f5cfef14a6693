"""A PyKDL-compatible subset (``Vector``, ``Rotation``, ``Frame``) built on posekit.geometry.

Lets code written for PyKDL, like the lecture's ``kdl_chain_demo``, run unchanged after
``import posekit.kdl as PyKDL``. Method names and behaviour follow PyKDL (Orocos KDL), including
its quirks: ``Vector * Vector`` is the cross product, ``GetRPY`` sets *roll* (not yaw) to 0 at
gimbal lock, quaternions are ``(x, y, z, w)``. All angles in radians, rotations active,
``Frame(M, p)`` maps child coordinates into the parent (``p_parent = F * p_child``).

Not covered: twists/wrenches, chains, solvers, jacobians.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import overload

from posekit.geometry import _quat as sk
from posekit.geometry.errors import ZeroAxisError

__all__ = ["Frame", "Rotation", "Vector", "cross", "dot"]


class Vector:
    """A 3-vector with PyKDL's interface: ``v.x()`` reads, ``v.x(1.0)`` writes, ``v[i]``."""

    __slots__ = ("_v",)

    def __init__(self, x: float = 0.0, y: float = 0.0, z: float = 0.0) -> None:
        self._v = [float(x), float(y), float(z)]

    @staticmethod
    def Zero() -> Vector:
        """The zero vector."""
        return Vector()

    def x(self, value: float | None = None) -> float:
        """Get (no argument) or set the x component."""
        if value is not None:
            self._v[0] = float(value)
        return self._v[0]

    def y(self, value: float | None = None) -> float:
        """Get (no argument) or set the y component."""
        if value is not None:
            self._v[1] = float(value)
        return self._v[1]

    def z(self, value: float | None = None) -> float:
        """Get (no argument) or set the z component."""
        if value is not None:
            self._v[2] = float(value)
        return self._v[2]

    def __getitem__(self, i: int) -> float:
        if not -3 <= i < 3:
            raise IndexError("Vector index out of range")
        return self._v[i]

    def __setitem__(self, i: int, value: float) -> None:
        if not -3 <= i < 3:
            raise IndexError("Vector index out of range")
        self._v[i] = float(value)

    def __len__(self) -> int:
        return 3

    def __iter__(self) -> Iterator[float]:
        return iter(self._v)

    def _t(self) -> sk.Vec3:
        return (self._v[0], self._v[1], self._v[2])

    def __add__(self, o: Vector) -> Vector:
        return Vector(self._v[0] + o._v[0], self._v[1] + o._v[1], self._v[2] + o._v[2])

    def __sub__(self, o: Vector) -> Vector:
        return Vector(self._v[0] - o._v[0], self._v[1] - o._v[1], self._v[2] - o._v[2])

    def __neg__(self) -> Vector:
        return Vector(-self._v[0], -self._v[1], -self._v[2])

    @overload
    def __mul__(self, o: Vector) -> Vector: ...
    @overload
    def __mul__(self, o: float) -> Vector: ...
    def __mul__(self, o: Vector | float) -> Vector:
        """Scalar product, or (as in PyKDL) the cross product for ``Vector * Vector``."""
        if isinstance(o, Vector):
            return cross(self, o)
        return Vector(self._v[0] * o, self._v[1] * o, self._v[2] * o)

    def __rmul__(self, o: float) -> Vector:
        return Vector(self._v[0] * o, self._v[1] * o, self._v[2] * o)

    def __truediv__(self, o: float) -> Vector:
        return Vector(self._v[0] / o, self._v[1] / o, self._v[2] / o)

    def __eq__(self, o: object) -> bool:
        if not isinstance(o, Vector):
            return NotImplemented
        return self._v == o._v

    __hash__ = None  # type: ignore[assignment]  # mutable, like PyKDL

    def Norm(self) -> float:
        """Euclidean length."""
        return math.hypot(*self._v)

    def Normalize(self, eps: float = 1e-5) -> float:
        """Scale to unit length in place and return the old length.

        As KDL, below ``eps`` the vector becomes (1, 0, 0).
        """
        n = self.Norm()
        if n < eps:
            self._v = [1.0, 0.0, 0.0]
        else:
            self._v = [c / n for c in self._v]
        return n

    def __repr__(self) -> str:
        return f"[{self._v[0]:12.6f},{self._v[1]:12.6f},{self._v[2]:12.6f}]"


def dot(a: Vector, b: Vector) -> float:
    """Scalar product (PyKDL ``dot``)."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a: Vector, b: Vector) -> Vector:
    """Cross product ``a × b``."""
    return Vector(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


class Rotation:
    """A rotation matrix with PyKDL's interface (stored as a unit quaternion internally).

    ``Rotation(Xx, Yx, Zx, Xy, Yy, Zy, Xz, Yz, Zz)`` takes the matrix row by row (the columns
    are the rotated unit axes X, Y, Z), like PyKDL.
    """

    __slots__ = ("_q",)

    def __init__(self, *m: float) -> None:
        if not m:
            self._q: sk.Quat = (0.0, 0.0, 0.0, 1.0)
        elif len(m) == 9:
            rows = ((m[0], m[1], m[2]), (m[3], m[4], m[5]), (m[6], m[7], m[8]))
            self._q = sk.matrix_to_quat_xyzw(
                tuple(tuple(float(v) for v in r) for r in rows)  # type: ignore[arg-type]
            )
        else:
            raise TypeError("Rotation() takes no arguments or the 9 matrix entries row by row")

    @classmethod
    def _from_q(cls, q: sk.Quat) -> Rotation:
        r = object.__new__(cls)
        r._q = q
        return r

    @staticmethod
    def Identity() -> Rotation:
        """The identity rotation."""
        return Rotation()

    @staticmethod
    def Quaternion(x: float, y: float, z: float, w: float) -> Rotation:
        """From a quaternion in ROS order ``(x, y, z, w)``; normalised like KDL."""
        return Rotation._from_q(sk.quat_normalize_xyzw(float(x), float(y), float(z), float(w)))

    @staticmethod
    def RPY(roll: float, pitch: float, yaw: float) -> Rotation:
        """Roll about fixed X, then pitch about fixed Y, then yaw about fixed Z (= tf2 setRPY)."""
        return Rotation._from_q(sk.quat_from_rpy_xyzw(roll, pitch, yaw))

    @staticmethod
    def EulerZYX(alpha: float, beta: float, gamma: float) -> Rotation:
        """Z (alpha), then moving Y (beta), then moving X (gamma) == ``RPY(gamma, beta, alpha)``."""
        return Rotation._from_q(sk.quat_from_euler_xyzw("ZYX", alpha, beta, gamma))

    @staticmethod
    def EulerZYZ(alpha: float, beta: float, gamma: float) -> Rotation:
        """Z, then moving Y, then moving Z."""
        return Rotation._from_q(sk.quat_from_euler_xyzw("ZYZ", alpha, beta, gamma))

    @staticmethod
    def RotX(angle: float) -> Rotation:
        """Rotation by ``angle`` about X."""
        return Rotation._from_q(sk.quat_from_axis_angle_xyzw((1.0, 0.0, 0.0), angle))

    @staticmethod
    def RotY(angle: float) -> Rotation:
        """Rotation by ``angle`` about Y."""
        return Rotation._from_q(sk.quat_from_axis_angle_xyzw((0.0, 1.0, 0.0), angle))

    @staticmethod
    def RotZ(angle: float) -> Rotation:
        """Rotation by ``angle`` about Z."""
        return Rotation._from_q(sk.quat_from_axis_angle_xyzw((0.0, 0.0, 1.0), angle))

    @staticmethod
    def Rot(axis: Vector, angle: float) -> Rotation:
        """Rotation by ``angle`` about ``axis`` (normalised; zero axis raises)."""
        n = axis.Norm()
        if not 0.0 < n < math.inf:
            raise ZeroAxisError("Rotation.Rot needs a non-zero axis")
        u = (axis[0] / n, axis[1] / n, axis[2] / n)
        return Rotation._from_q(sk.quat_from_axis_angle_xyzw(u, angle))

    def _m(self) -> sk.Mat3:
        return sk.quat_to_matrix_xyzw(self._q)

    def GetQuaternion(self) -> tuple[float, float, float, float]:
        """``(x, y, z, w)``, from the matrix (so ``w >= 0`` when the trace is positive)."""
        return sk.matrix_to_quat_xyzw(self._m())

    def GetRPY(self) -> tuple[float, float, float]:
        """``(roll, pitch, yaw)`` with KDL's rule: within 1e-12 of pitch ±π/2, roll = 0."""
        (m00, m01, _), (m10, m11, _), (m20, m21, m22) = self._m()
        pitch = math.atan2(-m20, math.hypot(m00, m10))
        if abs(pitch) > math.pi / 2.0 - 1e-12:
            return 0.0, pitch, math.atan2(-m01, m11)
        return math.atan2(m21, m22), pitch, math.atan2(m10, m00)

    def GetEulerZYX(self) -> tuple[float, float, float]:
        """``(alpha, beta, gamma)`` of :meth:`EulerZYX` (= ``GetRPY`` reversed)."""
        r, p, y = self.GetRPY()
        return y, p, r

    def GetRot(self) -> Vector:
        """Rotation vector (axis × angle)."""
        return Vector(*sk.quat_to_rotvec_xyzw(self._q))

    def Inverse(self) -> Rotation:
        """The inverse (transpose) rotation."""
        return Rotation._from_q(sk.quat_conjugate_xyzw(self._q))

    def UnitX(self) -> Vector:
        """First column: the rotated X axis."""
        m = self._m()
        return Vector(m[0][0], m[1][0], m[2][0])

    def UnitY(self) -> Vector:
        """Second column: the rotated Y axis."""
        m = self._m()
        return Vector(m[0][1], m[1][1], m[2][1])

    def UnitZ(self) -> Vector:
        """Third column: the rotated Z axis."""
        m = self._m()
        return Vector(m[0][2], m[1][2], m[2][2])

    def __getitem__(self, ij: tuple[int, int]) -> float:
        i, j = ij
        return self._m()[i][j]

    @overload
    def __mul__(self, o: Vector) -> Vector: ...
    @overload
    def __mul__(self, o: Rotation) -> Rotation: ...
    def __mul__(self, o: Vector | Rotation) -> Vector | Rotation:
        """``R * v`` rotates a vector; ``R1 * R2`` composes (``R2`` applied first)."""
        if isinstance(o, Vector):
            return Vector(*sk.quat_rotate_vector_xyzw(self._q, o._t()))
        if isinstance(o, Rotation):
            return Rotation._from_q(sk.quat_multiply_xyzw(self._q, o._q))
        return NotImplemented

    def __eq__(self, o: object) -> bool:
        if not isinstance(o, Rotation):
            return NotImplemented
        return all(
            abs(a - b) < 1e-6 for ra, rb in zip(self._m(), o._m(), strict=True)
            for a, b in zip(ra, rb, strict=True)
        )

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        rows = ";\n ".join(",".join(f"{v:12.6f}" for v in r) for r in self._m())
        return f"[{rows}]"


class Frame:
    """A rigid transform with PyKDL's interface: rotation ``M`` and origin ``p``."""

    __slots__ = ("M", "p")

    M: Rotation
    p: Vector

    def __init__(self, *args: Rotation | Vector) -> None:
        """``Frame()``, ``Frame(M)``, ``Frame(p)`` or ``Frame(M, p)``, like PyKDL."""
        self.M = Rotation()
        self.p = Vector()
        if len(args) > 2:
            raise TypeError("Frame() takes at most a Rotation and a Vector")
        for a in args:
            if isinstance(a, Rotation):
                self.M = a
            elif isinstance(a, Vector):
                self.p = a
            else:
                raise TypeError(f"Frame() arguments must be Rotation/Vector, not {type(a)}")

    @staticmethod
    def Identity() -> Frame:
        """The identity frame."""
        return Frame()

    def Inverse(self) -> Frame:
        """``(Rᵀ, -Rᵀ p)``."""
        inv = self.M.Inverse()
        return Frame(inv, -(inv * self.p))

    @overload
    def __mul__(self, o: Vector) -> Vector: ...
    @overload
    def __mul__(self, o: Frame) -> Frame: ...
    def __mul__(self, o: Vector | Frame) -> Vector | Frame:
        """``F * v`` maps a point; ``F_a_b * F_b_c`` chains to ``F_a_c``."""
        if isinstance(o, Vector):
            return self.M * o + self.p
        if isinstance(o, Frame):
            return Frame(self.M * o.M, self.M * o.p + self.p)
        return NotImplemented

    def __eq__(self, o: object) -> bool:
        if not isinstance(o, Frame):
            return NotImplemented
        return self.M == o.M and all(abs(a - b) < 1e-6 for a, b in zip(self.p, o.p, strict=True))

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return f"[{self.M!r},\n {self.p!r}]"
