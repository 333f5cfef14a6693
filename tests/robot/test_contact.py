"""Contact between the ROSbot and the world's boxes.

Oracles: a linear program (scipy.optimize.linprog) deciding whether two oriented boxes share
interior points, for the separating-axis test; closed-form stopping poses (box face or
vertex minus the robot's half extent) for the driven robot; the wheel angles the commanded
speed implies (they keep turning) and wheel odometry integrated from them.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import linprog
from scipy.spatial.transform import Rotation as ScipyRotation

from posekit.robot.contact import ROBOT_HALF_EXTENTS, Contact, boxes_overlap
from posekit.robot.drive import RosbotBase
from posekit.robot.odometry import WheelOdometry
from posekit.robot.params import DEFAULT_DRIVE, SlipParams
from posekit.worlds import World
from posekit.worlds.obstacles import BoxObstacles

HX, HY, _ = ROBOT_HALF_EXTENTS


def _halfspaces(centre, rot, half):
    """Rows (n, d) with n . p <= d for the 6 faces of a box."""
    normals, offsets = [], []
    for k in range(3):
        axis = rot[:, k]
        for sign in (1.0, -1.0):
            normals.append(sign * axis)
            offsets.append(sign * axis @ centre + half[k])
    return np.array(normals), np.array(offsets)


def _lp_overlap_depth(a, b) -> float:
    """max s such that some point is s inside every face of both boxes (> 0: overlap)."""
    na, da = _halfspaces(*a)
    nb, db = _halfspaces(*b)
    n = np.vstack([na, nb])
    d = np.concatenate([da, db])
    a_ub = np.hstack([n, np.ones((12, 1))])
    res = linprog(c=[0, 0, 0, -1], A_ub=a_ub, b_ub=d, bounds=[(None, None)] * 3 + [(None, 1.0)])
    assert res.status == 0
    return float(-res.fun)


def test_separating_axis_test_agrees_with_a_linear_program() -> None:
    rng = np.random.default_rng(5)
    decided = {True: 0, False: 0}
    for _ in range(400):
        boxes = []
        for _ in range(2):
            centre = rng.uniform(-0.6, 0.6, size=3)
            rot = ScipyRotation.random(random_state=rng).as_matrix()
            half = rng.uniform(0.05, 0.4, size=3)
            boxes.append((centre, rot, half))
        depth = _lp_overlap_depth(*boxes)
        if abs(depth) < 1e-6:
            continue  # too close to touching for a fair comparison
        as_tuples = [
            (tuple(c), tuple(tuple(row) for row in r), tuple(h)) for c, r, h in boxes
        ]
        got = boxes_overlap(*as_tuples[0], *as_tuples[1])
        assert got == (depth > 0)
        decided[got] += 1
    assert decided[True] > 50
    assert decided[False] > 50


def _world(*boxes: dict) -> World:
    return World.from_dict({"name": "t", "boxes": list(boxes)})


def _box(x: float, y: float, yaw: float = 0.0, z: float = 0.25, collision: bool = True) -> dict:
    return {"name": f"b{x}_{y}_{z}", "model": "aruco_box", "pose": [x, y, z, 0, 0, yaw],
            "collision": collision}


def _drive(world: World, v: float, w: float, seconds: float, yaw0: float = 0.0):
    contact = Contact(BoxObstacles.from_world(world, collision_only=True))
    base = RosbotBase(slip=SlipParams(enabled=False), yaw=yaw0, contact=contact)
    odom = WheelOdometry()
    odom.yaw_unwrapped = yaw0
    dt = DEFAULT_DRIVE.control_period
    n = round(seconds / dt)
    for k in range(n):
        t = k * dt
        base.submit_velocity(v, w, stamp=t, now=t)
        base.step(t, dt)
        if (k + 1) % 5 == 0:
            odom.update(*base.wheel_angles, t + dt)
    return base, odom, contact


def test_driving_into_a_face_stops_at_the_face_minus_the_half_length() -> None:
    world = _world(_box(2.25, 0.0))  # face at x = 2.0
    base, odom, contact = _drive(world, 0.5, 0.0, 8.0)
    x, y, yaw = base.pose
    assert x == pytest.approx(2.0 - HX, abs=1e-6)
    assert (y, yaw) == pytest.approx((0.0, 0.0), abs=1e-12)
    assert base.body_velocity[0] == pytest.approx(0.0, abs=1e-4)
    assert contact.contacts > 100
    # The wheels kept turning at the commanded speed for the whole 8 s (minus the ramp-up
    # at 1 m/s^2), so wheel odometry believes ~3.9 m.
    r_left = DEFAULT_DRIVE.effective_left_wheel_radius
    expected_angle = (0.5 * 8.0 - 0.5 * 0.5 * 0.5) / r_left
    assert base.wheel_angles[0] == pytest.approx(expected_angle, rel=1e-3)
    assert odom.x > 3.5
    # Backing away is free.
    dt = DEFAULT_DRIVE.control_period
    for k in range(100):
        t = 8.0 + k * dt
        base.submit_velocity(-0.3, 0.0, stamp=t, now=t)
        base.step(t, dt)
    assert base.pose[0] < 2.0 - HX - 0.1


def test_driving_sideways_and_into_a_vertex() -> None:
    # Heading +y into a face at y = 2.0: stops at 2.0 - half width.
    base, _, _ = _drive(_world(_box(0.0, 2.25)), 0.5, 0.0, 8.0, yaw0=math.pi / 2)
    assert base.pose[1] == pytest.approx(2.0 - HX, abs=1e-6)
    # Heading +x into a box turned 45 deg: its vertex at x = 2.25 - 0.25 sqrt 2 meets the
    # robot's front face.
    base, _, _ = _drive(_world(_box(2.25, 0.0, yaw=math.pi / 4)), 0.5, 0.0, 8.0)
    assert base.pose[0] == pytest.approx(2.25 - 0.25 * math.sqrt(2) - HX, abs=1e-6)
    # The half width: a box whose side face is 1 mm inside the robot's swept band stops it
    # at its near face; 1 mm outside, the robot passes.
    base, _, _ = _drive(_world(_box(1.0, HY + 0.25 - 1e-3)), 0.5, 0.0, 8.0)
    assert base.pose[0] == pytest.approx(0.75 - HX, abs=1e-6)
    base, _, contact = _drive(_world(_box(1.0, HY + 0.25 + 1e-3)), 0.5, 0.0, 8.0)
    assert base.pose[0] > 3.5
    assert contact.contacts == 0


def test_boxes_that_cannot_be_hit_do_not_stop_the_robot() -> None:
    world = _world(
        _box(2.25, 0.0, collision=False),  # drawn and scanned only
        _box(1.0, 0.0, z=0.45),  # its bottom (0.2 m) is above the robot's top (0.14 m)
    )
    base, _, contact = _drive(world, 0.5, 0.0, 8.0)
    assert base.pose[0] > 3.5
    assert contact.contacts == 0


def test_turning_in_place_against_a_face_is_blocked_and_leaving_a_spawn_overlap_is_free() -> None:
    world = _world(_box(2.25, 0.0))
    base, _, _ = _drive(world, 0.5, 0.0, 6.0)
    yaw_before = base.pose[2]
    dt = DEFAULT_DRIVE.control_period
    for k in range(200):
        t = 6.0 + k * dt
        base.submit_velocity(0.0, 1.0, stamp=t, now=t)
        base.step(t, dt)
    assert base.pose[2] == pytest.approx(yaw_before, abs=1e-6)  # a corner is on the face
    # Spawned overlapping a box: free to drive out.
    contact = Contact(BoxObstacles.from_world(world, collision_only=True))
    inside = RosbotBase(slip=SlipParams(enabled=False), x=2.0, contact=contact)
    for k in range(300):
        t = k * dt
        inside.submit_velocity(-0.5, 0.0, stamp=t, now=t)
        inside.step(t, dt)
    assert inside.pose[0] < 2.0 - 0.5


def test_walls_stop_the_robot_at_their_face_even_below_the_scan_plane() -> None:
    from posekit.worlds.obstacles import WallSegments

    for height in (1.0, 0.05):
        square = [[-2.0, -2.0], [2.0, -2.0], [2.0, 2.0], [-2.0, 2.0]]
        world = World.from_dict(
            {"name": "room", "walls": [{"name": "r", "height": height, "loops": [square]}]}
        )
        contact = Contact(BoxObstacles.from_world(world), WallSegments.from_world(world))
        base = RosbotBase(slip=SlipParams(enabled=False), contact=contact)
        dt = DEFAULT_DRIVE.control_period
        for k in range(800):
            t = k * dt
            base.submit_velocity(0.5, 0.0, stamp=t, now=t)
            base.step(t, dt)
        assert base.pose[0] == pytest.approx(2.0 - HX, abs=1e-6)
        assert base.wheel_angles[0] > 70.0  # rad: the wheels kept turning


def test_husarion_world_spawn_is_free() -> None:
    from posekit.worlds import load_world
    from posekit.worlds.obstacles import WallSegments

    world = load_world("husarion_world")
    contact = Contact(BoxObstacles.from_world(world), WallSegments.from_world(world))
    assert not contact.collides(*world.spawn)
    # The H's bar has a face at y = -0.317 below x = 0 (Gazebo's default spawn (0, 0) is
    # inside the bar): a robot straddling it collides, one clear of it does not.
    assert contact.collides(0.0, -0.317 - HY + 0.01, 0.0)
    assert not contact.collides(0.0, -0.317 - HY - 0.01, 0.0)
