"""Random mover: ranges, seeding, throttled log; EKF beats wheel odometry on a 120 s run."""

from __future__ import annotations

import math

import numpy as np
import pytest

from posekit.robot.headless import run_headless
from posekit.robot.random_mover import RandomMover, RandomMoverParams


def test_commands_uniform_in_course_ranges() -> None:
    mover = RandomMover(RandomMoverParams(seed=11))
    cmds = np.array([mover.next_command() for _ in range(4000)])
    assert np.all(np.abs(cmds[:, 0]) <= 0.5)
    assert np.all(np.abs(cmds[:, 1]) <= 1.0)
    # Uniform on [-a, a]: mean 0, std a / sqrt(3).
    assert cmds[:, 0].std() == pytest.approx(0.5 / math.sqrt(3), rel=0.05)
    assert cmds[:, 1].std() == pytest.approx(1.0 / math.sqrt(3), rel=0.05)
    assert abs(cmds[:, 0].mean()) < 0.03
    assert mover.period == 0.5


def test_seeded() -> None:
    a = [RandomMover(RandomMoverParams(seed=2)).next_command() for _ in range(3)]
    b = [RandomMover(RandomMoverParams(seed=2)).next_command() for _ in range(3)]
    assert a == b
    assert RandomMover(RandomMoverParams(seed=3)).next_command() != a[0]


def test_log_throttled_to_one_hz() -> None:
    mover = RandomMover()
    lines = [mover.pose_log(0.05 * k, 1.0, 2.0, 0.5) for k in range(41)]  # 2 s at 20 Hz
    logged = [line for line in lines if line is not None]
    assert len(logged) == 3  # t = 0, 1, 2
    assert logged[0] == "Odom: x=1.00, y=2.00, yaw=0.50"


def test_bad_rate() -> None:
    with pytest.raises(ValueError, match="publish_rate"):
        RandomMover(RandomMoverParams(publish_rate=0.0))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_filtered_beats_wheel_odometry_over_120s(seed: int) -> None:
    res = run_headless(scenario="random_mover", duration=120.0, seed=seed)
    assert res.t[-1] == pytest.approx(120.0)
    errs = res.final_errors()
    (w_pos, w_yaw), (f_pos, f_yaw) = errs["wheels"], errs["filtered"]
    print(
        f"seed {seed}: wheels pos {w_pos:.3f} m yaw {w_yaw:.4f} rad; "
        f"filtered pos {f_pos:.3f} m yaw {f_yaw:.4f} rad"
    )
    assert f_yaw < w_yaw
    assert f_pos < w_pos
    # The robot did move (not a trivially small run).
    assert np.max(np.hypot(res.truth[:, 0], res.truth[:, 1])) > 0.3
