"""Wheel odometry (the odometry part of diff_drive_controller), published on odometry/wheels.

Left and right wheel angles (rad; each side is the mean of its front and rear joints, as
the controller averages the wheels of a side) are turned into travelled distances with the
controller's *effective* radii; the increments give ``ds`` and ``dyaw`` over the interval::

    ds_L = r_L * dtheta_L,  ds_R = r_R * dtheta_R
    ds   = (ds_R + ds_L) / 2,  dyaw = (ds_R - ds_L) / L_eff

and the pose moves along the exact arc (constant curvature over the interval), not the
lecture's first-order Euler step ``x += ds cos(yaw)``. The twist is ``(ds/dt, 0, dyaw/dt)``
in base_link. Messages carry the course's constant covariances.
"""

from __future__ import annotations

from posekit.geometry import wrap_angle
from posekit.msgs.geometry_msgs import (
    Point,
    Pose,
    PoseWithCovariance,
    Twist,
    TwistWithCovariance,
    Vector3,
)
from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.std_msgs import Header
from posekit.robot._msgutil import covariance_from_diagonal, yaw_quaternion
from posekit.robot.kinematics import integrate_exact_arc
from posekit.robot.params import DEFAULT_DRIVE, DriveParams
from posekit.time import stamp_from_seconds

__all__ = ["WheelOdometry"]


class WheelOdometry:
    """Exact-arc integration of encoder increments (see module doc).

    The first :meth:`update` only records the wheel angles (pose stays at the origin).
    """

    def __init__(self, params: DriveParams = DEFAULT_DRIVE) -> None:
        self.params = params
        self.x = 0.0
        self.y = 0.0
        #: Accumulated (unwrapped) heading, rad.
        self.yaw_unwrapped = 0.0
        self.v = 0.0
        self.omega = 0.0
        self.t: float | None = None
        self._left: float | None = None
        self._right: float | None = None
        self._pose_cov = covariance_from_diagonal(params.pose_covariance_diagonal)
        self._twist_cov = covariance_from_diagonal(params.twist_covariance_diagonal)

    @property
    def yaw(self) -> float:
        """Heading wrapped to [-pi, pi), rad."""
        return wrap_angle(self.yaw_unwrapped)

    def update(self, left_angle: float, right_angle: float, t: float) -> None:
        """Integrate the increments since the last call; angles in rad, ``t`` in s."""
        if self._left is None or self._right is None or self.t is None:
            self._left, self._right, self.t = left_angle, right_angle, t
            return
        p = self.params
        ds_l = p.effective_left_wheel_radius * (left_angle - self._left)
        ds_r = p.effective_right_wheel_radius * (right_angle - self._right)
        ds = 0.5 * (ds_r + ds_l)
        dyaw = (ds_r - ds_l) / p.effective_wheel_separation
        self.x, self.y, self.yaw_unwrapped = integrate_exact_arc(
            self.x, self.y, self.yaw_unwrapped, ds, dyaw
        )
        dt = t - self.t
        if dt > 0.0:
            self.v, self.omega = ds / dt, dyaw / dt
        self._left, self._right, self.t = left_angle, right_angle, t

    def update_from_joint_positions(
        self, positions: tuple[float, float, float, float], t: float
    ) -> None:
        """Same as :meth:`update` from (fl, fr, rl, rr) joint angles (rad)."""
        fl, fr, rl, rr = positions
        self.update(0.5 * (fl + rl), 0.5 * (fr + rr), t)

    def to_msg(self, t: float | None = None) -> Odometry:
        """nav_msgs/Odometry: pose in odom, twist in base_link, course covariances."""
        p = self.params
        stamp_t = t if t is not None else (self.t if self.t is not None else 0.0)
        # Every field given (no default sub-message or covariance built and replaced), and
        # positionally in the messages' ROS field order (see Ekf2D.to_msg).
        return Odometry(
            Header(stamp_from_seconds(stamp_t), p.odom_frame_id),
            p.base_frame_id,
            PoseWithCovariance(
                Pose(
                    Point(self.x, self.y, 0.0),
                    yaw_quaternion(self.yaw),
                ),
                self._pose_cov.copy(),
            ),
            TwistWithCovariance(
                Twist(
                    Vector3(self.v, 0.0, 0.0),
                    Vector3(0.0, 0.0, self.omega),
                ),
                self._twist_cov.copy(),
            ),
        )
