"""A planar EKF in the role of robot_localization's ekf_node (course configuration).

State (odom frame pose, base_link twist)::

    s = [x, y, yaw, vx, vy, vyaw]       (m, m, rad, m/s, m/s, rad/s)

Process model (constant body velocity over ``dt``, as robot_localization's omnidirectional
model restricted to 2D)::

    x'    = x + (vx cos(yaw) - vy sin(yaw)) dt
    y'    = y + (vx sin(yaw) + vy cos(yaw)) dt
    yaw'  = yaw + vyaw dt
    v*'   = v*                              (velocities are a random walk)

    P' = F P F^T + Q dt,   F = d s' / d s,   Q = diag(process_noise_diagonal)

Measurement models are linear selections of the state (``z = H s + noise``):

* wheel odometry (``odometry/wheels`` twist, base_link): ``vx, vy, vyaw`` with the
  message's twist covariance diagonal;
* IMU (``imu/data``): ``yaw`` (relative: the first IMU yaw is taken as zero, as
  ``imu0_relative: true``) and ``vyaw``, with the message's covariances.

Components are fused one at a time (the measurement covariances are diagonal, so sequential
scalar updates equal the batch update); the yaw innovation is wrapped to [-pi, pi).
Measurements are queued and, at each :meth:`Ekf2D.step` (20 Hz), processed in stamp order,
each preceded by a prediction to its stamp; the filter then predicts to the step time and
reports. A measurement older than the filter time is fused without prediction (no history
smoothing, robot_localization's default). Zero variances are floored at 1e-9.
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.nav_msgs import Odometry
from posekit.robot._msgutil import stamp_from_seconds, yaw_quaternion
from posekit.robot.drive import stamp_to_seconds
from posekit.robot.kinematics import wrap_angle, yaw_from_quaternion_xyzw
from posekit.robot.params import DEFAULT_EKF, EkfParams

__all__ = ["VX", "VY", "VYAW", "YAW", "Ekf2D", "Measurement", "X", "Y"]

X, Y, YAW, VX, VY, VYAW = range(6)
_FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class Measurement:
    """A queued measurement: stamp ``t`` (s), fused state ``indices``, ``values`` and their
    ``variances`` (diagonal covariance)."""

    t: float
    indices: tuple[int, ...]
    values: tuple[float, ...]
    variances: tuple[float, ...]


class Ekf2D:
    """2D EKF over [x, y, yaw, vx, vy, vyaw] (see module doc for the models)."""

    def __init__(
        self,
        params: EkfParams = DEFAULT_EKF,
        *,
        t0: float | None = None,
        initial_pose: tuple[float, float, float] = (0.0, 0.0, 0.0),
    ) -> None:
        """``t0``: filter start time (s; None: the first step or measurement).
        ``initial_pose``: starting ``(x, y, yaw)`` in odom; a relative IMU yaw is reported
        as this yaw plus the change since the first IMU reading."""
        self.params = params
        self.state: _FloatArray = np.zeros(6)
        self.state[:3] = initial_pose
        self._yaw0 = float(initial_pose[2])
        self.covariance: _FloatArray = np.diag(np.asarray(params.initial_covariance_diagonal))
        self._q = np.asarray(params.process_noise_diagonal, dtype=np.float64)
        self._f = np.eye(6)  # Jacobian buffer: only the entries written in predict_to change
        self._diag = np.diag_indices(6)
        self.t: float | None = t0
        self._queue: list[tuple[float, int, Measurement]] = []
        self._seq = 0
        self._imu_yaw_offset: float | None = None

    # ------------------------------------------------------------------ queue
    def enqueue(self, m: Measurement) -> None:
        """Queue a measurement for the next :meth:`step`."""
        heapq.heappush(self._queue, (m.t, self._seq, m))
        self._seq += 1

    def add_wheel_twist(
        self, t: float, vx: float, vy: float, vyaw: float, variances: tuple[float, float, float]
    ) -> None:
        """Queue wheel-odometry ``vx, vy, vyaw`` (base_link) with their variances."""
        self.enqueue(Measurement(t, (VX, VY, VYAW), (vx, vy, vyaw), variances))

    def add_imu(self, t: float, yaw: float, vyaw: float, variances: tuple[float, float]) -> None:
        """Queue an IMU yaw (rad, absolute; made relative to the first one) and yaw rate."""
        if self.params.imu_yaw_relative:
            if self._imu_yaw_offset is None:
                self._imu_yaw_offset = yaw
            yaw = wrap_angle(yaw - self._imu_yaw_offset + self._yaw0)
        self.enqueue(Measurement(t, (YAW, VYAW), (yaw, vyaw), variances))

    def add_odometry_msg(self, msg: Any) -> None:
        """Queue a nav_msgs/Odometry (``odometry/wheels``): its twist vx, vy, vyaw."""
        cov = msg.twist.covariance
        self.add_wheel_twist(
            stamp_to_seconds(msg.header.stamp),
            float(msg.twist.twist.linear.x),
            float(msg.twist.twist.linear.y),
            float(msg.twist.twist.angular.z),
            (float(cov[0]), float(cov[7]), float(cov[35])),
        )

    def add_imu_msg(self, msg: Any) -> None:
        """Queue a sensor_msgs/Imu (``imu/data``): its yaw and angular velocity z."""
        q = msg.orientation
        self.add_imu(
            stamp_to_seconds(msg.header.stamp),
            yaw_from_quaternion_xyzw(float(q.x), float(q.y), float(q.z), float(q.w)),
            float(msg.angular_velocity.z),
            (float(msg.orientation_covariance[8]), float(msg.angular_velocity_covariance[8])),
        )

    # ------------------------------------------------------------------ filter
    def predict_to(self, t: float) -> None:
        """Propagate state and covariance to time ``t`` (s); no-op for ``t`` <= filter time."""
        if self.t is None:
            self.t = t
            return
        dt = t - self.t
        if dt <= 0.0:
            return
        s = self.state
        yaw, vx, vy = s[YAW], s[VX], s[VY]
        c, sn = math.cos(yaw), math.sin(yaw)
        s[X] += (vx * c - vy * sn) * dt
        s[Y] += (vx * sn + vy * c) * dt
        s[YAW] = wrap_angle(yaw + s[VYAW] * dt)
        f = self._f
        f[X, YAW] = (-vx * sn - vy * c) * dt
        f[X, VX] = c * dt
        f[X, VY] = -sn * dt
        f[Y, YAW] = (vx * c - vy * sn) * dt
        f[Y, VX] = sn * dt
        f[Y, VY] = c * dt
        f[YAW, VYAW] = dt
        p = f @ self.covariance @ f.T
        p[self._diag] += self._q * dt
        self.covariance = p
        self.t = t

    def update(self, m: Measurement) -> None:
        """Fuse one measurement now (sequential scalar updates, see module doc)."""
        floor = self.params.min_measurement_variance
        s, p = self.state, self.covariance
        for i, z, r in zip(m.indices, m.values, m.variances, strict=True):
            if not (math.isfinite(z) and math.isfinite(r)):
                continue
            innovation = z - s[i]
            if i == YAW:
                innovation = wrap_angle(innovation)
            row = p[i]
            gain = row / (row[i] + max(r, floor))
            s += gain * innovation
            # P is symmetric, so column i equals row i; the product is formed before -=.
            p -= gain[:, None] * row
        s[YAW] = wrap_angle(s[YAW])

    def step(self, t: float) -> None:
        """Process queued measurements up to ``t`` in stamp order, then predict to ``t``."""
        while self._queue and self._queue[0][0] <= t:
            _, _, m = heapq.heappop(self._queue)
            self.predict_to(m.t)
            self.update(m)
        self.predict_to(t)
        # Keep P symmetric against round-off.
        p = self.covariance
        self.covariance = 0.5 * (p + p.T)

    # ------------------------------------------------------------------ output
    @property
    def pose(self) -> tuple[float, float, float]:
        """Filtered ``(x, y, yaw)`` in odom (m, m, rad)."""
        return float(self.state[X]), float(self.state[Y]), float(self.state[YAW])

    def to_msg(self) -> Odometry:
        """nav_msgs/Odometry for ``odometry/filtered`` (pose in odom, twist in base_link).

        The 6x6 covariances hold the filter's x, y, yaw (and vx, vy, vyaw) blocks; z, roll
        and pitch (and their rates) get 1e-9, the value robot_localization reports in 2D."""
        p = self.params
        msg = Odometry()
        msg.header.stamp = stamp_from_seconds(self.t or 0.0)
        msg.header.frame_id = p.world_frame
        msg.child_frame_id = p.base_link_frame
        s = self.state
        msg.pose.pose.position.x = float(s[X])
        msg.pose.pose.position.y = float(s[Y])
        msg.pose.pose.orientation = yaw_quaternion(float(s[YAW]))
        msg.twist.twist.linear.x = float(s[VX])
        msg.twist.twist.linear.y = float(s[VY])
        msg.twist.twist.angular.z = float(s[VYAW])
        msg.pose.covariance = _embed_planar(self.covariance[:3, :3])
        msg.twist.covariance = _embed_planar(self.covariance[3:, 3:])
        return msg

    def to_transform(self) -> TransformStamped:
        """TF ``odom -> base_link`` (T_odom_base) at the filter time."""
        p = self.params
        tf = TransformStamped()
        tf.header.stamp = stamp_from_seconds(self.t or 0.0)
        tf.header.frame_id = p.world_frame
        tf.child_frame_id = p.base_link_frame
        tf.transform.translation.x = float(self.state[X])
        tf.transform.translation.y = float(self.state[Y])
        tf.transform.rotation = yaw_quaternion(float(self.state[YAW]))
        return tf


_PLANAR_BASE = np.zeros(36)
_PLANAR_BASE[::7] = 1e-9
# Row-major positions of the (x, y, yaw) x (x, y, yaw) entries in a 6x6 over (x..z, roll..yaw).
_PLANAR_FLAT = np.array([6 * r + c for r in (0, 1, 5) for c in (0, 1, 5)])


def _embed_planar(block: _FloatArray) -> _FloatArray:
    """3x3 covariance over (x, y, yaw) -> 36-element row-major 6x6 over (x..z, roll..yaw)."""
    full = _PLANAR_BASE.copy()
    full[_PLANAR_FLAT] = block.ravel()
    return full
