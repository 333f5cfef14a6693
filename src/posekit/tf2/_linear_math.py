"""tf2 LinearMath kernels on plain float tuples (quaternions are (x, y, z, w), Hamilton).

These reproduce the arithmetic of ``tf2/LinearMath`` operation by operation (same formulas,
same evaluation order), because tf2's observable outputs depend on them: the stored and
returned quaternions pass through ``Matrix3x3::setRotation`` / ``getRotation`` (normalised,
sign-canonicalised), interpolation uses tf2's ``slerp`` and a component-wise lerp.
Pure Python floats on purpose: a single lookup touches a handful of numbers, where numpy's
per-call overhead would dominate.
"""

from __future__ import annotations

import math

__all__ = [
    "Quat",
    "Vec3",
    "canonical_quat",
    "matrix_from_quat",
    "matrix_get_rpy",
    "quat_from_matrix",
    "quat_from_rpy",
    "quat_inverse",
    "quat_mul",
    "quat_rotate",
    "rpy_from_quat",
    "slerp",
]

Quat = tuple[float, float, float, float]
Vec3 = tuple[float, float, float]
Mat3 = tuple[float, float, float, float, float, float, float, float, float]

_acos = math.acos
_sin = math.sin
_sqrt = math.sqrt


def quat_mul(a: Quat, b: Quat) -> Quat:
    """Hamilton product ``a * b`` (tf2 ``Quaternion::operator*=``)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by + ay * bw + az * bx - ax * bz,
        aw * bz + az * bw + ax * by - ay * bx,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def quat_inverse(q: Quat) -> Quat:
    """tf2's ``Quaternion::inverse``: the conjugate (not divided by |q|^2)."""
    return (-q[0], -q[1], -q[2], q[3])


def quat_rotate(q: Quat, v: Vec3) -> Vec3:
    """tf2 ``quatRotate``: ``q * (v, 0) * conj(q)``; scales v by |q|^2 for non-unit q."""
    qx, qy, qz, qw = q
    vx, vy, vz = v
    # (q * v): tf2's Quaternion * Vector3
    px = qw * vx + qy * vz - qz * vy
    py = qw * vy + qz * vx - qx * vz
    pz = qw * vz + qx * vy - qy * vx
    pw = -qx * vx - qy * vy - qz * vz
    # (p * conj(q)), vector part only
    cx, cy, cz = -qx, -qy, -qz
    return (
        pw * cx + px * qw + py * cz - pz * cy,
        pw * cy + py * qw + pz * cx - px * cz,
        pw * cz + pz * qw + px * cy - py * cx,
    )


def matrix_from_quat(q: Quat) -> Mat3:
    """Row-major 3x3 rotation matrix (tf2 ``Matrix3x3::setRotation``; s = 2/|q|^2 normalises).

    A zero quaternion yields NaN entries (0 * inf), which is how tf2 ends up rejecting it.
    """
    x, y, z, w = q
    d = x * x + y * y + z * z + w * w
    s = 2.0 / d if d != 0.0 else math.inf  # C: 2/0 = inf, so a zero quaternion gives NaN
    xs, ys, zs = x * s, y * s, z * s
    wx, wy, wz = w * xs, w * ys, w * zs
    xx, xy, xz = x * xs, x * ys, x * zs
    yy, yz, zz = y * ys, y * zs, z * zs
    return (
        1.0 - (yy + zz), xy - wz, xz + wy,
        xy + wz, 1.0 - (xx + zz), yz - wx,
        xz - wy, yz + wx, 1.0 - (xx + yy),
    )  # fmt: skip


def quat_from_matrix(m: Mat3) -> Quat:
    """tf2 ``Matrix3x3::getRotation``: w > 0 if the trace is positive, else the largest-diagonal
    component is positive."""
    m00, m01, m02, m10, m11, m12, m20, m21, m22 = m
    trace = m00 + m11 + m22
    if trace > 0.0:
        s = _sqrt(trace + 1.0)
        w = s * 0.5
        s = 0.5 / s
        return ((m21 - m12) * s, (m02 - m20) * s, (m10 - m01) * s, w)
    rows = ((m00, m01, m02), (m10, m11, m12), (m20, m21, m22))
    i = (2 if m11 < m22 else 1) if m00 < m11 else (2 if m00 < m22 else 0)
    j = (i + 1) % 3
    k = (i + 2) % 3
    out = [0.0, 0.0, 0.0, 0.0]
    arg = rows[i][i] - rows[j][j] - rows[k][k] + 1.0
    s = _sqrt(arg) if arg >= 0.0 else math.nan  # NaN/inf input: propagate NaN like C
    out[i] = s * 0.5
    s = 0.5 / s if s != 0.0 else math.inf
    out[3] = (rows[k][j] - rows[j][k]) * s
    out[j] = (rows[j][i] + rows[i][j]) * s
    out[k] = (rows[k][i] + rows[i][k]) * s
    return (out[0], out[1], out[2], out[3])


