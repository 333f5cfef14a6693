"""Slerp through key rotations against scipy's ``Slerp`` (the oracle), and its errors."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRot
from scipy.spatial.transform import Slerp as SciSlerp

from posekit.geometry import Rotation, ShapeError, Slerp


def _close(ours: Rotation, ref: SciRot) -> bool:
    a, b = np.atleast_2d(ours.as_quat()), np.atleast_2d(ref.as_quat())
    return bool(np.minimum(np.abs(a - b).max(axis=1), np.abs(a + b).max(axis=1)).max() < 1e-10)


def test_matches_scipy_on_random_keys_and_times():
    rng = np.random.default_rng(11)
    for keys in (2, 3, 17):
        quats = SciRot.random(keys, rng=rng).as_quat()
        times = np.cumsum(rng.uniform(0.1, 2.0, keys))
        ours = Slerp(times, Rotation.from_quat(quats))
        ref = SciSlerp(times, SciRot.from_quat(quats))
        query = np.concatenate([rng.uniform(times[0], times[-1], 500), times])
        assert _close(ours(query), ref(query))
        for t in (times[0], times[-1], (times[0] + times[1]) / 2):
            single = ours(t)
            assert single.single == ref(t).single
            assert _close(single, ref(t))


def test_a_quarter_turn_at_constant_speed():
    slerp = Slerp([0.0, 2.0], Rotation.from_euler("z", [[0], [90]], degrees=True))
    yaw = slerp(np.linspace(0.0, 2.0, 5)).as_euler("xyz", degrees=True)[:, 2]
    assert np.allclose(yaw, [0.0, 22.5, 45.0, 67.5, 90.0])


def test_errors_name_the_problem():
    keys = Rotation.from_euler("z", [[0], [90], [180]], degrees=True)
    slerp = Slerp([0.0, 1.0, 2.0], keys)
    with pytest.raises(ValueError, match="within"):
        slerp(2.5)
    with pytest.raises(ValueError, match="increasing"):
        Slerp([0.0, 0.0, 1.0], keys)
    with pytest.raises(ShapeError, match="at least 2"):
        Slerp([0.0], keys[:1])
    with pytest.raises(ShapeError, match="2 times for 3"):
        Slerp([0.0, 1.0], keys)
    with pytest.raises(ValueError, match="finite"):
        Slerp([0.0, np.nan, 2.0], keys)
