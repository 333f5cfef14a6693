"""Contact between the ROSbot and the world's solid boxes: the body stops, the wheels do not.

Gazebo resolves contacts between the robot's collision shapes and a static box with forces:
driven into a box, the ROSbot stops against it while ros2_control keeps its wheels turning
at the commanded speed (they slip), so the wheel odometry keeps integrating although the
body does not move. posekit reproduces that kinematically:

* the robot's collision shape is one box in base_link: x ±0.0985 m (the body's 0.197 m
  collision box; the wheels reach 0.053 + 0.0425 = 0.0955 m), y ±0.114 m (wheel centres at
  0.096 plus half the 0.036 m tyre width), z from 0 to 0.1417 m (the top of the lidar's
  collision box): :data:`ROBOT_HALF_EXTENTS` about :data:`ROBOT_CENTRE_Z`;
* the world's boxes with ``collision`` true are static obstacles (any orientation), and so
  are the faces of its colliding walls (every wall starts at the ground, so any face the
  robot's outline crosses in the ground plane is a contact);
* each control step, if the step's motion (an arc) would make the shapes overlap, the body
  moves only the largest fraction of that arc that keeps them apart (bisection to
  :data:`CONTACT_TOLERANCE`), i.e. it stops at the surface. The wheels are not affected.

Limits, named plainly: there is no sliding along a face (a robot driving obliquely into a
wall stops rather than scraping along it), no push-back, no tipping, and turning in place
with a corner against a face is blocked too. A robot that starts a step already overlapping
a box (spawned inside it) moves freely until it is out.
"""

from __future__ import annotations

import math

import numpy as np

from posekit.robot.kinematics import integrate_exact_arc
from posekit.worlds.obstacles import BoxObstacles, WallSegments

__all__ = [
    "CONTACT_TOLERANCE",
    "ROBOT_CENTRE_Z",
    "ROBOT_HALF_EXTENTS",
    "Contact",
    "boxes_overlap",
]

#: Half sizes (m) of the robot's collision box along base_link x, y, z.
ROBOT_HALF_EXTENTS = (0.0985, 0.114, 0.1417 / 2)
#: Height (m) of the collision box's centre above base_link (it reaches the ground).
ROBOT_CENTRE_Z = 0.1417 / 2
#: How far (m of arc, or rad) the bisection may leave the robot short of the surface.
CONTACT_TOLERANCE = 1e-7

_Mat3 = tuple[tuple[float, float, float], ...]
_Vec3 = tuple[float, float, float]