def canonical_quat(q: Quat) -> Quat:
    """What tf2 stores/returns for q: ``getRotation(setRotation(q))`` (unit, canonical sign)."""
    return quat_from_matrix(matrix_from_quat(q))


def slerp(q1: Quat, q2: Quat, t: float) -> Quat:
    """tf2 ``slerp(q1, q2, t)``: shortest path, not renormalised; returns q1 when the angle is 0."""
    x1, y1, z1, w1 = q1
    x2, y2, z2, w2 = q2
    dot = x1 * x2 + y1 * y2 + z1 * z2 + w1 * w2
    s = _sqrt((x1 * x1 + y1 * y1 + z1 * z1 + w1 * w1) * (x2 * x2 + y2 * y2 + z2 * z2 + w2 * w2))
    c = (-dot if dot < 0.0 else dot) / s
    theta = _acos(-1.0 if c < -1.0 else (1.0 if c > 1.0 else c))
    if theta == 0.0:
        return q1
    d = 1.0 / _sin(theta)
    s0 = _sin((1.0 - t) * theta)
    s1 = _sin(t * theta)
    if dot < 0.0:
        s1 = -s1
    return ((x1 * s0 + x2 * s1) * d, (y1 * s0 + y2 * s1) * d, (z1 * s0 + z2 * s1) * d,
            (w1 * s0 + w2 * s1) * d)  # fmt: skip


def quat_from_rpy(roll: float, pitch: float, yaw: float) -> Quat:
    """tf2 ``Quaternion::setRPY`` (radians): R = Rz(yaw) Ry(pitch) Rx(roll), fixed axes.

    A yaw of pi/2 is the half-angle quaternion (0, 0, sin(pi/4), cos(pi/4)):

        >>> import math
        >>> [round(c, 6) for c in quat_from_rpy(0.0, 0.0, math.pi / 2)]
        [0.0, 0.0, 0.707107, 0.707107]
    """
    hr, hp, hy = roll * 0.5, pitch * 0.5, yaw * 0.5
    cr, sr = math.cos(hr), math.sin(hr)
    cp, sp = math.cos(hp), math.sin(hp)
    cy, sy = math.cos(hy), math.sin(hy)
    return (
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    )


def matrix_get_rpy(m: Mat3) -> tuple[float, float, float]:
    """tf2 ``Matrix3x3::getRPY`` (= getEulerYPR solution 1): (roll, pitch, yaw) in radians."""
    m00, _m01, _m02, m10, _m11, _m12, m20, m21, m22 = m
    if abs(m20) >= 1.0:
        delta = math.atan2(m21, m22)
        if m20 < 0.0:
            return (delta, math.pi / 2.0, 0.0)
        return (delta, -math.pi / 2.0, 0.0)
    pitch = -math.asin(m20)
    cp = math.cos(pitch)
    return (math.atan2(m21 / cp, m22 / cp), pitch, math.atan2(m10 / cp, m00 / cp))


def rpy_from_quat(q: Quat) -> tuple[float, float, float]:
    """tf2 ``Matrix3x3(q).getRPY()``: (roll, pitch, yaw) in radians of a quaternion (x, y, z, w),
    through tf2's matrix (any norm is normalised by ``setRotation``).

    (0, 0, 1, 1) has norm sqrt(2); setRotation normalises it to (0, 0, sin(pi/4), cos(pi/4)),
    a yaw of pi/2 (the pitch prints as -0.0 because tf2 computes it as -asin(0)):

        >>> [round(a, 6) for a in rpy_from_quat((0.0, 0.0, 1.0, 1.0))]
        [0.0, -0.0, 1.570796]
    """
    return matrix_get_rpy(matrix_from_quat(q))
