"""Function API on plain float tuples: the fastest validated path for one rotation.

For code that handles one pose at a time (ROS callbacks, tf2 lookups) and wants neither a
:class:`~posekit.geometry.Rotation` object nor numpy arrays. Same conventions as the rest of
posekit: Hamilton quaternions, ``(x, y, z, w)`` unless ``scalar_first=True``, active rotations,
lowercase extrinsic / uppercase intrinsic Euler sequences, radians unless ``degrees=True``.
Input quaternions follow the normalisation policy (normalised; NaN/inf/zero raise
:class:`~posekit.geometry.errors.InvalidQuaternionError`); outputs are unit quaternions.

``quat_from_rpy``/``rpy_from_quat`` are the equivalents of tf_transformations'
``quaternion_from_euler(r, p, y)``/``euler_from_quaternion(q)`` (fixed axes x, y, z).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence

from posekit.geometry import _quat as sk
from posekit.geometry._parse import check_finite
from posekit.geometry.errors import GimbalLockWarning, ShapeError

__all__ = [
    "euler_from_quat",
    "quat_from_euler",
    "quat_from_rpy",
    "quat_multiply",
    "quat_to_matrix",
    "rotate_vector",
    "rpy_from_quat",
]

Quat4 = tuple[float, float, float, float]


def _quat_in(q: Sequence[float], scalar_first: bool) -> sk.Quat:
    try:
        a, b, c, d = q
    except (TypeError, ValueError):
        raise ShapeError(f"a quaternion needs exactly 4 numbers, got {q!r}") from None
    if scalar_first:
        return sk.quat_normalize_xyzw(float(b), float(c), float(d), float(a))
    return sk.quat_normalize_xyzw(float(a), float(b), float(c), float(d))


def _quat_out(q: sk.Quat, scalar_first: bool) -> Quat4:
    if scalar_first:
        return (q[3], q[0], q[1], q[2])
    return q


def quat_from_euler(
    seq: str,
    a: float,
    b: float,
    c: float,
    *,
    degrees: bool = False,
    scalar_first: bool = False,
) -> Quat4:
    """Unit quaternion (``w >= 0``) of Euler angles listed in the order of ``seq``."""
    a, b, c = float(a), float(b), float(c)
    if not math.isfinite(a + b + c):
        check_finite((a, b, c), "Euler angles")
    if degrees:
        a, b, c = math.radians(a), math.radians(b), math.radians(c)
    return _quat_out(sk.quat_from_euler_xyzw(seq, a, b, c), scalar_first)


def euler_from_quat(
    seq: str,
    q: Sequence[float],
    *,
    scalar_first: bool = False,
    degrees: bool = False,
    warn: bool = True,
) -> tuple[float, float, float]:
    """Euler angles of a quaternion; at gimbal lock the third angle is 0 (with a warning)."""
    a, b, c, locked = sk.quat_to_euler_xyzw(seq, _quat_in(q, scalar_first))
    if locked and warn:
        warnings.warn(
            f"gimbal lock detected for sequence {seq!r}; the third angle was set to 0",
            GimbalLockWarning,
            stacklevel=2,
        )
    if degrees:
        return math.degrees(a), math.degrees(b), math.degrees(c)
    return a, b, c


def quat_from_rpy(roll: float, pitch: float, yaw: float) -> Quat4:
    """``(x, y, z, w)`` of ROS roll/pitch/yaw about fixed x, y, z (tf2 ``setRPY``).

    Examples:
        A yaw of π/2 is (0, 0, sin π/4, cos π/4):

        >>> import math
        >>> [round(c, 6) for c in quat_from_rpy(0.0, 0.0, math.pi / 2)]
        [0.0, 0.0, 0.707107, 0.707107]
    """
    r, p, y = float(roll), float(pitch), float(yaw)
    if not math.isfinite(r + p + y):
        check_finite((r, p, y), "roll/pitch/yaw")
    return sk.quat_from_rpy_xyzw(r, p, y)


def rpy_from_quat(q: Sequence[float], *, scalar_first: bool = False) -> tuple[float, float, float]:
    """ROS ``(roll, pitch, yaw)``; at pitch = ±π/2 yaw is 0, like tf2 ``getRPY``.

    Examples:
        >>> import math
        >>> half = math.sqrt(0.5)
        >>> [round(a, 6) for a in rpy_from_quat((0.0, 0.0, half, half))]   # yaw π/2
        [0.0, 0.0, 1.570796]
        >>> [round(a, 6) for a in rpy_from_quat((half, 0.0, 0.0, half))]   # roll π/2
        [1.570796, 0.0, 0.0]
    """
    return sk.quat_to_rpy_xyzw(_quat_in(q, scalar_first))


def quat_multiply(
    q1: Sequence[float], q2: Sequence[float], *, scalar_first: bool = False
) -> Quat4:
    """``q1 ⊗ q2``: the rotation that applies ``q2`` first, then ``q1``.

    Examples:
        A yaw of π/2 after a roll of π/2: ``w = w1 w2 - v1·v2`` and ``v = w1 v2 + w2 v1 +
        v1 × v2`` give (0.5, 0.5, 0.5, 0.5):

        >>> import math
        >>> half = math.sqrt(0.5)
        >>> yaw, roll = (0.0, 0.0, half, half), (half, 0.0, 0.0, half)
        >>> [round(c, 6) for c in quat_multiply(yaw, roll)]
        [0.5, 0.5, 0.5, 0.5]
    """
    prod = sk.quat_multiply_xyzw(_quat_in(q1, scalar_first), _quat_in(q2, scalar_first))
    return _quat_out(prod, scalar_first)


def rotate_vector(
    q: Sequence[float], v: Sequence[float], *, scalar_first: bool = False
) -> tuple[float, float, float]:
    """``q v q⁻¹``: the vector ``v`` rotated by ``q``.

    Examples:
        A yaw of π/2 maps ``(x, y, z)`` to ``(-y, x, z)``:

        >>> import math
        >>> half = math.sqrt(0.5)
        >>> [round(c, 6) for c in rotate_vector((0.0, 0.0, half, half), (1.0, 2.0, 3.0))]
        [-2.0, 1.0, 3.0]
    """
    try:
        x, y, z = v
    except (TypeError, ValueError):
        raise ShapeError(f"a vector needs exactly 3 numbers, got {v!r}") from None
    return sk.quat_rotate_vector_xyzw(_quat_in(q, scalar_first), (float(x), float(y), float(z)))


def quat_to_matrix(q: Sequence[float], *, scalar_first: bool = False) -> sk.Mat3:
    """Rotation matrix rows of a quaternion."""
    return sk.quat_to_matrix_xyzw(_quat_in(q, scalar_first))
