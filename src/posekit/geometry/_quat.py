"""Scalar quaternion kernels on plain Python floats (the single-item fast path).

Private but importable: :mod:`posekit.tf2` reuses these so that one transform lookup does
not pay numpy's per-call overhead. Every function states its quaternion order in its name:
``_xyzw`` means scalar-last (ROS messages, scipy default). Quaternions are Hamilton
quaternions, rotations are active, and all inputs are assumed *unit* unless a function says
otherwise (only :func:`quat_normalize_xyzw` validates). Angles are radians.

Types: ``Quat = (x, y, z, w)``, ``Vec3 = (x, y, z)``, ``Mat3`` = three row tuples.
"""

from __future__ import annotations

import math

from posekit.geometry.errors import InvalidQuaternionError, UnknownSequenceError

__all__ = [
    "EULER_SEQUENCES",
    "GIMBAL_EPS",
    "Mat3",
    "Quat",
    "Vec3",
    "euler_params",
    "matrix_to_quat_xyzw",
    "quat_conjugate_xyzw",
    "quat_from_axis_angle_xyzw",
    "quat_from_euler_xyzw",
    "quat_from_rotvec_xyzw",
    "quat_from_rpy_xyzw",
    "quat_multiply_xyzw",
    "quat_normalize_xyzw",
    "quat_rotate_vector_xyzw",
    "quat_slerp_xyzw",
    "quat_to_euler_xyzw",
    "quat_to_matrix_xyzw",
    "quat_to_rotvec_xyzw",
    "quat_to_rpy_xyzw",
    "wrap_angle",
]

Quat = tuple[float, float, float, float]
Vec3 = tuple[float, float, float]
Mat3 = tuple[Vec3, Vec3, Vec3]

_PI = math.pi
_TWO_PI = 2.0 * math.pi
_HALF_PI = 0.5 * math.pi

#: Middle-angle distance (rad) from a singularity below which ``as_euler`` reports gimbal lock
#: (same threshold as scipy).
GIMBAL_EPS = 1e-7

# (i, j, k, extrinsic, proper, parity) for each sequence; i, j, k are the axes of the
# *extrinsic-equivalent* sequence (intrinsic "IJK" == extrinsic "kji" with angles reversed),
# proper means i == k (then k here is the remaining third axis), parity = +1 for a cyclic
# (x->y->z) order of (i, j, k) and -1 otherwise.
_EulerParams = tuple[int, int, int, bool, bool, float]


def _build_sequences() -> dict[str, _EulerParams]:
    table: dict[str, _EulerParams] = {}
    axes = "xyz"
    for a in range(3):
        for b in range(3):
            for c in range(3):
                if a == b or b == c:
                    continue
                low = axes[a] + axes[b] + axes[c]
                for seq in (low, low.upper()):
                    extrinsic = seq.islower()
                    i, j, k = (a, b, c) if extrinsic else (c, b, a)
                    proper = i == k
                    if proper:
                        k = 3 - i - j
                    parity = 1.0 if (j - i) % 3 == 1 else -1.0
                    table[seq] = (i, j, k, extrinsic, proper, parity)
    return table


_SEQ = _build_sequences()
#: The 24 valid Euler sequences: lowercase extrinsic (fixed axes), uppercase intrinsic.
EULER_SEQUENCES: tuple[str, ...] = tuple(sorted(_SEQ))


def euler_params(seq: str) -> _EulerParams:
    """Look up a sequence; raise :class:`UnknownSequenceError` with the valid choices."""
    try:
        return _SEQ[seq]
    except (KeyError, TypeError):
        raise UnknownSequenceError(
            f"unknown Euler sequence {seq!r}: expected 3 axis letters from 'xyz' with no axis "
            "repeated consecutively, all lowercase (extrinsic) or all uppercase (intrinsic), "
            "e.g. 'xyz', 'ZYX', 'zxz'"
        ) from None


def wrap_angle(a: float) -> float:
    """Wrap an angle (rad) into [-π, π]: values inside are untouched, others land in (-π, π].

    posekit's one convention for angle wrapping (Euler angles, SE(2), the robot's odometry,
    EKF and controller). Leaving in-range values untouched keeps them bit-exact (a modulo
    would round ``0.1`` to ``0.10000000000000009``) and costs one comparison; it is the
    behaviour of robot_localization's ``clampRotation`` for angles within one turn.
    """
    if -_PI <= a <= _PI:
        return a
    return a - _TWO_PI * math.ceil((a - _PI) / _TWO_PI)


