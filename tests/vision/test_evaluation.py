"""The evaluation helpers: look_at geometry and one accuracy-grid cell."""

from __future__ import annotations

import math

import numpy as np
import pytest

from posekit.vision.evaluation import accuracy_grid, look_at, marker_view_pose


def test_look_at_axes():
    T = look_at((1.0, 2.0, 3.0), (4.0, 2.0, 3.0))  # looking along world +x
    np.testing.assert_allclose(T[:3, 2], [1, 0, 0], atol=1e-12)  # optical z forward
    np.testing.assert_allclose(T[:3, 0], [0, -1, 0], atol=1e-12)  # image right = world -y
    np.testing.assert_allclose(T[:3, 1], [0, 0, -1], atol=1e-12)  # image down = world -z
    np.testing.assert_allclose(T[:3, 3], [1, 2, 3])
    assert np.linalg.det(T[:3, :3]) == pytest.approx(1.0)
    with pytest.raises(ValueError, match="parallel"):
        look_at((0, 0, 1), (0, 0, 0))


def test_marker_view_pose_distance_and_angle():
    T_world_box, T_wo = marker_view_pose(2.0, math.radians(40.0))
    centre = np.array([-0.25, 0.0, 0.25])
    assert np.linalg.norm(T_wo[:3, 3] - centre) == pytest.approx(2.0)
    to_cam = (T_wo[:3, 3] - centre) / 2.0
    assert math.degrees(math.acos(to_cam @ [-1.0, 0.0, 0.0])) == pytest.approx(40.0)
    np.testing.assert_allclose(T_world_box[:3, 3], [0, 0, 0.25])


def test_accuracy_cell_fields():
    (cell,) = accuracy_grid([1.0], [30.0], trials=2, jitter=0.01)
    assert cell.trials == 2
    assert cell.detection_rate == 1.0
    assert 0.0 <= cell.mean_position_error <= cell.max_position_error < 0.02
    assert cell.max_rotation_error_best_of_two_deg <= cell.max_rotation_error_deg < 3.0
    assert 0.0 <= cell.mean_ambiguity_ratio <= 1.0
