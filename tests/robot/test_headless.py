"""The headless closed loop: idle, custom streams that stop, bad arguments."""

from __future__ import annotations

import numpy as np
import pytest

from posekit.robot.headless import run_headless


def test_idle_robot_stays_put() -> None:
    res = run_headless(scenario="idle", duration=5.0, seed=1)
    assert np.all(res.truth == 0.0)
    assert np.all(res.wheels == 0.0)
    assert len(res.t) == 101  # 20 Hz including t = 0


def test_stream_that_stops_halts_robot() -> None:
    """Commands at 100 Hz until t = 3 s, then nothing: the robot stops by 3 + 0.5 + 0.5 s."""

    def source(t: float) -> tuple[float, float] | None:
        return (0.5, 0.2) if t < 3.0 else None

    res = run_headless(scenario="custom", command_source=source, duration=8.0, seed=2)
    moving = np.hypot(np.diff(res.truth[:, 0]), np.diff(res.truth[:, 1])) > 1e-12
    t_mid = res.t[1:]
    assert moving[(t_mid > 1.0) & (t_mid < 3.4)].all()
    assert not moving[t_mid > 4.05].any()


def test_unknown_scenario_and_missing_source() -> None:
    with pytest.raises(ValueError, match="unknown scenario"):
        run_headless(scenario="fly", duration=1.0)
    with pytest.raises(ValueError, match="command_source"):
        run_headless(scenario="custom", duration=1.0)
