"""Small numpy-only rotation helpers used by the vision models.

Kept local so :mod:`posekit.vision` does not depend on the geometry package's API while it is
being written; all matrices are active rotations, quaternions are (x, y, z, w) unless a
keyword says otherwise.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

__all__ = [
    "make_transform",
    "matrix_to_quat_xyzw",
    "quat_xyzw_to_matrix",
    "rotation_angle_between",
    "rotvec_to_matrix",
    "rpy_to_matrix",
    "rx",
    "ry",
    "rz",
]

F64Array = npt.NDArray[np.float64]


def rx(angle: float) -> F64Array:
    """Rotation matrix about x by ``angle`` radians."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def ry(angle: float) -> F64Array:
    """Rotation matrix about y by ``angle`` radians."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rz(angle: float) -> F64Array:
    """Rotation matrix about z by ``angle`` radians."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rpy_to_matrix(roll: float, pitch: float, yaw: float) -> F64Array:
    """SDF/URDF ``rpy``: fixed-axis x then y then z, i.e. ``R = Rz(yaw) @ Ry(pitch) @ Rx(roll)``."""
    return rz(yaw) @ ry(pitch) @ rx(roll)


def make_transform(rotation: npt.ArrayLike, translation: npt.ArrayLike) -> F64Array:
    """4x4 homogeneous transform from a 3x3 rotation and a 3-vector translation."""
    T = np.eye(4)
    T[:3, :3] = np.asarray(rotation, dtype=np.float64)
    T[:3, 3] = np.asarray(translation, dtype=np.float64).reshape(3)
    return T


def rotvec_to_matrix(rotvec: npt.ArrayLike) -> F64Array:
    """Rotation matrix of an axis-angle vector (Rodrigues' formula, angle = norm in radians)."""
    v = np.asarray(rotvec, dtype=np.float64).reshape(3)
    angle = float(np.linalg.norm(v))
    if angle < 1e-12:
        return np.eye(3)
    k = v / angle
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    out: F64Array = np.eye(3) + math.sin(angle) * K + (1.0 - math.cos(angle)) * (K @ K)
    return out


def matrix_to_quat_xyzw(R: npt.ArrayLike) -> F64Array:
    """Unit quaternion (x, y, z, w) of a rotation matrix, with w >= 0 (Shepperd's method)."""
    m = np.asarray(R, dtype=np.float64)
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    # Pick the largest of (w, x, y, z) to divide by, for stability near 180 degrees.
    diag = (trace, m[0, 0], m[1, 1], m[2, 2])
    i = int(np.argmax(diag))
    if i == 0:
        s = 2.0 * math.sqrt(max(1.0 + trace, 0.0))
        q = np.array(
            [(m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, 0.25 * s]
        )
    elif i == 1:
        s = 2.0 * math.sqrt(max(1.0 + m[0, 0] - m[1, 1] - m[2, 2], 0.0))
        q = np.array(
            [0.25 * s, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s, (m[2, 1] - m[1, 2]) / s]
        )
    elif i == 2:
        s = 2.0 * math.sqrt(max(1.0 - m[0, 0] + m[1, 1] - m[2, 2], 0.0))
        q = np.array(
            [(m[0, 1] + m[1, 0]) / s, 0.25 * s, (m[1, 2] + m[2, 1]) / s, (m[0, 2] - m[2, 0]) / s]
        )
    else:
        s = 2.0 * math.sqrt(max(1.0 - m[0, 0] - m[1, 1] + m[2, 2], 0.0))
        q = np.array(
            [(m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, 0.25 * s, (m[1, 0] - m[0, 1]) / s]
        )
    q /= np.linalg.norm(q)
    if q[3] < 0.0:
        q = -q
    return q


def quat_xyzw_to_matrix(q: npt.ArrayLike) -> F64Array:
    """Rotation matrix of a quaternion given as (x, y, z, w); the quaternion is normalised."""
    x, y, z, w = np.asarray(q, dtype=np.float64).reshape(4) / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def rotation_angle_between(R_a: npt.ArrayLike, R_b: npt.ArrayLike) -> float:
    """Angle in radians of the relative rotation ``R_a^T @ R_b`` (geodesic distance on SO(3))."""
    R = np.asarray(R_a, dtype=np.float64).T @ np.asarray(R_b, dtype=np.float64)
    c = (np.trace(R) - 1.0) / 2.0
    return math.acos(min(1.0, max(-1.0, c)))
