"""Worlds: docs/specs/rosbot_and_worlds.md's marker positions and camera intrinsics, validation
errors, files."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from posekit.worlds import (
    ARUCO_BOX,
    BoxSpec,
    WorldError,
    load_world,
    marker_poses,
    world_names,
)


def test_builtin_names_and_alias() -> None:
    names = world_names()
    for n in ("empty_world", "aruco_box_world", "aruco_box_camera_world", "aruco_markers_world"):
        assert n in names
    assert load_world("aruco_markers_world") is load_world("aruco_box_world")
    assert load_world("empty_world").boxes == ()


def test_aruco_box_world_faces_seen_from_origin_match_spec() -> None:
    world = load_world("aruco_box_world")
    got = {(m.box, m.marker_id): m.T_world_marker for m in marker_poses(world)}
    expected = {
        ("box_1", 4): (2.000, 0.000, 0.250),
        ("box_2", 2): (2.000, -0.5002, 0.250),
        ("box_3", 5): (2.000, 0.5002, 0.250),
    }
    q_ref = np.array([0.0, -0.7071, 0.0, 0.7071])
    for key, pos in expected.items():
        T = got[key]
        assert T[:3, 3] == pytest.approx(pos, abs=1e-4)
        q = Rotation.from_matrix(T[:3, :3]).as_quat()
        q = q if q[3] > 0 else -q
        assert np.allclose(q, q_ref, atol=4e-4)
        # The marker faces the robot at the origin: its z axis points towards -x.
        assert T[0, 2] == pytest.approx(-1.0, abs=1e-6)


def test_marker_axes_are_right_handed_and_outward() -> None:
    for face in ARUCO_BOX.faces:
        normal = face.normal
        T = ARUCO_BOX.T_box_marker(face.marker_id)
        assert np.array_equal(T, ARUCO_BOX.T_box_marker(face))  # by id or by face: one pose
        assert np.linalg.det(T[:3, :3]) == pytest.approx(1.0)
        assert np.allclose(T[:3, 2], normal)
        assert np.allclose(T[:3, 3], 0.25 * np.asarray(normal))


def test_camera_world() -> None:
    world = load_world("aruco_box_camera_world")
    (box,) = world.boxes
    assert (box.name, box.model) == ("box_1", "aruco_box")
    top = next(m for m in marker_poses(world) if m.marker_id == 3)
    assert top.T_world_marker[:3, 3] == pytest.approx((2.0, 2.0, 0.5))
    q = Rotation.from_matrix(top.T_world_marker[:3, :3]).as_quat()
    assert np.allclose(np.abs(q), (0, 0, 1, 0), atol=1e-12)
    (cam,) = world.cameras
    assert (
        pytest.approx(np.array([[554.383, 0, 320], [0, 554.383, 240], [0, 0, 1]]), abs=1e-3)
        == cam.K
    )
    # The model's +x looks down.
    assert np.allclose(cam.T_world_camera[:3, 0], (0, 0, -1), atol=1e-4)
    # Launch static TFs: odom -> overhead_camera -> optical frame; optical z looks down too.
    tf1, tf2 = world.static_transforms
    assert (tf1.parent, tf1.child, tf2.child) == (
        "odom",
        "overhead_camera",
        "overhead_camera_optical_frame",
    )
    R = Rotation.from_quat(tf1.quaternion_xyzw) * Rotation.from_quat(tf2.quaternion_xyzw)
    assert np.allclose(R.apply([0, 0, 1]), (0, 0, -1), atol=1e-4)


def test_box_pose_against_scipy() -> None:
    rng = np.random.default_rng(0)
    for _ in range(20):
        pose = rng.uniform(-3, 3, 6)
        ref = Rotation.from_euler("xyz", pose[3:]).as_matrix()  # extrinsic x-y-z = SDF rpy
        m = BoxSpec("b", "aruco_box", tuple(pose)).T_world_box
        assert np.allclose(m[:3, :3], ref, atol=1e-12)
        assert np.allclose(m[:3, 3], pose[:3])


def _world(**changes: Any) -> dict[str, Any]:
    data = load_world("aruco_box_camera_world").to_dict()
    data.update(changes)
    return data


def _write(tmp_path: Path, data: Any, name: str = "w.json") -> Path:
    p = tmp_path / name
    p.write_text(json.dumps(data))
    return p


def test_json_round_trip(tmp_path: Path) -> None:
    for name in ("aruco_box_world", "husarion_world"):
        original = load_world(name)
        loaded = load_world(_write(tmp_path, original.to_dict()))
        assert loaded == original
        assert loaded.source.endswith("w.json")


def test_husarion_world_walls_as_derived() -> None:
    """husarion_world: 8 logo shapes 1.8 m tall (one 1.802 m), the ring as two loops that
    enclose the spawn, 505 faces (the outline edges of the mesh's top faces)."""
    world = load_world("husarion_world")
    assert [w.name for w in world.walls] == [
        "rectangle", "feather6", "feather2", "feather4", "feather3", "feather5", "feather1", "H"
    ]
    assert sum(len(w.segments()) for w in world.walls) == 505
    assert {w.height for w in world.walls} == {1.8, 1.802}
    ring = world.walls[0]
    assert len(ring.loops) == 2
    for loop in ring.loops:
        xs, ys = zip(*loop, strict=True)
        assert min(xs) < world.spawn[0] < max(xs)
        assert min(ys) < world.spawn[1] < max(ys)


def test_pose_as_mapping(tmp_path: Path) -> None:
    data = {
        "name": "mine",
        "boxes": [{"name": "b", "model": "aruco_box", "pose": {"x": 1.0, "yaw": math.pi / 2}}],
    }
    world = load_world(_write(tmp_path, data))
    assert world.boxes[0].pose == (1.0, 0.0, 0.0, 0.0, 0.0, math.pi / 2)


@pytest.mark.parametrize(
    ("data", "match"),
    [
        ({"boxes": []}, "missing required key 'name'"),
        (
            _world(boxes=[{"name": "b", "model": "aruco_box", "pose": [1, 2, 3, 4, 5]}]),
            r"boxes\[0\]\.pose: expected 6 numbers",
        ),
        (_world(boxes=[{"name": "b", "model": "crate", "pose": [0] * 6}]), "unknown model 'crate'"),
        (_world(boxez=[]), r"unknown key\(s\) \['boxez'\]"),
        (
            _world(boxes=[{"name": "overhead_camera", "model": "aruco_box", "pose": [0] * 6}]),
            "duplicate name 'overhead_camera'",
        ),
        (_world(spawn=[0, "north", 0]), r"spawn\[1\]: expected a number"),
        (
            _world(
                cameras=[
                    {"name": "c", "pose": [0] * 6, "width": 640, "height": 0, "horizontal_fov": 1.0}
                ]
            ),
            r"cameras\[0\]\.height",
        ),
        (
            _world(
                cameras=[
                    {
                        "name": "c",
                        "pose": [0] * 6,
                        "width": 64,
                        "height": 48,
                        "horizontal_fov": 1.0,
                        "clip": [5, 1],
                    }
                ]
            ),
            "near < far",
        ),
        (_world(static_transforms=[{"parent": "a", "child": "a"}]), "same frame"),
        (_world(physics_step=-1), "physics_step: must be > 0"),
        (
            _world(walls=[{"name": "w", "height": 1.0, "loops": [[[0, 0], [1, 0]]]}]),
            r"walls\[0\]\.loops\[0\]: a loop needs >= 3 points, got 2",
        ),
        (
            _world(walls=[{"name": "w", "height": 0.0, "loops": [[[0, 0], [1, 0], [0, 1]]]}]),
            r"walls\[0\]\.height: must be > 0",
        ),
        (_world(walls=[{"name": "w", "height": 1.0, "loops": []}]), "needs at least one loop"),
        (
            _world(walls=[{"name": "w", "height": 1, "loops": [[[0, 0], [1, "a"], [0, 1]]]}]),
            r"walls\[0\]\.loops\[0\]\[1\]\[1\]: expected a number",
        ),
        (
            _world(boxes=[{"name": "b", "model": "aruco_box", "pose": [0] * 6,
                           "collision": "yes"}]),
            r"boxes\[0\]\.collision: expected true or false",
        ),
        ([1, 2, 3], "expected a mapping"),
    ],
)
def test_validation_errors(tmp_path: Path, data: Any, match: str) -> None:
    with pytest.raises(WorldError, match=match):
        load_world(_write(tmp_path, data))


def test_non_finite_rejected() -> None:
    from posekit.worlds import World

    with pytest.raises(WorldError, match="finite"):
        World.from_dict(_world(spawn=[0.0, float("nan"), 0.0]))


def test_file_errors(tmp_path: Path) -> None:
    with pytest.raises(WorldError, match="unknown world 'moon'"):
        load_world("moon")
    with pytest.raises(WorldError, match="cannot read"):
        load_world(tmp_path / "missing.json")
    bad = tmp_path / "bad.json"
    bad.write_text("{name: ")
    with pytest.raises(WorldError, match="not valid JSON"):
        load_world(bad)
    with pytest.raises(WorldError, match="unsupported extension"):
        load_world(_write(tmp_path, {}, "w.txt"))


def test_yaml_file(tmp_path: Path) -> None:
    p = tmp_path / "w.yaml"
    p.write_text(
        "name: mine\nboxes:\n  - {name: b, model: aruco_box, pose: [1, 0, 0.25, 0, 0, 0]}\n"
    )
    try:
        import yaml  # noqa: F401
    except ImportError:
        with pytest.raises(WorldError, match="PyYAML is not installed"):
            load_world(p)
    else:
        assert load_world(p).boxes[0].pose[0] == 1.0


def _camera(**extra: Any) -> dict[str, Any]:
    return {"name": "c", "pose": [0] * 6, "width": 64, "height": 48, "horizontal_fov": 1.0,
            **extra}


@pytest.mark.parametrize(
    ("camera", "match"),
    [
        (_camera(width=100_000, height=100_000), r"cameras\[0\]\.width: 100000 px is over"),
        (_camera(width=8192, height=8192), r"width x height: 8192 x 8192 px is over"),
        (_camera(rate_hz=1e6), r"rate_hz: 1000000.0 Hz is over"),
    ],
)
def test_absurd_cameras_are_refused_at_validation(tmp_path: Path, camera: dict[str, Any],
                                                   match: str) -> None:
    """A 100000 x 100000 camera must fail here, not later as a MemoryError per frame.
    Oracle: the documented limits (MAX_CAMERA_SIDE, MAX_CAMERA_PIXELS, MAX_CAMERA_RATE_HZ)."""
    with pytest.raises(WorldError, match=match):
        load_world(_write(tmp_path, _world(cameras=[camera])))


def test_limits_are_inclusive(tmp_path: Path) -> None:
    from posekit.worlds import MAX_CAMERA_PIXELS, MAX_CAMERA_SIDE

    side = math.isqrt(MAX_CAMERA_PIXELS)
    assert side <= MAX_CAMERA_SIDE
    world = load_world(_write(tmp_path, _world(cameras=[_camera(width=side, height=side)])))
    assert world.cameras[0].width * world.cameras[0].height == MAX_CAMERA_PIXELS


def test_non_utf8_and_oversized_files_are_named_errors(tmp_path: Path) -> None:
    from posekit.worlds import MAX_WORLD_FILE_BYTES

    latin = tmp_path / "latin.yaml"
    latin.write_bytes(b"name: caf\xe9\n")
    with pytest.raises(WorldError, match=r"latin\.yaml' is not UTF-8 text \(byte 9"):
        load_world(latin)
    huge = tmp_path / "huge.json"
    huge.write_bytes(b" " * (MAX_WORLD_FILE_BYTES + 1))
    with pytest.raises(WorldError, match="over the limit"):
        load_world(huge)
