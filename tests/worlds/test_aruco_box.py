"""aruco_box model: face table consistency and the marker poses docs/specs/rosbot_and_worlds.md
lists for the worlds."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRotation

from posekit.geometry import Transform
from posekit.worlds import (
    ARUCO_BOX,
    ArucoBoxModel,
    BoxFace,
    WorldError,
    marker_corners_local,
)


def _quat_close(q, ref, atol):
    q, ref = np.asarray(q), np.asarray(ref)
    return min(np.abs(q - ref).max(), np.abs(q + ref).max()) <= atol


def test_face_table_ids_and_axes():
    assert ARUCO_BOX.size == 0.5
    assert ARUCO_BOX.marker_size == 0.2
    assert ARUCO_BOX.dictionary == "DICT_5X5_250"
    ids = {tuple(f.normal): f.marker_id for f in ARUCO_BOX.faces}
    assert ids == {(0, 0, 1): 3, (0, -1, 0): 2, (-1, 0, 0): 4, (0, 0, -1): 1, (1, 0, 0): 6,
                   (0, 1, 0): 5}
    for face in ARUCO_BOX.faces:
        T = ARUCO_BOX.T_box_marker(face)
        R = T[:3, :3]
        np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-12)
        assert np.linalg.det(R) == pytest.approx(1.0)  # no mirrored face
        np.testing.assert_allclose(T[:3, 3], 0.25 * np.asarray(face.normal))


def test_corner_order_is_ippe_square():
    np.testing.assert_allclose(
        marker_corners_local(0.2),
        [[-0.1, 0.1, 0], [0.1, 0.1, 0], [0.1, -0.1, 0], [-0.1, -0.1, 0]],
    )


def test_aruco_box_world_markers_match_spec():
    # docs/specs/rosbot_and_worlds.md, aruco_box_worlds.sdf: id 4 at (2.000, 0, 0.25), id 2 at
    # (2.000, -0.5002, 0.25),
    # id 5 at (2.000, 0.5002, 0.25), orientations ~ quat (0, -0.7071, 0, 0.7071) +- 3e-4
    boxes = [Transform.from_xyz_rpy((2.25, 0.0, 0.25), (0.0, 0.0, 0.0)).as_matrix(),
             Transform.from_xyz_rpy((2.25, -0.5, 0.25), (0.0, 0.0, -1.57)).as_matrix(),
             Transform.from_xyz_rpy((2.25, 0.5, 0.25), (0.0, 0.0, 1.57)).as_matrix()]
    truth = {(g.box_index, g.marker_id): g for g in ARUCO_BOX.ground_truth(boxes)}
    expected = {(0, 4): (2.0, 0.0, 0.25), (1, 2): (2.0, -0.5002, 0.25), (2, 5): (2.0, 0.5002, 0.25)}
    for key, pos in expected.items():
        g = truth[key]
        np.testing.assert_allclose(g.T_world_marker[:3, 3], pos, atol=1e-4)
        q = SciRotation.from_matrix(g.T_world_marker[:3, :3]).as_quat()
        assert _quat_close(q, [0, -math.sqrt(0.5), 0, math.sqrt(0.5)], 4e-4)
        # corners lie at +-0.1 m from the centre in the marker plane
        np.testing.assert_allclose(g.corners_world.mean(axis=0), pos, atol=1e-4)
        np.testing.assert_allclose(np.linalg.norm(g.corners_world[0] - g.corners_world[1]), 0.2)
    # the outer side faces are the boxes' local +x faces, id 6, at y = -+0.75
    assert truth[(1, 6)].T_world_marker[1, 3] == pytest.approx(-0.75, abs=1e-3)
    assert truth[(2, 6)].T_world_marker[1, 3] == pytest.approx(0.75, abs=1e-3)


def test_overhead_world_top_marker_matches_spec():
    # box_1 at (2, 2, 0.25): top marker id 3, centre (2, 2, 0.5), quat (0, 0, 1, 0)
    T_world_box = Transform.from_xyz_rpy((2.0, 2.0, 0.25), (0.0, 0.0, 0.0)).as_matrix()
    g = next(g for g in ARUCO_BOX.ground_truth([T_world_box]) if g.marker_id == 3)
    np.testing.assert_allclose(g.T_world_marker[:3, 3], [2.0, 2.0, 0.5], atol=1e-12)
    q = SciRotation.from_matrix(g.T_world_marker[:3, :3]).as_quat()
    assert _quat_close(q, [0, 0, 1, 0], 1e-12)
    np.testing.assert_allclose(g.face_normal_world, [0, 0, 1], atol=1e-12)


def test_face_by_id_and_errors():
    assert ARUCO_BOX.face_by_id(5).normal == (0.0, 1.0, 0.0)
    with pytest.raises(KeyError):
        ARUCO_BOX.face_by_id(7)
    with pytest.raises(WorldError, match="marker_size"):
        ArucoBoxModel(size=0.5, marker_size=0.6)
    bad = (BoxFace((0.0, 0.0, 1.0), 3, (1.0, 0.0, 0.0), (0.0, -1.0, 0.0)),)  # mirrored
    with pytest.raises(WorldError, match="normal"):
        ArucoBoxModel(faces=bad)