def boxes_overlap(
    centre_a: _Vec3, rot_a: _Mat3, half_a: _Vec3, centre_b: _Vec3, rot_b: _Mat3, half_b: _Vec3
) -> bool:
    """Whether two oriented boxes overlap (separating axis test).

    ``rot_*`` are row-major 3x3 rotations R_world_box, ``half_*`` half sizes (m). Boxes
    whose faces only touch (within 1e-9 m) do not overlap. 15 candidate axes: the 3 face
    normals of each box and the 9 cross products of their edges.
    """
    eps = 1e-9
    # R[i][j] = a_i . b_j; t = translation in A's frame.
    col_a = [tuple(rot_a[k][i] for k in range(3)) for i in range(3)]
    col_b = [tuple(rot_b[k][j] for k in range(3)) for j in range(3)]
    r = [[sum(col_a[i][k] * col_b[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
    # The small term keeps the cross axes of (nearly) parallel edges, whose cross product
    # vanishes, from declaring a separation (Gottschalk's robustness fix).
    abs_r = [[abs(r[i][j]) + 1e-9 for j in range(3)] for i in range(3)]
    d = [centre_b[k] - centre_a[k] for k in range(3)]
    t = [sum(d[k] * col_a[i][k] for k in range(3)) for i in range(3)]
    a, b = half_a, half_b
    for i in range(3):
        if abs(t[i]) >= a[i] + sum(b[j] * abs_r[i][j] for j in range(3)) - eps:
            return False
    for j in range(3):
        dist = abs(t[0] * r[0][j] + t[1] * r[1][j] + t[2] * r[2][j])
        if dist >= sum(a[i] * abs_r[i][j] for i in range(3)) + b[j] - eps:
            return False
    for i in range(3):
        i1, i2 = (i + 1) % 3, (i + 2) % 3
        for j in range(3):
            j1, j2 = (j + 1) % 3, (j + 2) % 3
            ra = a[i1] * abs_r[i2][j] + a[i2] * abs_r[i1][j]
            rb = b[j1] * abs_r[i][j2] + b[j2] * abs_r[i][j1]
            if abs(t[i2] * r[i1][j] - t[i1] * r[i2][j]) > ra + rb:
                return False
    return True


def _segments_hit_rectangle(
    x: float, y: float, yaw: float, starts: np.ndarray, ends: np.ndarray
) -> bool:
    """Whether any segment crosses the robot's outline at (x, y, yaw) (2-D separating axes:
    the outline's two axes and each segment's normal; touching within 1e-9 m is not)."""
    eps = 1e-9
    hx, hy = ROBOT_HALF_EXTENTS[0], ROBOT_HALF_EXTENTS[1]
    c, s = math.cos(yaw), math.sin(yaw)
    rel_a = starts - (x, y)
    rel_b = ends - (x, y)
    ax, ay = c * rel_a[:, 0] + s * rel_a[:, 1], -s * rel_a[:, 0] + c * rel_a[:, 1]
    bx, by = c * rel_b[:, 0] + s * rel_b[:, 1], -s * rel_b[:, 0] + c * rel_b[:, 1]
    apart = (np.minimum(ax, bx) >= hx - eps) | (np.maximum(ax, bx) <= -hx + eps)
    apart |= (np.minimum(ay, by) >= hy - eps) | (np.maximum(ay, by) <= -hy + eps)
    nx, ny = -(by - ay), bx - ax  # normal of each segment
    apart |= np.abs(nx * ax + ny * ay) >= hx * np.abs(nx) + hy * np.abs(ny) - eps * np.hypot(
        nx, ny
    )
    return not bool(np.all(apart))


class Contact:
    """The robot against ``obstacles`` and ``walls`` (pass only the colliding ones; see the
    module doc). ``contacts`` counts the control steps whose motion was cut short.
    """

    def __init__(self, obstacles: BoxObstacles, walls: WallSegments | None = None) -> None:
        self.obstacles = obstacles
        self.contacts = 0
        self._walls = walls if walls is not None and len(walls) else None
        if self._walls is not None:
            mid = 0.5 * (self._walls.starts + self._walls.ends)
            self._wall_mid = mid
            self._wall_reach = 0.5 * np.linalg.norm(
                self._walls.ends - self._walls.starts, axis=1
            ) + math.hypot(*ROBOT_HALF_EXTENTS[:2])
        self._boxes: list[tuple[_Vec3, _Mat3, _Vec3]] = []
        top = 2.0 * ROBOT_CENTRE_Z
        xy, radius = [], []
        for c, rot, h in zip(
            obstacles.centres, obstacles.rotations, obstacles.half_extents, strict=True
        ):
            z_reach = float(np.abs(rot[2]) @ h)  # vertical half extent of the box
            if c[2] + z_reach <= 0.0 or c[2] - z_reach >= top:
                continue  # wholly above the robot or below the ground
            self._boxes.append(
                (
                    (float(c[0]), float(c[1]), float(c[2])),
                    tuple((float(row[0]), float(row[1]), float(row[2])) for row in rot),
                    (float(h[0]), float(h[1]), float(h[2])),
                )
            )
            xy.append(c[:2])
            radius.append(float(np.linalg.norm(h)))
        self._xy = np.array(xy, dtype=np.float64).reshape(-1, 2)
        self._reach = np.array(radius, dtype=np.float64) + math.hypot(*ROBOT_HALF_EXTENTS[:2])

    def _near_walls(self, x: float, y: float, margin: float) -> np.ndarray | None:
        """Indices of wall faces within ``margin`` of the robot's bounding circle, or None."""
        if self._walls is None:
            return None
        dist = np.hypot(self._wall_mid[:, 0] - x, self._wall_mid[:, 1] - y)
        idx = np.flatnonzero(dist < self._wall_reach + margin)
        return idx if idx.size else None

    def _walls_hit(self, x: float, y: float, yaw: float, idx: np.ndarray | None) -> bool:
        if idx is None or self._walls is None:
            return False
        return _segments_hit_rectangle(x, y, yaw, self._walls.starts[idx], self._walls.ends[idx])

    def _near(self, x: float, y: float, margin: float) -> list[int]:
        """Boxes whose bounding circle comes within ``margin`` of the robot's at (x, y)."""
        if not self._boxes:
            return []
        if len(self._boxes) <= 16:
            out = []
            for k, ((cx, cy, _), reach) in enumerate(
                zip((b[0] for b in self._boxes), self._reach, strict=True)
            ):
                if math.hypot(cx - x, cy - y) < reach + margin:
                    out.append(k)
            return out
        dist = np.hypot(self._xy[:, 0] - x, self._xy[:, 1] - y)
        return [int(k) for k in np.flatnonzero(dist < self._reach + margin)]

    def collides(
        self,
        x: float,
        y: float,
        yaw: float,
        candidates: list[int] | None = None,
        wall_candidates: np.ndarray | None = None,
    ) -> bool:
        """Whether the robot at ``(x, y, yaw)`` overlaps a box or crosses a wall face."""
        if candidates is None:
            candidates = self._near(x, y, 0.0)
            wall_candidates = self._near_walls(x, y, 0.0)
        if self._walls_hit(x, y, yaw, wall_candidates):
            return True
        if not candidates:
            return False
        c, s = math.cos(yaw), math.sin(yaw)
        rot = ((c, -s, 0.0), (s, c, 0.0), (0.0, 0.0, 1.0))
        centre = (x, y, ROBOT_CENTRE_Z)
        return any(
            boxes_overlap(centre, rot, ROBOT_HALF_EXTENTS, *self._boxes[k]) for k in candidates
        )

    def free_fraction(self, x: float, y: float, yaw: float, ds: float, dyaw: float) -> float:
        """The largest fraction in [0, 1] of the arc ``(ds m, dyaw rad)`` from ``(x, y, yaw)``
        that keeps the robot out of every box (1.0 when nothing is in the way)."""
        candidates = self._near(x, y, abs(ds) + 1e-6)
        walls = self._near_walls(x, y, abs(ds) + 1e-6)
        if not candidates and walls is None:
            return 1.0
        if not self.collides(*integrate_exact_arc(x, y, yaw, ds, dyaw), candidates, walls):
            return 1.0
        if self.collides(x, y, yaw, candidates, walls):
            return 1.0  # already overlapping (spawned there): let it leave
        lo, hi = 0.0, 1.0
        span = max(abs(ds), abs(dyaw))
        while (hi - lo) * span > CONTACT_TOLERANCE:
            mid = 0.5 * (lo + hi)
            pose = integrate_exact_arc(x, y, yaw, mid * ds, mid * dyaw)
            if self.collides(*pose, candidates, walls):
                hi = mid
            else:
                lo = mid
        self.contacts += 1
        return lo
