"""Planar poses (SE(2)) with the exact exponential and logarithm (arc motion).

``Pose2D(x, y, theta)`` named ``T_a_b`` maps frame-``b`` coordinates into frame ``a``: the
pose of ``b`` in ``a``, heading ``theta`` (rad, counter-clockwise about +z, REP 103), kept in
[-π, π]. Chaining cancels inner indices: ``T_odom_base2 = T_odom_base1 * Pose2D.exp(...)``.

Exact-arc odometry: a body moving with constant body-frame velocity ``(vx, vy, ω)`` for
``dt`` seconds travels the motion ``Pose2D.exp(vx*dt, vy*dt, ω*dt)`` expressed in its starting
body frame, so ``T_odom_base_new = T_odom_base * Pose2D.exp(vx*dt, vy*dt, ω*dt)`` is exact
for any ``dt`` (a circle arc of radius ``v/ω``, a straight line when ``ω = 0``).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from posekit.geometry._lazy import lazy_module

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from posekit.geometry._parse import F64
else:
    np = lazy_module("numpy")

from posekit.geometry._parse import check_finite, parse_rows
from posekit.geometry._quat import wrap_angle
from posekit.geometry.errors import NonOrthonormalMatrixError, ShapeError

__all__ = ["Pose2D", "integrate_arc"]

_SMALL = 1e-6


def integrate_arc(
    x: float, y: float, theta: float, dx: float, dy: float, dtheta: float
) -> tuple[float, float, float]:
    """``Pose2D(x, y, theta) * Pose2D.exp(dx, dy, dtheta)`` on plain floats, for hot loops.

    The one implementation of the SE(2) exponential: :meth:`Pose2D.exp` calls it from the
    origin.

    Args:
        x: start position x of ``T_fixed_body`` (m).
        y: start position y of ``T_fixed_body`` (m).
        theta: start heading of ``T_fixed_body`` (rad).
        dx: displacement along body x over the step (``vx * dt``, m).
        dy: displacement along body y over the step (``vy * dt``, m).
        dtheta: heading change over the step (``ω * dt``, rad).

    Returns:
        The end pose ``(x, y, theta + dtheta)``. Unlike :class:`Pose2D` the heading is *not*
        wrapped (so it can be accumulated) and inputs are not checked for NaN/inf: about ten
        times faster than building the two poses, which matters at simulator rates.
    """
    # a = sin θ / θ, b = (1 - cos θ) / θ, with their Taylor series near 0
    if abs(dtheta) < _SMALL:
        t2 = dtheta * dtheta
        a, b = 1.0 - t2 / 6.0, dtheta / 2.0 - dtheta * t2 / 24.0
    else:
        s_half = math.sin(0.5 * dtheta)
        # 1 - cos θ = 2 sin²(θ/2) avoids cancellation for small θ
        a, b = math.sin(dtheta) / dtheta, 2.0 * s_half * s_half / dtheta
    ex, ey = a * dx - b * dy, b * dx + a * dy  # end point in the start body frame
    c, s = math.cos(theta), math.sin(theta)
    return x + c * ex - s * ey, y + s * ex + c * ey, theta + dtheta


class Pose2D:
    """A planar rigid transform: translation ``(x, y)`` in metres and heading ``theta`` (rad).

    Immutable. ``theta`` is wrapped to [-π, π] on construction.
    """

    __slots__ = ("_c", "_s", "theta", "x", "y")

    x: float
    y: float
    theta: float
    _c: float
    _s: float

    def __init__(self, x: float = 0.0, y: float = 0.0, theta: float = 0.0) -> None:
        xf, yf, tf = float(x), float(y), float(theta)
        check_finite((xf, yf, tf), "Pose2D (x, y, theta)")
        tf = wrap_angle(tf)
        object.__setattr__(self, "x", xf)
        object.__setattr__(self, "y", yf)
        object.__setattr__(self, "theta", tf)
        object.__setattr__(self, "_c", math.cos(tf))
        object.__setattr__(self, "_s", math.sin(tf))

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError("Pose2D is immutable; build a new one")

    def __repr__(self) -> str:
        return f"Pose2D(x={self.x!r}, y={self.y!r}, theta={self.theta!r})"

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Pose2D):
            return NotImplemented
        return (self.x, self.y, self.theta) == (other.x, other.y, other.theta)

    def __hash__(self) -> int:
        return hash((self.x, self.y, self.theta))

    @classmethod
    def identity(cls) -> Pose2D:
        """The identity pose (0, 0, 0)."""
        return cls()

    # -- Lie group ----------------------------------------------------------------------------
    @classmethod
    def exp(cls, dx: float, dy: float, dtheta: float) -> Pose2D:
        """Exact exponential of a body-frame twist applied for unit time.

        Args:
            dx: forward displacement rate × time (``vx * dt``, metres, body x).
            dy: leftward displacement rate × time (``vy * dt``, metres, body y; 0 for a
                differential drive).
            dtheta: heading change (``ω * dt``, rad, counter-clockwise).

        Returns:
            The relative motion ``T_start_end`` along the constant-twist arc.
        """
        check_finite((float(dx), float(dy), float(dtheta)), "twist")
        ex, ey, _ = integrate_arc(0.0, 0.0, 0.0, dx, dy, dtheta)
        return cls(ex, ey, dtheta)

    def log(self) -> tuple[float, float, float]:
        """Inverse of :meth:`exp`: the twist whose unit-time arc reaches this pose.

        The twist is ``(dx, dy, dtheta)``, dtheta in [-π, π].
        """
        th = self.theta
        half = 0.5 * th
        # k = (θ/2) cot(θ/2), with its Taylor series near 0
        k = 1.0 - th * th / 12.0 if abs(th) < _SMALL else half * math.cos(half) / math.sin(half)
        return (k * self.x + half * self.y, -half * self.x + k * self.y, th)

    def __mul__(self, other: Pose2D) -> Pose2D:
        """Chain ``T_a_c = T_a_b * T_b_c``."""
        if not isinstance(other, Pose2D):
            return NotImplemented
        c, s = self._c, self._s
        return Pose2D(
            self.x + c * other.x - s * other.y,
            self.y + s * other.x + c * other.y,
            self.theta + other.theta,
        )

    def inv(self) -> Pose2D:
        """Inverse ``T_b_a``."""
        c, s = self._c, self._s
        return Pose2D(-c * self.x - s * self.y, s * self.x - c * self.y, -self.theta)

    def apply(self, points: npt.ArrayLike) -> F64:
        """Map point(s) ``(2,)`` or ``(N, 2)`` from frame ``b`` into frame ``a`` (metres)."""
        p = parse_rows(points, 2, "points")
        c, s = self._c, self._s
        if isinstance(p, tuple):
            return np.array((self.x + c * p[0] - s * p[1], self.y + s * p[0] + c * p[1]))
        out = np.empty_like(p)
        out[:, 0] = self.x + c * p[:, 0] - s * p[:, 1]
        out[:, 1] = self.y + s * p[:, 0] + c * p[:, 1]
        return out

    def interpolate(self, other: Pose2D, t: float) -> Pose2D:
        """Constant-twist (geodesic) interpolation: ``self * exp(t * log(self⁻¹ * other))``."""
        dx, dy, dth = (self.inv() * other).log()
        return self * Pose2D.exp(t * dx, t * dy, t * dth)

    # -- conversions --------------------------------------------------------------------------
    def as_matrix(self) -> F64:
        """3×3 homogeneous matrix ``[[c, -s, x], [s, c, y], [0, 0, 1]]``."""
        c, s = self._c, self._s
        return np.array(((c, -s, self.x), (s, c, self.y), (0.0, 0.0, 1.0)))

    @classmethod
    def from_matrix(cls, matrix: npt.ArrayLike, *, atol: float = 1e-6) -> Pose2D:
        """From a 3×3 homogeneous matrix; the 2×2 block must be a rotation within ``atol``."""
        m = np.asarray(matrix, dtype=np.float64)
        if m.shape != (3, 3):
            raise ShapeError(f"Pose2D matrix must have shape (3, 3), got {m.shape}")
        r = m[:2, :2]
        if not (
            np.allclose(r @ r.T, np.eye(2), rtol=0.0, atol=atol)
            and abs(np.linalg.det(r) - 1.0) <= atol
            and np.allclose(m[2], (0.0, 0.0, 1.0), rtol=0.0, atol=atol)
        ):
            raise NonOrthonormalMatrixError(f"not an SE(2) homogeneous matrix: {m.tolist()}")
        return cls(m[0, 2], m[1, 2], math.atan2(m[1, 0], m[0, 0]))

    def as_tuple(self) -> tuple[float, float, float]:
        """``(x, y, theta)``."""
        return (self.x, self.y, self.theta)

    def approx_equal(self, other: Pose2D, atol: float = 1e-9) -> bool:
        """Position within ``atol`` m and heading within ``atol`` rad (wrap-aware)."""
        return (
            abs(self.x - other.x) <= atol
            and abs(self.y - other.y) <= atol
            and abs(wrap_angle(self.theta - other.theta)) <= atol
        )
