"""The robot's static frames, checked against docs/specs/rosbot_and_worlds.md's composite numbers
with scipy."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from posekit.robot.description import static_transforms, wheel_transforms


def _matrix(tf) -> np.ndarray:  # type: ignore[no-untyped-def]
    q = tf.transform.rotation
    t = tf.transform.translation
    m = np.eye(4)
    m[:3, :3] = Rotation.from_quat([q.x, q.y, q.z, q.w]).as_matrix()
    m[:3, 3] = (t.x, t.y, t.z)
    return m


def _chain_to_base(frame: str) -> np.ndarray:
    by_child = {tf.child_frame_id: tf for tf in static_transforms()}
    T = np.eye(4)
    while frame != "base_link":
        tf = by_child[frame]
        T = _matrix(tf) @ T
        frame = tf.header.frame_id
    return T


def test_tree_rooted_at_base_link() -> None:
    tfs = static_transforms()
    children = [tf.child_frame_id for tf in tfs]
    assert len(children) == len(set(children))
    for needed in (
        "body_link",
        "imu_link",
        "camera_mount_link",
        "oak_link",
        "oak_rgb_camera_frame",
        "oak_rgb_camera_optical_frame",
        "cover_link",
    ):
        assert needed in children
        _chain_to_base(needed)  # reaches base_link without a KeyError


def test_camera_composite_matches_spec() -> None:
    T = _chain_to_base("oak_rgb_camera_frame")
    assert T[:3, 3] == pytest.approx((-0.0241, 0.0, 0.1875), abs=1e-12)
    assert np.allclose(T[:3, :3], np.eye(3))
    T_opt = _chain_to_base("oak_rgb_camera_optical_frame")
    R_ref = (
        Rotation.from_euler("z", -math.pi / 2).as_matrix()
        @ Rotation.from_euler("x", -math.pi / 2).as_matrix()
    )
    assert np.allclose(T_opt[:3, :3], R_ref, atol=1e-12)
    # Optical convention: z forward (= base x), x right (= -base y), y down (= -base z).
    assert np.allclose(T_opt[:3, 2], (1, 0, 0), atol=1e-12)
    assert np.allclose(T_opt[:3, 0], (0, -1, 0), atol=1e-12)
    assert np.allclose(T_opt[:3, 1], (0, 0, -1), atol=1e-12)


def test_imu_and_body_offsets() -> None:
    assert _chain_to_base("body_link")[:3, 3] == pytest.approx((0, 0, 0.0425))
    assert _chain_to_base("imu_link")[:3, 3] == pytest.approx((0.003, -0.0495, 0.0425 + 0.04332))


def test_wheels_rotate_about_y() -> None:
    tfs = wheel_transforms((0.5, 0.0, 0.0, 0.0), t=1.0)
    assert [tf.child_frame_id for tf in tfs] == [
        "fl_wheel_link",
        "fr_wheel_link",
        "rl_wheel_link",
        "rr_wheel_link",
    ]
    m = _matrix(tfs[0])
    assert np.allclose(m[:3, :3], Rotation.from_euler("y", 0.5).as_matrix())
    assert m[:3, 3] == pytest.approx((0.053, 0.096, 0.0))
    assert tfs[0].header.frame_id == "body_link"
    assert tfs[0].header.stamp.sec == 1
