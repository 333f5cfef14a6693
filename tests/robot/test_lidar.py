"""The simulated LiDAR and the ray caster under it.

Oracles: closed-form distances from the scan origin to known axis-aligned box faces; an
independent ray-box intersection (the slab method, scalar Python per ray and box, box
orientation from scipy) for randomly posed boxes; Husarion's description values for the
beam geometry; REP 117 for out-of-range returns; the noise's sample statistics.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as ScipyRotation

from posekit.geometry import Rotation, Transform
from posekit.robot.description import T_base_frame
from posekit.robot.lidar import DEFAULT_LIDAR, Lidar, LidarParams
from posekit.worlds import World, load_world
from posekit.worlds.obstacles import BoxObstacles, cast_rays

NOISELESS = LidarParams(noise_stddev=0.0)
HALF = 0.25  # the aruco_box is a 0.5 m cube


def _world(*poses: tuple[float, ...]) -> World:
    return World.from_dict(
        {
            "name": "t",
            "boxes": [
                {"name": f"b{i}", "model": "aruco_box", "pose": list(p)}
                for i, p in enumerate(poses)
            ],
        }
    )


def _T_world_laser(x: float, y: float, yaw: float) -> Transform:
    return Transform(Rotation.from_rpy(0.0, 0.0, yaw), (x, y, 0.0)) * T_base_frame("laser")


def _slab(origin: np.ndarray, d: np.ndarray, centre, quat_xyzw, half) -> float:
    """Reference: entry distance of one ray into one oriented box, inf if none."""
    rot = ScipyRotation.from_quat(quat_xyzw).as_matrix()
    o = rot.T @ (origin - np.asarray(centre))
    v = rot.T @ d
    t_lo, t_hi = -math.inf, math.inf
    for axis in range(3):
        if abs(v[axis]) < 1e-15:
            if abs(o[axis]) > half[axis]:
                return math.inf
            continue
        a = (-half[axis] - o[axis]) / v[axis]
        b = (half[axis] - o[axis]) / v[axis]
        t_lo = max(t_lo, min(a, b))
        t_hi = min(t_hi, max(a, b))
    return t_lo if t_lo <= t_hi and t_lo > 0 else math.inf


def test_beam_geometry_matches_the_s2_description() -> None:
    p = DEFAULT_LIDAR
    assert (p.frame_id, p.rate_hz, p.samples) == ("laser", 10.0, 3000)
    assert (p.range_min, p.range_max, p.noise_stddev) == (0.05, 30.0, 0.015)
    # Gazebo spaces samples (max - min) / (samples - 1): 0.120 deg, the S2 datasheet's value.
    assert math.degrees(p.angle_increment) == pytest.approx(0.12004, abs=1e-5)
    assert p.angles[0] == -math.pi
    assert p.angles[-1] == pytest.approx(math.pi, abs=1e-12)
    # laser frame: cover_link + (0.02, 0, 0) + (0, 0, 0.0285), turned by pi about z.
    T = T_base_frame("laser").as_matrix()
    np.testing.assert_allclose(T[:3, 3], (0.02, 0.0, 0.0425 + 0.0603 + 0.0285), atol=1e-12)
    np.testing.assert_allclose(T[:3, :3], np.diag([-1.0, -1.0, 1.0]), atol=1e-12)


def test_ranges_equal_closed_form_distances_to_box_faces() -> None:
    # Boxes straight ahead (face at x = 2.0) and to the left (face at y = 1.75) of a robot at
    # the origin with yaw 0.
    world = _world((2.25, 0.0, 0.25, 0, 0, 0), (0.0, 2.0, 0.25, 0, 0, 0))
    lidar = Lidar(BoxObstacles.from_world(world), NOISELESS)
    ranges = lidar.scan(_T_world_laser(0.0, 0.0, 0.0), 0).astype(np.float64)
    # Beam angle a in the laser frame looks along base angle a + pi.
    base_angles = np.remainder(lidar.params.angles + math.pi + math.pi, 2 * math.pi) - math.pi
    laser_x = 0.02
    ahead = np.abs(np.tan(base_angles)) * (2.0 - laser_x) < HALF - 1e-6
    ahead &= np.cos(base_angles) > 0
    expected = (2.0 - laser_x) / np.cos(base_angles[ahead])
    np.testing.assert_allclose(ranges[ahead], expected, rtol=2e-7)
    assert ahead.sum() > 40
    # To the left: base angle pi/2 is laser angle -pi/2; the face is y = 1.75.
    left = np.abs(np.abs(base_angles - math.pi / 2)) < 0.1
    dy = 1.75
    ok = np.abs(laser_x + dy / np.tan(base_angles[left])) < HALF - 1e-6
    np.testing.assert_allclose(
        ranges[left][ok], dy / np.sin(base_angles[left][ok]), rtol=2e-7
    )
    # Everything else sees nothing: +inf (REP 117), never a finite max-range value.
    seen = ahead.copy()
    seen[np.flatnonzero(left)[ok]] = True
    miss = ~np.isfinite(ranges)
    assert np.all(ranges[miss] == np.inf)
    assert np.all(np.isfinite(ranges[seen]))


def test_rotated_boxes_against_an_independent_slab_implementation() -> None:
    rng = np.random.default_rng(3)
    poses = []
    for _ in range(6):
        x, y = rng.uniform(-4, 4, size=2)
        if math.hypot(x, y) < 1.0:
            x += 2.0
        roll, pitch = rng.uniform(-0.3, 0.3, size=2)
        poses.append((x, y, 0.2, roll, pitch, rng.uniform(-math.pi, math.pi)))
    world = _world(*poses)
    obstacles = BoxObstacles.from_world(world)
    lidar = Lidar(obstacles, NOISELESS)
    for x, y, yaw in ((0.0, 0.0, 0.0), (0.3, -0.4, 2.0), (-0.5, 0.2, -1.2)):
        T = _T_world_laser(x, y, yaw)
        got = lidar.true_ranges(T)
        m = T.as_matrix()
        origin = m[:3, 3]
        directions = lidar.directions_laser @ m[:3, :3].T
        quats = [ScipyRotation.from_euler("xyz", p[3:]).as_quat() for p in poses]
        beams = range(0, lidar.params.samples, 7)
        ref = np.array(
            [
                min(_slab(origin, directions[i], p[:3], q, (HALF,) * 3)
                    for p, q in zip(poses, quats, strict=True))
                for i in beams
            ]
        )
        np.testing.assert_allclose(got[list(beams)], ref, rtol=1e-9)
        assert np.isfinite(ref).sum() > 50  # the boxes are in view


def test_culling_and_chunking_give_the_same_answer_as_one_pass() -> None:
    # 400 boxes on a grid: the caster works in chunks; a max_range cull must not change hits
    # nearer than max_range.
    poses = [(gx * 1.5, gy * 1.5, 0.25, 0, 0, 0.3 * gx) for gx in range(-10, 10)
             for gy in range(-10, 10) if (gx, gy) != (0, 0)]
    obstacles = BoxObstacles.from_world(_world(*poses))
    a = np.linspace(-math.pi, math.pi, 720)
    d = np.stack([np.cos(a), np.sin(a), np.zeros_like(a)], axis=1)
    full = cast_rays((0.1, 0.2, 0.2), d, obstacles)
    culled = cast_rays((0.1, 0.2, 0.2), d, obstacles, max_range=3.0)
    near = full <= 3.0
    np.testing.assert_array_equal(full[near], culled[near])
    assert np.all(np.isinf(culled[~near]) | (culled[~near] == full[~near]))


def test_out_of_range_returns_follow_rep_117() -> None:
    # Laser 3 cm from a box face: those beams are below range_min -> -inf; a far box beyond
    # range_max -> +inf; an empty world -> all +inf.
    world = _world((0.28, 0.0, 0.25, 0, 0, 0), (-40.0, 0.0, 0.25, 0, 0, 0))
    lidar = Lidar(BoxObstacles.from_world(world), NOISELESS)
    T = Transform(Rotation.identity(), (0.0, 0.0, 0.13))
    r = lidar.scan(T, 0)
    forward = np.abs(lidar.params.angles) < 0.1
    assert np.all(r[forward] == -np.inf)
    backward = np.abs(np.abs(lidar.params.angles) - math.pi) < 0.005
    assert np.all(r[backward] == np.inf)  # the box 40 m away is beyond 30 m
    empty = Lidar(BoxObstacles.from_world(load_world("empty_world")), DEFAULT_LIDAR)
    assert np.all(empty.scan(T, 5) == np.inf)


def test_noise_is_deterministic_per_seed_and_scan_and_has_the_datasheet_sigma() -> None:
    world = _world((2.25, 0.0, 0.25, 0, 0, 0), (-2.25, 0.0, 0.25, 0, 0, 0.5),
                   (0.0, 2.25, 0.25, 0, 0, 0), (0.0, -2.25, 0.25, 0, 0, 1.0))
    obstacles = BoxObstacles.from_world(world)
    T = _T_world_laser(0.1, 0.0, 0.3)
    a = Lidar(obstacles, seed=11)
    truth = a.true_ranges(T)
    s1 = a.scan(T, 4)
    assert s1.dtype == np.float32
    np.testing.assert_array_equal(s1, Lidar(obstacles, seed=11).scan(T, 4))
    assert not np.array_equal(s1, a.scan(T, 5))
    assert not np.array_equal(s1, Lidar(obstacles, seed=12).scan(T, 4))
    hit = np.isfinite(truth)
    assert np.array_equal(hit, np.isfinite(s1))
    err = np.concatenate([a.scan(T, k)[hit] - truth[hit] for k in range(10)])
    assert err.size > 3000
    assert abs(err.mean()) < 4 * 0.015 / math.sqrt(err.size)
    assert err.std() == pytest.approx(0.015, rel=0.05)


def test_laser_scan_message_fields() -> None:
    lidar = Lidar(BoxObstacles.from_world(load_world("aruco_box_world")))
    msg = lidar.to_msg(lidar.scan(_T_world_laser(0, 0, 0), 0))
    assert msg.header.frame_id == "laser"
    assert msg.ranges.shape == msg.intensities.shape == (3000,)
    assert msg.angle_min + 2999 * msg.angle_increment == pytest.approx(msg.angle_max)
    assert (msg.scan_time, msg.time_increment) == (0.1, 0.0)
    assert (msg.range_min, msg.range_max) == (0.05, 30.0)


def test_bad_parameters_are_named_errors() -> None:
    with pytest.raises(ValueError, match="samples"):
        LidarParams(samples=1)
    with pytest.raises(ValueError, match="range_min"):
        LidarParams(range_min=5.0, range_max=1.0)


def _room(half: float = 5.0, height: float = 1.0, **extra) -> World:
    square = [[-half, -half], [half, -half], [half, half], [-half, half]]
    return World.from_dict(
        {"name": "room", "walls": [{"name": "room", "height": height, "loops": [square]}],
         **extra}
    )


def test_walls_closed_form_distances_in_a_square_room() -> None:
    from posekit.worlds.obstacles import WallSegments

    world = _room()
    lidar = Lidar(BoxObstacles.from_world(world), NOISELESS, walls=WallSegments.from_world(world))
    x0, y0, yaw = 1.0, -2.0, 0.7
    T = _T_world_laser(x0, y0, yaw)
    ranges = lidar.scan(T, 0).astype(np.float64)
    ox, oy = T.as_matrix()[:2, 3]
    heading = lidar.params.angles + math.pi + yaw  # beam direction in the world
    c, s = np.cos(heading), np.sin(heading)
    with np.errstate(divide="ignore"):
        tx = np.where(c > 0, (5.0 - ox) / c, (-5.0 - ox) / c)
        ty = np.where(s > 0, (5.0 - oy) / s, (-5.0 - oy) / s)
    np.testing.assert_allclose(ranges, np.minimum(tx, ty), rtol=1e-6)


def test_walls_lower_than_the_scan_plane_are_not_seen() -> None:
    from posekit.worlds.obstacles import WallSegments

    world = _room(height=0.1)  # the laser is 0.1313 m above the ground
    lidar = Lidar(BoxObstacles.from_world(world), NOISELESS, walls=WallSegments.from_world(world))
    assert np.all(lidar.scan(_T_world_laser(0, 0, 0), 0) == np.inf)


def test_husarion_world_is_scanned_from_its_spawn() -> None:
    from posekit.worlds.obstacles import WallSegments

    world = load_world("husarion_world")
    lidar = Lidar(BoxObstacles.from_world(world), NOISELESS, walls=WallSegments.from_world(world))
    x, y, yaw = world.spawn
    r = lidar.scan(_T_world_laser(x, y, yaw), 0)
    # Inside the outer ring every beam hits something, and nothing is within the robot.
    assert np.all(np.isfinite(r))
    assert r.min() > 0.3
    # Straight ahead (+x): the nearest crossing of the line y = spawn y by any wall face
    # ahead of the laser, found with plain Python over the world's loops.
    ox = x + 0.02
    crossings = []
    for wall in world.walls:
        for loop in wall.loops:
            for (ax, ay), (bx, by) in zip(loop, loop[1:] + loop[:1], strict=True):
                if (ay - y) * (by - y) < 0:
                    cx = ax + (y - ay) * (bx - ax) / (by - ay)
                    if cx > ox:
                        crossings.append(cx - ox)
    forward = int(np.argmin(np.abs(np.abs(lidar.params.angles) - math.pi)))
    assert r[forward] == pytest.approx(min(crossings), abs=1e-5)
    assert 5.0 < r[forward] < 7.0  # the nearest feather
