"""A printed walkthrough of the lecture's "Pose" section, computed live with posekit.geometry.

Run: ``python -m posekit.demos.pose_walkthrough``. Every number below comes from posekit
(nothing is a hard-coded result): the common-quaternion table, the axis-angle exercise, the
double cover, world vs body composition, and Appendix A's gimbal-lock example.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence

import numpy as np

from posekit.geometry import GimbalLockWarning, Rotation, compose_body, compose_world

__all__ = ["COMMON_ROTATIONS", "main", "report"]

#: (description, axis, angle in degrees) of the lecture's table of common quaternions.
COMMON_ROTATIONS: tuple[tuple[str, tuple[float, float, float], float], ...] = (
    ("No rotation (identity)", (0.0, 0.0, 1.0), 0.0),
    ("90 deg about Z (yaw left)", (0.0, 0.0, 1.0), 90.0),
    ("180 deg about Z (face backward)", (0.0, 0.0, 1.0), 180.0),
    ("90 deg about X (roll right)", (1.0, 0.0, 0.0), 90.0),
    ("45 deg about Y (pitch up)", (0.0, 1.0, 0.0), 45.0),
)


def _num(v: float) -> str:
    return f"{round(float(v), 3) + 0.0:+.3f}"  # + 0.0 turns -0.0 into 0.0


def _q(values: Sequence[float] | np.ndarray) -> str:
    return "(" + ", ".join(_num(v) for v in values) + ")"


_vec = _q


def _matrix(m: np.ndarray, indent: str = "    ") -> list[str]:
    return [indent + "[" + " ".join(_num(v) for v in row) + "]" for row in m]


def report() -> str:
    """The whole walkthrough as text."""
    out: list[str] = []
    add = out.append
    add("posekit pose walkthrough (lecture section 'Pose', Appendix A)")
    add("Quaternions are printed (w, x, y, z) like the lecture; posekit stores (x, y, z, w).")
    add("")

    add("1. Common quaternion values")
    add(f"   {'rotation':34s} {'(w, x, y, z)':34s} angle")
    for name, axis, deg in COMMON_ROTATIONS:
        r = Rotation.from_axis_angle(axis, deg, degrees=True)
        wxyz = r.as_quat(scalar_first=True)
        add(f"   {name:34s} {_q(wxyz):34s} {math.degrees(float(r.magnitude())):6.1f} deg")
    add("")

    add("2. Exercise: rotation of pi/2 about the x axis")
    u = np.array((1.0, 0.0, 0.0))
    alpha = math.pi / 2
    add(f"   axis u = {_vec(u)}, |u| = {np.linalg.norm(u):.3f} (unit, as required)")
    r_ex = Rotation.from_axis_angle(u, alpha)
    w, x, y, z = r_ex.as_quat(scalar_first=True)
    add(f"   w = cos(alpha/2) = {w:.3f}; x = sin(alpha/2) * u_x = {x:.3f}; "
        f"y = {y:.3f}; z = {z:.3f}")
    add(f"   q = (w, x, y, z) = {_q(np.array((w, x, y, z)))}")
    p = np.array((0.0, 1.0, 0.0))
    add(f"   rotating p = {_vec(p)} by p' = q p q^-1 gives {_vec(r_ex.apply(p))}")
    neg = Rotation.from_quat(-r_ex.as_quat())
    same = bool(neg.approx_equal(r_ex))
    minus_q = _q(-r_ex.as_quat(scalar_first=True))
    add(f"   double cover: -q = {minus_q} is the same rotation: {same}")
    add("")

    add("3. World vs body composition (start: yaw 90 deg; then roll 90 deg)")
    O_init = Rotation.from_rpy(0.0, 0.0, math.pi / 2)
    O_rot = Rotation.from_rpy(math.pi / 2, 0.0, 0.0)
    world = compose_world(O_rot, O_init)
    body = compose_body(O_init, O_rot)
    nose = np.array((1.0, 0.0, 0.0))
    up = np.array((0.0, 0.0, 1.0))
    add("   world frame  O_final = O_rot * O_init (roll about the fixed world x axis)")
    add(f"      q = {_q(world.as_quat(scalar_first=True))}, nose -> {_vec(world.apply(nose))},"
        f" top -> {_vec(world.apply(up))}")
    add("   body frame   O_final = O_init * O_rot (roll about the robot's own nose axis)")
    add(f"      q = {_q(body.as_quat(scalar_first=True))}, nose -> {_vec(body.apply(nose))},"
        f" top -> {_vec(body.apply(up))}")
    add(f"   same result? {bool(world.approx_equal(body))} (quaternion products do not commute)")
    add("")

    add("4. Gimbal lock (Appendix A): R = Rz(psi) Ry(theta) Rx(phi) with theta = 90 deg")
    r1 = Rotation.from_euler("ZYX", [90.0, 90.0, 30.0], degrees=True)
    r2 = Rotation.from_euler("ZYX", [120.0, 90.0, 60.0], degrees=True)
    add("   (psi, phi) = (90, 30) deg:")
    out.extend(_matrix(r1.as_matrix(), "      "))
    add("   (psi, phi) = (120, 60) deg:")
    out.extend(_matrix(r2.as_matrix(), "      "))
    diff = float(np.abs(r1.as_matrix() - r2.as_matrix()).max())
    add(f"   largest entry difference: {diff:.1e} -> identical; only psi - phi = 60 deg survives")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        back = r1.as_euler("ZYX", degrees=True)
    warned = any(issubclass(c.category, GimbalLockWarning) for c in caught)
    add(f"   as_euler('ZYX') -> (psi, theta, phi) = {_vec(back)} deg; "
        f"GimbalLockWarning raised: {warned}")
    add("   (posekit sets the third angle, phi, to 0 and folds the rotation into psi)")
    return "\n".join(out)


def main() -> None:
    """Print the walkthrough."""
    print(report())


if __name__ == "__main__":
    main()
