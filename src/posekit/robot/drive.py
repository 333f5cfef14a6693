"""The simulated ROSbot base: diff_drive_controller command handling plus a skid-steer plant.

:class:`RosbotBase` is a pure model (no runtime): a node wrapper calls
:meth:`RosbotBase.submit` for every ``/cmd_vel`` TwistStamped and :meth:`RosbotBase.step`
at the controller rate (100 Hz), then reads :attr:`RosbotBase.state` for ground truth and
the wheel joints.

Command handling follows ros2_controllers' diff_drive_controller (Jazzy):

* a command whose header stamp is zero is stamped with the current time;
* a command older than ``cmd_vel_timeout`` on arrival is rejected (with a reason string);
* a command with a non-finite component is rejected;
* at each update, if the last accepted command is older than ``cmd_vel_timeout`` the target
  becomes zero, so a stream that stops makes the robot brake (at the acceleration limit);
* the target is limited in acceleration, then in velocity (SpeedLimiter order), converted
  to wheel speeds with the *effective* separation and radii, and each wheel saturates at the
  URDF joint velocity limit.

The plant replaces Gazebo's contacts with the slip model of
:class:`~posekit.robot.params.SlipParams`
(yaw efficiency ``eta`` and longitudinal slip ``s``, seeded per-run offset plus an
Ornstein-Uhlenbeck wander). The ground-truth pose is integrated with the exact arc. With a
:class:`~posekit.robot.contact.Contact`, a step that would drive the body into a solid box
is cut short at its surface while the wheels turn on (see :mod:`posekit.robot.contact`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from posekit.geometry import wrap_angle
from posekit.robot.kinematics import integrate_exact_arc
from posekit.robot.params import DEFAULT_DRIVE, DEFAULT_SLIP, DriveParams, SlipParams
from posekit.time import stamp_to_seconds

if TYPE_CHECKING:
    from posekit.robot.contact import Contact

__all__ = ["FUTURE_TOLERANCE", "BaseState", "CommandResult", "RosbotBase"]

#: A command stamped more than this (s) after the current time is "in the future" (1 µs:
#: far below any real clock offset, above the rounding of float seconds near 1e9).
FUTURE_TOLERANCE = 1e-6


def _clamp(value: float, low: float, high: float) -> float:
    return low if value < low else high if value > high else value


@dataclass(frozen=True, slots=True)
class CommandResult:
    """Outcome of :meth:`RosbotBase.submit`: ``accepted`` and, if not, the ``reason``.

    ``reason`` is also set for an accepted command that needed fixing (zero stamp).
    ``kind`` names the rule: ``""`` (accepted as is), ``"zero_stamp"``, ``"stale"``,
    ``"future"`` or ``"non_finite"``.
    """

    accepted: bool
    reason: str = ""
    kind: str = ""


@dataclass(slots=True)
class BaseState:
    """Ground truth of the simulated base at one instant.

    Pose of base_link in the world/odom frame (the robot spawns at the odom origin):
    ``x, y`` (m), ``yaw`` (rad, wrapped to [-pi, pi)). Body twist in base_link: ``v`` (m/s),
    ``omega`` (rad/s); body acceleration in base_link: ``ax`` (dv/dt) and ``ay`` (v * omega,
    centripetal), m/s². Wheel joints in WHEEL_JOINT_NAMES order (fl, fr, rl, rr):
    ``wheel_positions`` (rad, unwrapped) and ``wheel_velocities`` (rad/s). ``commanded_v``
    and ``commanded_omega`` are the limited command the controller applied (what its odometry
    believes it asked for).
    """

    x: float = 0.0
    y: float = 0.0
    yaw: float = 0.0
    v: float = 0.0
    omega: float = 0.0
    ax: float = 0.0
    ay: float = 0.0
    wheel_positions: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)
    wheel_velocities: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)
    commanded_v: float = 0.0
    commanded_omega: float = 0.0
    yaw_efficiency: float = 1.0
    longitudinal_slip: float = 0.0


class RosbotBase:
    """diff_drive_controller + skid-steer plant of the simulated ROSbot (see module doc).

    Args:
        params: controller and wheel parameters.
        slip: slip model parameters (``SlipParams(enabled=False)`` for an ideal base whose
            true motion equals the command).
        seed: seeds the per-run slip offsets and their wander (same seed, same run).
        x, y, yaw: spawn pose in odom (m, m, rad).
        contact: the world's solid boxes (None: nothing stops the body).
    """

    def __init__(
        self,
        params: DriveParams = DEFAULT_DRIVE,
        slip: SlipParams = DEFAULT_SLIP,
        *,
        seed: int | None = 0,
        x: float = 0.0,
        y: float = 0.0,
        yaw: float = 0.0,
        contact: Contact | None = None,
    ) -> None:
        self.params = params
        #: Contact with the world's solid boxes, or None.
        self.contact = contact
        self.slip = slip
        self._rng = np.random.default_rng(seed)
        self._normals: list[float] = []
        # Raw (unwrapped) heading: wrapped only when reported.
        self._x, self._y, self._yaw = float(x), float(y), float(yaw)
        self._v_cmd = 0.0
        self._w_cmd = 0.0
        self._v_true = 0.0
        self._w_true = 0.0
        self._ax = 0.0
        self._left_angle = 0.0
        self._right_angle = 0.0
        self._omega_left = 0.0
        self._omega_right = 0.0
        self._target_v = 0.0
        self._target_w = 0.0
        self._cmd_stamp: float | None = None
        self._l_eff = params.effective_wheel_separation
        self._r_left = params.effective_left_wheel_radius
        self._r_right = params.effective_right_wheel_radius
        self._ou_coeffs: dict[float, tuple[float, float]] = {}
        if slip.enabled:
            self._eta0 = slip.nominal_yaw_efficiency(params) * (
                1.0 + slip.yaw_efficiency_run_std * self._normal()
            )
            self._s0 = (
                slip.nominal_longitudinal_slip(params)
                + (1.0 - slip.nominal_longitudinal_slip(params))
                * slip.longitudinal_slip_run_std
                * self._normal()
            )
        else:
            # Ideal base: exactly what the controller's effective geometry predicts.
            r_eff = 0.5 * (params.effective_left_wheel_radius + params.effective_right_wheel_radius)
            self._eta0 = (
                r_eff
                * params.track_width
                / (params.wheel_radius * params.effective_wheel_separation)
            )
            self._s0 = 1.0 - r_eff / params.wheel_radius
        # The wander starts from its stationary distribution (no transient at spawn).
        self._eta_walk = slip.yaw_efficiency_walk_std * self._normal() if slip.enabled else 0.0
        self._s_walk = slip.longitudinal_slip_walk_std * self._normal() if slip.enabled else 0.0

    # ------------------------------------------------------------------ commands
    def submit(self, msg: Any, now: float) -> CommandResult:
        """Offer a geometry_msgs/TwistStamped received at ``now`` (s). Only linear.x and
        angular.z are used (the other components are ignored, as on the real controller)."""
        return self.submit_velocity(
            float(msg.twist.linear.x),
            float(msg.twist.angular.z),
            stamp=stamp_to_seconds(msg.header.stamp),
            now=now,
        )

    def submit_velocity(self, v: float, omega: float, *, stamp: float, now: float) -> CommandResult:
        """Offer a command ``(v m/s, omega rad/s)`` stamped ``stamp`` arriving at ``now`` (s).

        Returns whether it was accepted and why not. A zero stamp means "now".
        """
        if not (math.isfinite(v) and math.isfinite(omega) and math.isfinite(stamp)):
            return CommandResult(
                False, f"non-finite command (v={v}, omega={omega}, stamp={stamp})", "non_finite"
            )
        note = kind = ""
        if stamp == 0.0:
            stamp = now
            note, kind = "zero header stamp: stamped with the current time", "zero_stamp"
        if stamp - now > FUTURE_TOLERANCE:
            return CommandResult(
                False,
                f"command stamped in the future: stamp {stamp:.9f} s is {stamp - now:.3f} s "
                f"ahead of the simulation's time ({now:.9f} s), so cmd_vel_timeout could "
                "never expire; its sender is not on this simulation's clock (run it with "
                "use_sim_time:=true, or stamp 0 for 'now')",
                "future",
            )
        age = now - stamp
        timeout = self.params.cmd_vel_timeout
        if timeout > 0.0 and age >= timeout:
            return CommandResult(
                False,
                f"stale command: stamp {stamp:.9f} s is {age:.9f} s older than now "
                f"({now:.9f} s), which exceeds cmd_vel_timeout {timeout:.3f} s",
                "stale",
            )
        self._target_v = v
        self._target_w = omega
        self._cmd_stamp = stamp
        return CommandResult(True, note, kind)

    # ------------------------------------------------------------------ simulation
    def step(self, now: float, dt: float | None = None) -> None:
        """Advance the base from ``now`` by one control period (or ``dt`` s); read the new
        state from :attr:`state` (or the cheap :attr:`pose`, :attr:`wheel_angles`)."""
        p = self.params
        if dt is None:
            dt = p.control_period
        # Timeout: brake when the last command is too old (or none has arrived).
        if self._cmd_stamp is None or (
            p.cmd_vel_timeout > 0.0 and now - self._cmd_stamp > p.cmd_vel_timeout
        ):
            tv, tw = 0.0, 0.0
        else:
            tv, tw = self._target_v, self._target_w
        # SpeedLimiter: acceleration first, then velocity (clamps inlined: 100 Hz hot path).
        low, high = (
            self._v_cmd - p.max_linear_acceleration * dt,
            self._v_cmd + p.max_linear_acceleration * dt,
        )
        v = low if tv < low else high if tv > high else tv
        low, high = (
            self._w_cmd - p.max_angular_acceleration * dt,
            self._w_cmd + p.max_angular_acceleration * dt,
        )
        w = low if tw < low else high if tw > high else tw
        high = p.max_linear_velocity
        v = -high if v < -high else high if v > high else v
        high = p.max_angular_velocity
        w = -high if w < -high else high if w > high else w
        self._v_cmd, self._w_cmd = v, w
        # Controller: body command -> wheel angular velocities with the effective geometry.
        half_w_l = 0.5 * w * self._l_eff
        wl = (v - half_w_l) / self._r_left
        wr = (v + half_w_l) / self._r_right
        lim = p.wheel_velocity_limit
        if lim is not None:
            wl = _clamp(wl, -lim, lim)
            wr = _clamp(wr, -lim, lim)
        self._omega_left, self._omega_right = wl, wr
        # Plant: wheel surface speeds with the URDF radius, then the slip model.
        eta, s = self._slip_factors(dt)
        u_l = p.wheel_radius * wl
        u_r = p.wheel_radius * wr
        v_true = (1.0 - s) * 0.5 * (u_l + u_r)
        w_true = eta * (u_r - u_l) / p.track_width
        contact = self.contact
        if contact is not None and (v_true != 0.0 or w_true != 0.0):
            # The body stops at a solid surface; the wheels (below) turn on regardless.
            fraction = contact.free_fraction(
                self._x, self._y, self._yaw, v_true * dt, w_true * dt
            )
            if fraction < 1.0:
                v_true *= fraction
                w_true *= fraction
        self._x, self._y, self._yaw = integrate_exact_arc(
            self._x, self._y, self._yaw, v_true * dt, w_true * dt
        )
        self._ax = (v_true - self._v_true) / dt
        self._v_true, self._w_true = v_true, w_true
        self._left_angle += wl * dt
        self._right_angle += wr * dt

    def _normal(self) -> float:
        # Standard normals drawn in blocks: numpy's generator, amortised per call.
        if not self._normals:
            self._normals = self._rng.standard_normal(4096).tolist()
            self._normals.reverse()
        return self._normals.pop()

    def _slip_factors(self, dt: float) -> tuple[float, float]:
        sp = self.slip
        if not sp.enabled:
            return self._eta0, self._s0
        # Ornstein-Uhlenbeck (exact discretisation) for both relative wanders.
        coeffs = self._ou_coeffs.get(dt)
        if coeffs is None:
            decay = math.exp(-dt / sp.correlation_time)
            coeffs = self._ou_coeffs[dt] = (decay, math.sqrt(1.0 - decay * decay))
        decay, kick = coeffs
        self._eta_walk = decay * self._eta_walk + kick * sp.yaw_efficiency_walk_std * self._normal()
        self._s_walk = decay * self._s_walk + kick * sp.longitudinal_slip_walk_std * self._normal()
        eta = self._eta0 * (1.0 + self._eta_walk)
        s = self._s0 + (1.0 - self._s0) * self._s_walk
        return eta, s

    @property
    def state(self) -> BaseState:
        """Ground truth now (see :class:`BaseState`)."""
        return BaseState(
            x=self._x,
            y=self._y,
            yaw=wrap_angle(self._yaw),
            v=self._v_true,
            omega=self._w_true,
            ax=self._ax,
            ay=self._v_true * self._w_true,
            wheel_positions=(
                self._left_angle,
                self._right_angle,
                self._left_angle,
                self._right_angle,
            ),
            wheel_velocities=(
                self._omega_left,
                self._omega_right,
                self._omega_left,
                self._omega_right,
            ),
            commanded_v=self._v_cmd,
            commanded_omega=self._w_cmd,
            yaw_efficiency=self._eta0 * (1.0 + self._eta_walk),
            longitudinal_slip=self._s0 + (1.0 - self._s0) * self._s_walk,
        )

    @property
    def pose(self) -> tuple[float, float, float]:
        """Ground-truth ``(x, y, yaw)`` with yaw unwrapped (accumulated), cheap to read."""
        return self._x, self._y, self._yaw

    @property
    def wheel_angles(self) -> tuple[float, float]:
        """Left and right wheel angles (rad, unwrapped); front and rear of a side are equal."""
        return self._left_angle, self._right_angle

    @property
    def wheel_velocities(self) -> tuple[float, float, float, float]:
        """Commanded wheel angular velocities (fl, fr, rl, rr), rad/s, cheap to read."""
        wl, wr = self._omega_left, self._omega_right
        return wl, wr, wl, wr

    @property
    def body_velocity(self) -> tuple[float, float, float]:
        """True ``(v, omega, ax)`` in base_link, cheap to read."""
        return self._v_true, self._w_true, self._ax

    @property
    def last_command_stamp(self) -> float | None:
        """Stamp (s) of the last accepted command, None before the first."""
        return self._cmd_stamp
