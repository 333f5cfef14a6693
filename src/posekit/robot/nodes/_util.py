"""Helpers shared by the ROSbot nodes: wheel-geometry parameters and rates as periods."""

from __future__ import annotations

from typing import TypedDict

from posekit.robot.params import DEFAULT_DRIVE
from posekit.runtime.node import Node
from posekit.runtime.parameters import declare_value
from posekit.time import NS_PER_S

__all__ = [
    "NS",
    "WheelGeometry",
    "declare_wheel_geometry",
    "period_ns",
]

NS = NS_PER_S


class WheelGeometry(TypedDict):
    """The ``DriveParams`` wheel fields (m, and dimensionless multipliers)."""

    wheel_separation: float
    wheel_radius: float
    wheel_separation_multiplier: float
    left_wheel_radius_multiplier: float
    right_wheel_radius_multiplier: float


def declare_wheel_geometry(node: Node) -> WheelGeometry:
    """Declare the diff_drive_controller wheel parameters that both the simulated drive and
    the wheel odometry read, defaults from :data:`DEFAULT_DRIVE`; ``DriveParams`` keywords."""
    d = DEFAULT_DRIVE
    return WheelGeometry(
        wheel_separation=float(declare_value(node, "wheel_separation", d.wheel_separation)),
        wheel_radius=float(declare_value(node, "wheel_radius", d.wheel_radius)),
        wheel_separation_multiplier=float(
            declare_value(node, "wheel_separation_multiplier", d.wheel_separation_multiplier)
        ),
        left_wheel_radius_multiplier=float(
            declare_value(node, "left_wheel_radius_multiplier", d.left_wheel_radius_multiplier)
        ),
        right_wheel_radius_multiplier=float(
            declare_value(node, "right_wheel_radius_multiplier", d.right_wheel_radius_multiplier)
        ),
    )


def period_ns(rate_hz: float, what: str) -> int:
    """Period in ns of a positive rate (Hz); a clear ValueError otherwise."""
    if not rate_hz > 0.0:
        raise ValueError(f"{what} must be > 0 Hz, got {rate_hz}")
    return round(NS / rate_hz)
