"""Long runs keep bounded structures: no odometry series unless asked, a ring of log records.

Oracle: the run's own node list and the lengths of what it keeps, compared with what a run
of that length produces when everything is kept.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from posekit.launch.scenarios import ScenarioError
from posekit.robot.nodes import OdometryRecorder
from posekit.robot.scenarios import run_robot_scenario


def test_headless_run_without_record_keeps_no_series_and_a_bounded_log() -> None:
    full = run_robot_scenario("p_controller", until_sim_time=30.0, record=False)
    assert len(full.logs) >= 2  # the run logs (position reached, goal reached)
    kept = run_robot_scenario("p_controller", until_sim_time=30.0, record=False, max_log_records=1)
    assert [r.message for r in kept.logs] == [r.message for r in full.logs][-1:]
    assert kept.run is not None
    assert not any(isinstance(n, OdometryRecorder) for n in kept.run.nodes)
    assert kept.recording is None
    assert kept.goal_reached_time is not None  # still known, from the controller
    assert kept.goal_reached_time == full.goal_reached_time


def test_recorded_goal_time_matches_the_controller() -> None:
    recorded = run_robot_scenario("p_controller", until_sim_time=30.0, record=True)
    plain = run_robot_scenario("p_controller", until_sim_time=30.0, record=False)
    assert recorded.goal_reached_time == pytest.approx(plain.goal_reached_time, abs=1e-9)


def test_bad_log_bound() -> None:
    with pytest.raises(ScenarioError, match="max_log_records"):
        run_robot_scenario("p_controller", until_sim_time=1.0, max_log_records=-1)


@pytest.mark.parametrize(("extra", "recorded"), [([], False), (["--plot", "PLOT"], True)])
def test_launch_records_odometry_only_for_a_plot(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path, extra: list[str], recorded: bool
) -> None:
    import posekit.robot.scenarios as robot_scenarios
    from posekit.cli import launch_cmd

    seen: list[dict[str, Any]] = []

    def spy(*args: Any, **kwargs: Any) -> Any:
        seen.append(kwargs)
        result = run_robot_scenario(*args, **kwargs)
        seen.append({"nodes": [type(n) for n in result.run.nodes]})  # type: ignore[union-attr]
        return result

    monkeypatch.setattr(robot_scenarios, "run_robot_scenario", spy)
    argv = ["p_controller", "--until-sim-time", "2",
            *[str(tmp_path / "odom.png") if a == "PLOT" else a for a in extra]]
    assert launch_cmd.main(argv) == 0
    assert seen[0]["record"] is recorded
    assert (OdometryRecorder in seen[1]["nodes"]) is recorded