def quat_normalize_xyzw(x: float, y: float, z: float, w: float) -> Quat:
    """Normalise a finite, non-zero quaternion; raise :class:`InvalidQuaternionError` otherwise."""
    n = math.hypot(x, y, z, w)
    if not 0.0 < n < math.inf:
        raise InvalidQuaternionError(
            f"quaternion (x, y, z, w) = ({x!r}, {y!r}, {z!r}, {w!r}) encodes no rotation: "
            + ("its norm is zero" if n == 0.0 else "it contains NaN or infinity")
        )
    if n == 1.0:
        return (x, y, z, w)
    return (x / n, y / n, z / n, w / n)


def quat_multiply_xyzw(a: Quat, b: Quat) -> Quat:
    """Hamilton product ``a ⊗ b``: the rotation that applies ``b`` first, then ``a``."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def quat_conjugate_xyzw(q: Quat) -> Quat:
    """Conjugate ``(-x, -y, -z, w)``, the inverse of a unit quaternion."""
    return (-q[0], -q[1], -q[2], q[3])


def quat_rotate_vector_xyzw(q: Quat, v: Vec3) -> Vec3:
    """Rotate ``v`` by unit ``q`` (the lecture's ``p' = q p q⁻¹``), as ``v + 2u×(u×v + w v)``."""
    x, y, z, w = q
    vx, vy, vz = v
    # t = 2 (u × v)
    tx = 2.0 * (y * vz - z * vy)
    ty = 2.0 * (z * vx - x * vz)
    tz = 2.0 * (x * vy - y * vx)
    return (
        vx + w * tx + (y * tz - z * ty),
        vy + w * ty + (z * tx - x * tz),
        vz + w * tz + (x * ty - y * tx),
    )


def quat_to_matrix_xyzw(q: Quat) -> Mat3:
    """Rotation matrix (rows) of a unit quaternion."""
    x, y, z, w = q
    xx, yy, zz = x * x, y * y, z * z
    xy, xz, yz = x * y, x * z, y * z
    wx, wy, wz = w * x, w * y, w * z
    return (
        (1.0 - 2.0 * (yy + zz), 2.0 * (xy - wz), 2.0 * (xz + wy)),
        (2.0 * (xy + wz), 1.0 - 2.0 * (xx + zz), 2.0 * (yz - wx)),
        (2.0 * (xz - wy), 2.0 * (yz + wx), 1.0 - 2.0 * (xx + yy)),
    )


def matrix_to_quat_xyzw(m: Mat3) -> Quat:
    """Unit quaternion of a rotation matrix (tf2 ``Matrix3x3::getRotation`` branch rule).

    Picks the numerically largest of ``w, x, y, z`` to divide by, then normalises. Output sign:
    ``w > 0`` when the trace is positive, else the largest-diagonal component is positive.
    The matrix is assumed orthonormal (the caller validates).
    """
    (m00, m01, m02), (m10, m11, m12), (m20, m21, m22) = m
    trace = m00 + m11 + m22
    if trace > 0.0:
        s = math.sqrt(trace + 1.0)
        w = 0.5 * s
        s = 0.5 / s
        x, y, z = (m21 - m12) * s, (m02 - m20) * s, (m10 - m01) * s
    elif m00 >= m11 and m00 >= m22:
        s = math.sqrt(m00 - m11 - m22 + 1.0)
        x = 0.5 * s
        s = 0.5 / s
        w, y, z = (m21 - m12) * s, (m10 + m01) * s, (m20 + m02) * s
    elif m11 >= m22:
        s = math.sqrt(m11 - m22 - m00 + 1.0)
        y = 0.5 * s
        s = 0.5 / s
        w, z, x = (m02 - m20) * s, (m21 + m12) * s, (m01 + m10) * s
    else:
        s = math.sqrt(m22 - m00 - m11 + 1.0)
        z = 0.5 * s
        s = 0.5 / s
        w, x, y = (m10 - m01) * s, (m02 + m20) * s, (m12 + m21) * s
    n = math.hypot(x, y, z, w)
    return (x / n, y / n, z / n, w / n)


def quat_from_axis_angle_xyzw(axis: Vec3, angle: float) -> Quat:
    """Quaternion ``(u sin(θ/2), cos(θ/2))`` for a *unit* axis ``u`` and angle ``θ`` (rad)."""
    h = 0.5 * angle
    s = math.sin(h)
    return (axis[0] * s, axis[1] * s, axis[2] * s, math.cos(h))


def quat_from_rotvec_xyzw(rx: float, ry: float, rz: float) -> Quat:
    """Quaternion of a rotation vector (axis × angle in rad, OpenCV's ``rvec``)."""
    angle = math.sqrt(rx * rx + ry * ry + rz * rz)
    if angle < 1e-6:
        # Taylor series of sin(θ/2)/θ keeps full precision for tiny angles.
        a2 = angle * angle
        scale = 0.5 - a2 / 48.0 + a2 * a2 / 3840.0
    else:
        scale = math.sin(0.5 * angle) / angle
    return (rx * scale, ry * scale, rz * scale, math.cos(0.5 * angle))


def quat_to_rotvec_xyzw(q: Quat) -> Vec3:
    """Rotation vector (axis × angle, angle in [0, π]) of a unit quaternion."""
    x, y, z, w = q
    if w < 0.0:  # pick the representative with angle <= π
        x, y, z, w = -x, -y, -z, -w
    s = math.sqrt(x * x + y * y + z * z)
    angle = 2.0 * math.atan2(s, w)
    if angle < 1e-3:
        a2 = angle * angle
        # angle / sin(angle/2), series for small angles
        scale = 2.0 + a2 / 12.0 + 7.0 * a2 * a2 / 2880.0
    else:
        scale = angle / s
    return (x * scale, y * scale, z * scale)


def quat_slerp_xyzw(q1: Quat, q2: Quat, t: float) -> Quat:
    """Spherical interpolation along the shortest arc (tf2 ``slerp`` formula), ``t`` in [0, 1].

    ``t = 0`` gives ``q1`` exactly; the result is not renormalised (for unit inputs it is
    unit to rounding). When ``q1·q2 < 0`` the path goes to ``-q2`` (same rotation, shorter arc).
    """
    dot = q1[0] * q2[0] + q1[1] * q2[1] + q1[2] * q2[2] + q1[3] * q2[3]
    n = math.sqrt(
        (q1[0] * q1[0] + q1[1] * q1[1] + q1[2] * q1[2] + q1[3] * q1[3])
        * (q2[0] * q2[0] + q2[1] * q2[1] + q2[2] * q2[2] + q2[3] * q2[3])
    )
    c = abs(dot) / n
    theta = math.acos(c if c < 1.0 else 1.0)
    if theta == 0.0:
        return q1
    d = 1.0 / math.sin(theta)
    s0 = math.sin((1.0 - t) * theta) * d
    s1 = math.sin(t * theta) * d
    if dot < 0.0:
        s1 = -s1
    return (
        q1[0] * s0 + q2[0] * s1,
        q1[1] * s0 + q2[1] * s1,
        q1[2] * s0 + q2[2] * s1,
        q1[3] * s0 + q2[3] * s1,
    )


def quat_from_euler_xyzw(seq: str, a: float, b: float, c: float) -> Quat:
    """Quaternion of Euler angles ``(a, b, c)`` (rad) in the order the sequence names them.

    Extrinsic ``'ijk'``: ``R = R_k(c) R_j(b) R_i(a)``; intrinsic ``'IJK'``: ``R = R_I(a) R_J(b)
    R_K(c)`` (same conventions as scipy). Closed form of the product of the three elementary
    quaternions; the result has ``w >= 0``.
    """
    try:
        i, j, k, extrinsic, proper, e = _SEQ[seq]
    except (KeyError, TypeError):
        i, j, k, extrinsic, proper, e = euler_params(seq)  # raises the named error
    if not extrinsic:
        a, c = c, a
    # now extrinsic: first a about i, then b about j, then c about k (or i again if proper)
    hb = 0.5 * b
    cb, sb = math.cos(hb), math.sin(hb)
    v = [0.0, 0.0, 0.0, 0.0]
    if proper:
        hs, hd = 0.5 * (a + c), 0.5 * (c - a)
        w = cb * math.cos(hs)
        v[i] = cb * math.sin(hs)
        v[j] = sb * math.cos(hd)
        v[k] = e * sb * math.sin(hd)
    else:
        ha, hc = 0.5 * a, 0.5 * c
        ca, sa = math.cos(ha), math.sin(ha)
        cc, sc = math.cos(hc), math.sin(hc)
        w = ca * cb * cc + e * sa * sb * sc
        v[i] = sa * cb * cc - e * ca * sb * sc
        v[j] = ca * sb * cc + e * sa * cb * sc
        v[k] = ca * cb * sc - e * sa * sb * cc
    if w < 0.0:
        return (-v[0], -v[1], -v[2], -w)
    v[3] = w
    return tuple(v)  # type: ignore[return-value]


def quat_to_euler_xyzw(seq: str, q: Quat) -> tuple[float, float, float, bool]:
    """Euler angles (rad) of a unit quaternion, plus a gimbal-lock flag.

    Direct quaternion method of Bernardes & Viollet (PLoS ONE 2022): the middle angle comes
    from ``atan2`` of two norms (well conditioned everywhere, unlike ``asin`` of a matrix
    entry). Ranges: first and third angles in [-π, π]; middle angle in [-π/2, π/2] for
    Tait-Bryan sequences and [0, π] for proper Euler sequences. At gimbal lock (middle angle
    within :data:`GIMBAL_EPS` of a singularity) the third angle of ``seq`` is set to 0 and the
    flag is True.
    """
    try:
        i, j, k, extrinsic, proper, parity = _SEQ[seq]
    except (KeyError, TypeError):
        i, j, k, extrinsic, proper, parity = euler_params(seq)  # raises the named error
    w = q[3]
    qi, qj, qk = q[i], q[j], q[k] * parity
    if proper:
        a, b, c, d = w, qi, qj, qk
    else:
        # Rotating the frame by π/2 about j turns Tait-Bryan i-j-k into proper i-j-i.
        a, b, c, d = w - qj, qi + qk, qj + w, qk - qi
    middle = 2.0 * math.atan2(math.hypot(c, d), math.hypot(a, b))
    half_sum = math.atan2(b, a)
    half_diff = math.atan2(d, c)
    locked = False
    if abs(middle) <= GIMBAL_EPS:
        locked = True
        if extrinsic:
            first, third = 2.0 * half_sum, 0.0
        else:
            first, third = 0.0, 2.0 * half_sum
    elif abs(middle - _PI) <= GIMBAL_EPS:
        locked = True
        if extrinsic:
            first, third = -2.0 * half_diff, 0.0
        else:
            first, third = 0.0, 2.0 * half_diff
    else:
        first, third = half_sum - half_diff, half_sum + half_diff
    if not proper:
        third *= parity
        middle -= _HALF_PI
    if not -_PI <= first <= _PI:
        first = wrap_angle(first)
    if not -_PI <= third <= _PI:
        third = wrap_angle(third)
    if extrinsic:
        return first, middle, third, locked
    return third, middle, first, locked


def quat_from_rpy_xyzw(roll: float, pitch: float, yaw: float) -> Quat:
    """ROS fixed-axis roll/pitch/yaw (tf2 ``setRPY``): ``R = Rz(yaw) Ry(pitch) Rx(roll)``."""
    hr, hp, hy = 0.5 * roll, 0.5 * pitch, 0.5 * yaw
    cr, sr = math.cos(hr), math.sin(hr)
    cp, sp = math.cos(hp), math.sin(hp)
    cy, sy = math.cos(hy), math.sin(hy)
    return (
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    )


def quat_to_rpy_xyzw(q: Quat) -> tuple[float, float, float]:
    """ROS (roll, pitch, yaw) of a unit quaternion, inverse of :func:`quat_from_rpy_xyzw`.

    Same angles as tf2 ``Matrix3x3::getRPY`` away from gimbal lock; at pitch = ±π/2 yaw is
    set to 0 (tf2 does the same) and roll carries the remaining rotation.
    """
    roll, pitch, yaw, _ = quat_to_euler_xyzw("xyz", q)
    return roll, pitch, yaw
