"""Wheel encoders: the four wheel joint angles as ``/joint_states`` reports them.

Gazebo's ros2_control system reports exact joint positions; :class:`WheelEncoders` can
optionally quantise them to the real robot's ~1633 counts per wheel revolution
(``EncoderParams.quantize``), rounding to the nearest count.
"""

from __future__ import annotations

import math

import numpy as np

from posekit.msgs.sensor_msgs import JointState
from posekit.msgs.std_msgs import Header
from posekit.robot.params import DEFAULT_ENCODERS, WHEEL_JOINT_NAMES, EncoderParams
from posekit.time import stamp_from_seconds

__all__ = ["WheelEncoders"]


class WheelEncoders:
    """Turns true wheel angles (rad) into encoder readings (rad), optionally quantised."""

    def __init__(self, params: EncoderParams = DEFAULT_ENCODERS) -> None:
        self.params = params
        self._rad_per_count = 2.0 * math.pi / params.counts_per_revolution

    def read_angle(self, angle: float) -> float:
        """One wheel's reported angle (rad) for a true angle (rad)."""
        if not self.params.quantize:
            return angle
        return round(angle / self._rad_per_count) * self._rad_per_count

    def read(
        self, wheel_positions: tuple[float, float, float, float]
    ) -> tuple[float, float, float, float]:
        """Reported angles of (fl, fr, rl, rr) for the true angles, rad."""
        fl, fr, rl, rr = wheel_positions
        return self.read_angle(fl), self.read_angle(fr), self.read_angle(rl), self.read_angle(rr)

    def joint_state(
        self,
        wheel_positions: tuple[float, float, float, float],
        wheel_velocities: tuple[float, float, float, float],
        t: float,
    ) -> JointState:
        """sensor_msgs/JointState for ``/joint_states`` at time ``t`` (s)."""
        # Fields positionally, in the message's (ROS) order: header, name, position,
        # velocity, effort (twice as fast as keywords for these dataclasses).
        return JointState(
            Header(stamp_from_seconds(t), ""),
            list(WHEEL_JOINT_NAMES),
            np.array(self.read(wheel_positions), dtype=np.float64),
            np.array(wheel_velocities, dtype=np.float64),
            np.zeros(0, dtype=np.float64),
        )
