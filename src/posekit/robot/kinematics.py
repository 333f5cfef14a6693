"""Differential-drive kinematics, angle wrapping and exact-arc pose integration (SE(2)).

Conventions (lecture, REP-103): ``v`` is forward speed along base_link x (m/s, > 0 forward),
``omega`` the yaw rate about z (rad/s, > 0 counter-clockwise = left turn). ``v_left`` and
``v_right`` are wheel *surface* speeds (m/s); wheel angular velocities are those divided by
the wheel radius. ``L`` is the wheel separation (m) and ``r`` the wheel radius (m).

Lecture formulas::

    v = r (w_R + w_L) / 2          omega = r (w_R - w_L) / L        (w: wheel rad/s)
    w_R = (2 v + omega L) / (2 r)  w_L = (2 v - omega L) / (2 r)
"""

from __future__ import annotations

import math

from posekit.geometry.se2 import integrate_arc

__all__ = [
    "body_to_wheel_speeds",
    "integrate_exact_arc",
    "quaternion_xyzw_from_yaw",
    "wheel_to_body_speeds",
    "yaw_from_quaternion_xyzw",
]

def wheel_to_body_speeds(
    omega_left: float, omega_right: float, *, wheel_separation: float, wheel_radius: float
) -> tuple[float, float]:
    """Wheel angular velocities (rad/s) -> body ``(v, omega)`` in base_link (m/s, rad/s)."""
    v = wheel_radius * (omega_right + omega_left) / 2.0
    omega = wheel_radius * (omega_right - omega_left) / wheel_separation
    return v, omega


def body_to_wheel_speeds(
    v: float, omega: float, *, wheel_separation: float, wheel_radius: float
) -> tuple[float, float]:
    """Body ``(v, omega)`` -> wheel angular velocities ``(omega_left, omega_right)`` (rad/s)."""
    omega_right = (2.0 * v + omega * wheel_separation) / (2.0 * wheel_radius)
    omega_left = (2.0 * v - omega * wheel_separation) / (2.0 * wheel_radius)
    return omega_left, omega_right


def integrate_exact_arc(
    x: float,
    y: float,
    yaw: float,
    ds: float,
    dyaw: float,
    lateral: float = 0.0,
) -> tuple[float, float, float]:
    """Move a planar pose along a constant-curvature arc (the SE(2) exponential).

    Args:
        x, y, yaw: start pose in the fixed frame (m, m, rad).
        ds: distance travelled along base_link x over the step (m), i.e. ``v * dt``.
        dyaw: heading change over the step (rad), i.e. ``omega * dt``.
        lateral: distance travelled along base_link y (m), ``vy * dt`` (0 for diff drive).

    Returns:
        The end pose ``(x, y, yaw)``; yaw is *not* wrapped, so it can be accumulated.

    This is exact for a constant body twist over the step: the robot follows a circle of
    radius ``ds / dyaw``. The lecture's Euler update ``x += ds cos(yaw)`` is its first-order
    approximation. The maths is :func:`posekit.geometry.se2.integrate_arc` (the kernel of
    ``Pose2D.exp``, with a Taylor series near ``dyaw = 0``), kept as plain floats because the
    simulator calls it at 100 Hz per robot.
    """
    return integrate_arc(x, y, yaw, ds, lateral, dyaw)


def quaternion_xyzw_from_yaw(yaw: float) -> tuple[float, float, float, float]:
    """Quaternion (x, y, z, w), ROS order, of a rotation by ``yaw`` rad about +z."""
    half = 0.5 * yaw
    return 0.0, 0.0, math.sin(half), math.cos(half)


def yaw_from_quaternion_xyzw(qx: float, qy: float, qz: float, qw: float) -> float:
    """Yaw (rad, in [-pi, pi]) of a quaternion given in ROS order (x, y, z, w)."""
    return math.atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))
