"""Small message helpers shared by the robot models (quaternions, covariances)."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from posekit.msgs.geometry_msgs import Quaternion
from posekit.robot.kinematics import quaternion_xyzw_from_yaw

__all__ = [
    "covariance_from_diagonal",
    "yaw_quaternion",
]

def yaw_quaternion(yaw: float) -> Quaternion:
    """geometry_msgs/Quaternion of a rotation by ``yaw`` rad about +z."""
    qx, qy, qz, qw = quaternion_xyzw_from_yaw(yaw)
    return Quaternion(qx, qy, qz, qw)


def covariance_from_diagonal(diagonal: tuple[float, ...] | list[float]) -> npt.NDArray[np.float64]:
    """A row-major n x n covariance (flattened) with the given diagonal."""
    n = len(diagonal)
    cov = np.zeros(n * n, dtype=np.float64)
    cov[:: n + 1] = diagonal
    return cov
