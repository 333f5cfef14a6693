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

:meth:`Ekf2D.set_pose` resets the filter to a given pose, as robot_localization's
``set_pose`` does: the state becomes that pose with zero velocities, the covariance
``1e-6 I`` with the pose's x, y, yaw block, queued measurements are dropped, later ones
stamped before the new pose are ignored, and a relative IMU yaw restarts from it.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from posekit.geometry import wrap_angle
from posekit.msgs.geometry_msgs import (
    Point,
    Pose,
    PoseWithCovariance,
    TransformStamped,
    Twist,
    TwistWithCovariance,
    Vector3,
)
from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.std_msgs import Header
from posekit.robot._msgutil import yaw_quaternion
from posekit.robot.kinematics import yaw_from_quaternion_xyzw
from posekit.robot.params import DEFAULT_EKF, EkfParams
from posekit.time import stamp_from_seconds, stamp_to_seconds

__all__ = ["VX", "VY", "VYAW", "YAW", "Ekf2D", "Measurement", "X", "Y"]

X, Y, YAW, VX, VY, VYAW = range(6)
_STATE_INDICES = frozenset(range(6))
_FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class Measurement:
    """A queued measurement.

    Stamp ``t`` (s), fused state ``indices``, ``values`` and their ``variances`` (diagonal
    covariance).

    Raises:
        IndexError: an index is not a state index 0..5 (``X`` .. ``VYAW``).
    """

    t: float
    indices: tuple[int, ...]
    values: tuple[float, ...]
    variances: tuple[float, ...]

    def __post_init__(self) -> None:
        if not _STATE_INDICES.issuperset(self.indices):
            bad = next(i for i in self.indices if i not in _STATE_INDICES)
            raise IndexError(f"measurement index {bad!r} is not a state index 0..5")


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

        ``initial_pose``: starting ``(x, y, yaw)`` in odom; a relative IMU yaw is reported as
        this yaw plus the change since the first IMU reading.
        """
        self.params = params
        # Like the covariance, the state lives as Python floats; the ``state`` array is only
        # built when read (and from then on kept up to date in place, as it always was).
        x0, y0, yaw0 = (float(v) for v in initial_pose)
        self._state_list: list[float] | None = [x0, y0, yaw0, 0.0, 0.0, 0.0]
        self._state_array: _FloatArray | None = None
        self._state_bytes = b""
        self._yaw0 = float(initial_pose[2])
        # The covariance lives as a packed list (see the filter section) and is materialised
        # as a 6x6 array when read through the ``covariance`` property.
        self._cov_packed: list[float] | None = None
        self._cov_array: _FloatArray | None = None
        self._cov_bytes = b""
        self.covariance = np.diag(np.asarray(params.initial_covariance_diagonal, dtype=float))
        self._q_list = [float(q) for q in params.process_noise_diagonal]
        if len(self._q_list) != 6:
            raise ValueError(
                f"process_noise_diagonal needs 6 values, got {len(self._q_list)}"
            )
        self.t: float | None = t0
        self._queue: list[tuple[float, int, Measurement]] = []
        self._seq = 0
        self._imu_yaw_offset: float | None = None
        # Measurements stamped before the last set_pose are ignored (s; None: none yet).
        self._ignore_before: float | None = None

    # ------------------------------------------------------------------ queue
    def enqueue(self, m: Measurement) -> None:
        """Queue a measurement for the next :meth:`step`.

        One stamped before the last :meth:`set_pose` is dropped.
        """
        if self._ignore_before is not None and m.t < self._ignore_before:
            return
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

    def set_pose(self, t: float, x: float, y: float, yaw: float,
                 covariance: npt.ArrayLike) -> None:
        """Reset the filter to pose ``(x, y, yaw)`` (m, m, rad, world frame) at time ``t`` (s).

        As robot_localization's ``set_pose``. Velocities become zero, the covariance ``1e-6 I``
        with the 3x3 ``covariance`` (over x, y, yaw) as its pose block, the queue is emptied,
        measurements stamped before ``t`` are ignored from now on, and a relative IMU yaw is
        measured from ``yaw`` with the next IMU reading as its zero.

        Raises:
            ValueError: a non-finite value or a covariance that is not 3x3.
        """
        cov3 = np.asarray(covariance, dtype=np.float64)
        if cov3.shape != (3, 3):
            raise ValueError(f"set_pose needs a 3x3 covariance over x, y, yaw, got {cov3.shape}")
        values = (t, x, y, yaw)
        if not all(math.isfinite(v) for v in values) or not np.isfinite(cov3).all():
            raise ValueError(f"set_pose needs finite values, got {values} and {cov3.tolist()}")
        self.state = np.array([x, y, wrap_angle(yaw), 0.0, 0.0, 0.0])
        full = np.eye(6) * 1e-6
        idx = np.array([X, Y, YAW])
        full[np.ix_(idx, idx)] = cov3
        self.covariance = full
        self._queue.clear()
        self.t = float(t)
        self._ignore_before = float(t)
        self._yaw0 = float(yaw)
        self._imu_yaw_offset = None

    # ------------------------------------------------------------------ state, covariance
    @property
    def state(self) -> _FloatArray:
        """The state ``[x, y, yaw, vx, vy, vyaw]`` (float64 array, updated in place by the filter).

        It may be replaced or edited in place; the filter picks the change up at its next call.
        """
        arr = self._state_array
        if arr is None:
            arr = np.array(self._state_list, dtype=np.float64)
            self._state_array, self._state_bytes = arr, arr.tobytes()
        return arr

    @state.setter
    def state(self, value: _FloatArray) -> None:
        arr = np.asarray(value, dtype=np.float64)
        if arr.shape != (6,):
            raise ValueError(f"the state must have 6 entries, got shape {arr.shape}")
        self._state_array, self._state_list = arr, None

    def _state_values(self) -> list[float]:
        """The state as floats, re-read from the array if that was set or edited."""
        arr = self._state_array
        values = self._state_list
        if values is None or (arr is not None and arr.tobytes() != self._state_bytes):
            assert arr is not None
            values = arr.tolist()
            self._state_list, self._state_bytes = values, arr.tobytes()
        return values

    @property
    def covariance(self) -> _FloatArray:
        """The 6x6 state covariance (float64 array over x, y, yaw, vx, vy, vyaw).

        It may be replaced or edited in place; the filter picks the change up at its next call.
        """
        arr = self._cov_array
        if arr is None:
            p = self._cov_packed
            assert p is not None
            full = np.empty(36)
            full[_UPPER_FLAT] = p
            full[_LOWER_FLAT] = p
            arr = full.reshape(6, 6)
            self._cov_array, self._cov_bytes = arr, arr.tobytes()
        return arr

    @covariance.setter
    def covariance(self, value: _FloatArray) -> None:
        arr = np.asarray(value, dtype=np.float64)
        if arr.shape != (6, 6):
            raise ValueError(f"the covariance must be 6x6, got shape {arr.shape}")
        self._cov_array, self._cov_packed = arr, None

    def _packed_covariance(self) -> list[float]:
        """The packed covariance, re-read from the array if that was set or edited."""
        arr = self._cov_array
        p = self._cov_packed
        if p is None or (arr is not None and arr.tobytes() != self._cov_bytes):
            assert arr is not None
            p = _pack(arr)
            self._cov_packed, self._cov_bytes = p, arr.tobytes()
        return p

    def _set_packed_covariance(self, p: list[float]) -> None:
        self._cov_packed, self._cov_array = p, None

    # ------------------------------------------------------------------ filter
    # ``state`` and ``covariance`` stay numpy arrays between calls (users read and set
    # them), but the arithmetic runs on Python floats: the state and the 21 distinct entries
    # of the symmetric P (packed row-major upper triangle, see _PACKED) live in local
    # variables for a whole step. For a 6-state filter every numpy call costs more than the
    # few flops it does (measured in docs/performance.md). P is kept exactly symmetric, which
    # also makes the symmetrisation of the array form moot.
    def predict_to(self, t: float) -> None:
        """Propagate state and covariance to time ``t`` (s); no-op for ``t`` <= filter time."""
        self._run((), t, predict=True)

    def update(self, m: Measurement) -> None:
        """Fuse one measurement now (sequential scalar updates, see module doc)."""
        self._run((m,), None, predict=False)

    def step(self, t: float) -> None:
        """Process queued measurements up to ``t`` in stamp order, then predict to ``t``."""
        queue = self._queue
        due = []
        while queue and queue[0][0] <= t:
            due.append(heapq.heappop(queue)[2])
        self._run(due, t, predict=True)

    def _run(
        self, due: Sequence[Measurement], t_end: float | None, *, predict: bool
    ) -> None:
        """Fuse ``due`` in order, then predict to ``t_end`` (None: no final prediction).

        Each measurement is fused after a prediction to its stamp when ``predict``.
        """
        x, y, yaw, vx, vy, vyaw = self._state_values()
        (p00, p01, p02, p03, p04, p05, p11, p12, p13, p14, p15,
         p22, p23, p24, p25, p33, p34, p35, p44, p45, p55) = self._packed_covariance()  # fmt: skip
        q0, q1, q2, q3, q4, q5 = self._q_list
        floor = self.params.min_measurement_variance
        cos, sin, isfinite = math.cos, math.sin, math.isfinite
        t_filter = self.t
        targets: list[tuple[float | None, Measurement | None]] = [(m.t, m) for m in due]
        if t_end is not None:
            targets.append((t_end, None))
        for t_target, m in targets:
            if predict and t_target is not None:
                dt = 0.0 if t_filter is None else t_target - t_filter
                if t_filter is None:
                    t_filter = t_target
                elif dt > 0.0:
                    t_filter = t_target
                    # State: constant body velocity over dt.
                    c, sn = cos(yaw), sin(yaw)
                    x = x + (vx * c - vy * sn) * dt
                    y = y + (vx * sn + vy * c) * dt
                    yaw = wrap_angle(yaw + vyaw * dt)
                    # F = I except rows x: (yaw a, vx b, vy e), y: (yaw d, vx g, vy b),
                    # yaw: (vyaw dt). M = P F^T (the x, y, yaw columns the upper triangle
                    # of F M needs), then P' = F M + Q dt.
                    a = (-vx * sn - vy * c) * dt
                    d = (vx * c - vy * sn) * dt
                    b, g = c * dt, sn * dt
                    e = -g
                    m00 = p00 + a * p02 + b * p03 + e * p04
                    m20 = p02 + a * p22 + b * p23 + e * p24
                    m30 = p03 + a * p23 + b * p33 + e * p34
                    m40 = p04 + a * p24 + b * p34 + e * p44
                    m01 = p01 + d * p02 + g * p03 + b * p04
                    m11 = p11 + d * p12 + g * p13 + b * p14
                    m21 = p12 + d * p22 + g * p23 + b * p24
                    m31 = p13 + d * p23 + g * p33 + b * p34
                    m41 = p14 + d * p24 + g * p34 + b * p44
                    m02 = p02 + dt * p05
                    m12 = p12 + dt * p15
                    m22 = p22 + dt * p25
                    m32 = p23 + dt * p35
                    m42 = p24 + dt * p45
                    m52 = p25 + dt * p55
                    (p00, p01, p02, p03, p04, p05, p11, p12, p13, p14, p15,
                     p22, p23, p24, p25, p33, p34, p35, p44, p45, p55) = (
                        m00 + a * m20 + b * m30 + e * m40 + q0 * dt,
                        m01 + a * m21 + b * m31 + e * m41,
                        m02 + a * m22 + b * m32 + e * m42,
                        p03 + a * p23 + b * p33 + e * p34,
                        p04 + a * p24 + b * p34 + e * p44,
                        p05 + a * p25 + b * p35 + e * p45,
                        m11 + d * m21 + g * m31 + b * m41 + q1 * dt,
                        m12 + d * m22 + g * m32 + b * m42,
                        p13 + d * p23 + g * p33 + b * p34,
                        p14 + d * p24 + g * p34 + b * p44,
                        p15 + d * p25 + g * p35 + b * p45,
                        m22 + dt * m52 + q2 * dt,
                        p23 + dt * p35,
                        p24 + dt * p45,
                        p25 + dt * p55,
                        p33 + q3 * dt,
                        p34,
                        p35,
                        p44 + q4 * dt,
                        p45,
                        p55 + q5 * dt,
                    )  # fmt: skip
            if m is None:
                continue
            for i, z, r in zip(m.indices, m.values, m.variances, strict=True):
                if not (isfinite(z) and isfinite(r)):
                    continue
                # Row i of P (= column i, P is symmetric) and the state component.
                if i == VX:
                    r0, r1, r2, r3, r4, r5, innovation = p03, p13, p23, p33, p34, p35, z - vx
                elif i == YAW:
                    r0, r1, r2, r3, r4, r5 = p02, p12, p22, p23, p24, p25
                    innovation = wrap_angle(z - yaw)
                elif i == VYAW:
                    r0, r1, r2, r3, r4, r5, innovation = p05, p15, p25, p35, p45, p55, z - vyaw
                elif i == VY:
                    r0, r1, r2, r3, r4, r5, innovation = p04, p14, p24, p34, p44, p45, z - vy
                elif i == X:
                    r0, r1, r2, r3, r4, r5, innovation = p00, p01, p02, p03, p04, p05, z - x
                else:  # Y: a Measurement holds state indices only
                    r0, r1, r2, r3, r4, r5, innovation = p01, p11, p12, p13, p14, p15, z - y
                denominator = (r0, r1, r2, r3, r4, r5)[i] + max(r, floor)
                g0, g1, g2 = r0 / denominator, r1 / denominator, r2 / denominator
                g3, g4, g5 = r3 / denominator, r4 / denominator, r5 / denominator
                x, y, yaw = x + g0 * innovation, y + g1 * innovation, yaw + g2 * innovation
                vx, vy, vyaw = vx + g3 * innovation, vy + g4 * innovation, vyaw + g5 * innovation
                # P -= gain row^T, upper triangle (P stays exactly symmetric).
                (p00, p01, p02, p03, p04, p05, p11, p12, p13, p14, p15,
                 p22, p23, p24, p25, p33, p34, p35, p44, p45, p55) = (
                    p00 - g0 * r0, p01 - g0 * r1, p02 - g0 * r2, p03 - g0 * r3, p04 - g0 * r4,
                    p05 - g0 * r5, p11 - g1 * r1, p12 - g1 * r2, p13 - g1 * r3, p14 - g1 * r4,
                    p15 - g1 * r5, p22 - g2 * r2, p23 - g2 * r3, p24 - g2 * r4, p25 - g2 * r5,
                    p33 - g3 * r3, p34 - g3 * r4, p35 - g3 * r5, p44 - g4 * r4, p45 - g4 * r5,
                    p55 - g5 * r5,
                )  # fmt: skip
            yaw = wrap_angle(yaw)
        values = [x, y, yaw, vx, vy, vyaw]
        self._state_list = values
        arr = self._state_array
        if arr is not None:  # someone holds the array: update it in place
            arr[:] = values
            self._state_bytes = arr.tobytes()
        self._set_packed_covariance(
            [p00, p01, p02, p03, p04, p05, p11, p12, p13, p14, p15,
             p22, p23, p24, p25, p33, p34, p35, p44, p45, p55]
        )  # fmt: skip
        self.t = t_filter

    # ------------------------------------------------------------------ output
    @property
    def pose(self) -> tuple[float, float, float]:
        """Filtered ``(x, y, yaw)`` in odom (m, m, rad)."""
        x, y, yaw = self._state_values()[:3]
        return x, y, yaw

    def to_msg(self) -> Odometry:
        """nav_msgs/Odometry for ``odometry/filtered`` (pose in odom, twist in base_link).

        The 6x6 covariances hold the filter's x, y, yaw (and vx, vy, vyaw) blocks; z, roll
        and pitch (and their rates) get 1e-9, the value robot_localization reports in 2D.
        """
        params = self.params
        x, y, yaw, vx, vy, vyaw = self._state_values()
        (p00, p01, p02, _, _, _, p11, p12, _, _, _,
         p22, _, _, _, p33, p34, p35, p44, p45, p55) = self._packed_covariance()  # fmt: skip
        # Every field given (no default sub-message or covariance built and dropped), and
        # positionally in the messages' ROS field order (header, child_frame_id, pose, twist;
        # pose = (position, orientation), twist = (linear, angular)): about twice as fast as
        # keyword arguments for these dataclasses.
        return Odometry(
            Header(stamp_from_seconds(self.t or 0.0), params.world_frame),
            params.base_link_frame,
            PoseWithCovariance(
                Pose(Point(x, y, 0.0), yaw_quaternion(yaw)),
                _embed_planar(p00, p01, p02, p11, p12, p22),
            ),
            TwistWithCovariance(
                Twist(Vector3(vx, vy, 0.0), Vector3(0.0, 0.0, vyaw)),
                _embed_planar(p33, p34, p35, p44, p45, p55),
            ),
        )

    def to_transform(self) -> TransformStamped:
        """TF ``odom -> base_link`` (T_odom_base) at the filter time."""
        p = self.params
        tf = TransformStamped()
        tf.header.stamp = stamp_from_seconds(self.t or 0.0)
        tf.header.frame_id = p.world_frame
        tf.child_frame_id = p.base_link_frame
        x, y, yaw = self._state_values()[:3]
        tf.transform.translation.x = x
        tf.transform.translation.y = y
        tf.transform.rotation = yaw_quaternion(yaw)
        return tf


# Packed symmetric 6x6: the upper triangle row-major (00 01 .. 05 11 12 .. 55).
_PACKED = [(r, c) for r in range(6) for c in range(r, 6)]
_UPPER_FLAT = np.array([6 * r + c for r, c in _PACKED])
_LOWER_FLAT = np.array([6 * c + r for r, c in _PACKED])
_UPPER_ROWS, _UPPER_COLS = np.triu_indices(6)


def _pack(covariance: _FloatArray) -> list[float]:
    """Packed upper triangle of a (symmetric) 6x6 covariance.

    An asymmetric one (set by a user) is symmetrised first, 0.5 (P + P^T).
    """
    upper = covariance[_UPPER_ROWS, _UPPER_COLS]
    lower = covariance[_UPPER_COLS, _UPPER_ROWS]
    if not np.array_equal(upper, lower):
        upper = 0.5 * (upper + lower)
    packed: list[float] = upper.tolist()
    return packed


def _embed_planar(
    a00: float, a01: float, a02: float, a11: float, a12: float, a22: float
) -> _FloatArray:
    """A 3x3 covariance over (x, y, yaw) as the 6x6 of a ROS message.

    The 3x3 is given by its upper triangle; the result is 36 elements, row-major over (x, y, z,
    roll, pitch, yaw), with 1e-9 for z, roll and pitch.
    """
    full = _PLANAR_BASE.copy()  # item writes beat building an array from a list here
    full[0], full[1], full[5] = a00, a01, a02
    full[6], full[7], full[11] = a01, a11, a12
    full[30], full[31], full[35] = a02, a12, a22
    return full


_PLANAR_BASE = np.zeros(36)
_PLANAR_BASE[[14, 21, 28]] = 1e-9  # z, roll, pitch variances
