"""The course's go-to-pose P controller (robot_control_demo ``p_controller``) as a pure model.

At each tick (20 Hz in the node) from the filtered pose ``(x, y, yaw)``::

    dx, dy = x_g - x, y_g - y,   rho = hypot(dx, dy)
    phase 1 (rho > goal_tolerance):
        alpha = wrap(atan2(dy, dx) - yaw)
        v     = clip(k_rho * rho,   +-max_linear)
        omega = clip(k_alpha * alpha, +-max_angular)
    phase 2 (rho <= goal_tolerance):
        e     = wrap(yaw_g - yaw)
        |e| >= yaw_tolerance: v = 0, omega = clip(k_yaw * e, +-max_angular)
        |e| <  yaw_tolerance: zero twist, goal reached (latched until a new goal)

Angles are wrapped to [-pi, pi) so the robot always turns the short way. A goal of exactly
(0, 0, 0) is the node's "no goal" default: the controller stays idle and commands nothing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum

from posekit.geometry import wrap_angle

__all__ = ["ControlOutput", "PController", "PControllerParams", "Phase"]


class Phase(StrEnum):
    """Which part of the control law produced a command."""

    IDLE = "idle"
    POSITION = "position"
    ORIENTATION = "orientation"
    DONE = "done"


@dataclass(frozen=True, slots=True)
class PControllerParams:
    """Node parameters and defaults of the course's ``p_controller`` (gains in 1/s)."""

    k_rho: float = 0.4
    k_alpha: float = 0.8
    k_yaw: float = 0.8
    goal_tolerance: float = 0.10
    yaw_tolerance: float = 0.05
    max_linear: float = 0.5
    max_angular: float = 1.0
    rate_hz: float = 20.0
    goal_x: float = 0.0
    goal_y: float = 0.0
    goal_yaw: float = 0.0


@dataclass(frozen=True, slots=True)
class ControlOutput:
    """One tick's result: command ``v`` (m/s), ``omega`` (rad/s), the ``phase``, distance
    ``rho`` (m), the angle error being driven (``alpha`` in phase 1, yaw error in phase 2,
    rad), ``goal_reached`` (latched) and ``just_reached`` (True only on the reaching tick).
    ``publish`` is False while idle (no goal): the node then sends nothing."""

    v: float
    omega: float
    phase: Phase
    rho: float
    angle_error: float
    goal_reached: bool
    just_reached: bool
    publish: bool = True


def _clip(value: float, limit: float) -> float:
    return max(-limit, min(limit, value))


class PController:
    """The two-phase proportional controller (see module doc)."""

    def __init__(self, params: PControllerParams = PControllerParams()) -> None:
        self.params = params
        self.goal: tuple[float, float, float] | None = None
        self.goal_reached = False
        self.set_goal(params.goal_x, params.goal_y, params.goal_yaw)

    @property
    def period(self) -> float:
        """Seconds between ticks."""
        return 1.0 / self.params.rate_hz

    def set_goal(self, x: float, y: float, yaw: float) -> None:
        """New goal in odom (m, m, rad); (0, 0, 0) clears it. Resets ``goal_reached``."""
        if not all(math.isfinite(a) for a in (x, y, yaw)):
            raise ValueError(f"goal must be finite, got ({x}, {y}, {yaw})")
        self.goal = None if (x, y, yaw) == (0.0, 0.0, 0.0) else (x, y, wrap_angle(yaw))
        self.goal_reached = False

    def compute(self, x: float, y: float, yaw: float) -> ControlOutput:
        """One control tick from the pose ``(x, y, yaw)`` in odom."""
        p = self.params
        if self.goal is None:
            return ControlOutput(0.0, 0.0, Phase.IDLE, 0.0, 0.0, False, False, publish=False)
        gx, gy, gyaw = self.goal
        dx, dy = gx - x, gy - y
        rho = math.hypot(dx, dy)
        if self.goal_reached:
            return ControlOutput(0.0, 0.0, Phase.DONE, rho, wrap_angle(gyaw - yaw), True, False)
        if rho > p.goal_tolerance:
            alpha = wrap_angle(math.atan2(dy, dx) - yaw)
            return ControlOutput(
                _clip(p.k_rho * rho, p.max_linear),
                _clip(p.k_alpha * alpha, p.max_angular),
                Phase.POSITION,
                rho,
                alpha,
                False,
                False,
            )
        err = wrap_angle(gyaw - yaw)
        if abs(err) >= p.yaw_tolerance:
            return ControlOutput(
                0.0, _clip(p.k_yaw * err, p.max_angular), Phase.ORIENTATION, rho, err, False, False
            )
        self.goal_reached = True
        return ControlOutput(0.0, 0.0, Phase.DONE, rho, err, True, True)
