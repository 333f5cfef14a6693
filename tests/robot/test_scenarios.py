"""The robot's named scenarios through the node layer: the P controller reaches the course
goal, seeds reproduce every message, the EKF beats wheel odometry on the random mover, TF
lookups during a run, and the registry / parameter routing API on the robot's nodes."""

from __future__ import annotations

import math
import re
import time

import numpy as np
import pytest

from posekit.launch import LaunchDescription
from posekit.launch import Node as LaunchNode
from posekit.launch.scenarios import (
    ScenarioError,
    get_scenario,
    register_scenario,
    scenario_names,
    scenario_node,
)
from posekit.robot.nodes import PControllerNode
from posekit.robot.scenarios import DEFAULT_GOAL, robot_nodes, run_robot_scenario
from posekit.runtime.node import Node
from posekit.tf2_ros import Buffer, TransformException, TransformListener
from posekit.time import Time

GOAL_X, GOAL_Y, GOAL_YAW = DEFAULT_GOAL


def _wrap(a: float) -> float:
    return (a + math.pi) % (2 * math.pi) - math.pi


def _row_at(rows: np.ndarray, t: float) -> np.ndarray:
    """The last row stamped at or before ``t``."""
    i = int(np.searchsorted(rows[:, 0], t + 1e-9, side="right")) - 1
    return rows[i]


def test_p_controller_reaches_the_course_goal_and_stops() -> None:
    result = run_robot_scenario("p_controller", seed=0, until_sim_time=26.0)
    t_goal = result.goal_reached_time
    assert t_goal is not None
    assert 15.0 < t_goal < 26.0
    rec = result.recording
    assert rec is not None
    # The controller decided on the filtered pose it had at t_goal (published one tick before).
    x, y, yaw = _row_at(rec.series["filtered"], t_goal - 0.05)[1:4]
    assert math.hypot(GOAL_X - x, GOAL_Y - y) <= 0.10
    assert abs(_wrap(GOAL_YAW - yaw)) < 0.05
    line = next(r.message for r in result.logs if "Goal reached" in r.message)
    assert line == f"Goal reached: x={x:.2f}, y={y:.2f}, yaw={yaw:.2f}"
    # The true pose carries the position drift of the estimate (wheel slip): looser bound.
    gx, gy, gyaw = _row_at(rec.series["ground_truth"], t_goal)[1:4]
    assert math.hypot(GOAL_X - gx, GOAL_Y - gy) < 0.3
    assert abs(_wrap(GOAL_YAW - gyaw)) < 0.06
    # Zero twist from then on: the base is still half a second later and stays there.
    after = rec.series["ground_truth"][rec.series["ground_truth"][:, 0] >= t_goal + 0.5]
    assert len(after) > 10
    assert np.all(after[:, 4] == 0.0)
    assert np.all(after[:, 5] == 0.0)
    assert np.all(after[:, 1] == after[0, 1])
    assert result.rejected_commands == []


def test_same_seed_gives_identical_messages_and_another_seed_does_not() -> None:
    a = run_robot_scenario("p_controller", seed=3, until_sim_time=12.0)
    b = run_robot_scenario("p_controller", seed=3, until_sim_time=12.0)
    c = run_robot_scenario("p_controller", seed=4, until_sim_time=12.0)
    assert a.recording is not None
    assert b.recording is not None
    assert c.recording is not None
    for name in ("ground_truth", "wheels", "filtered"):
        rows_a, rows_b = a.recording.series[name], b.recording.series[name]
        assert len(rows_a) >= 239
        assert np.array_equal(rows_a, rows_b)  # every odometry message, bit for bit
    assert [(r.stamp_ns, r.message) for r in a.logs] == [(r.stamp_ns, r.message) for r in b.logs]
    other = c.recording.series["ground_truth"]
    assert not np.array_equal(a.recording.series["ground_truth"], other)


def test_random_mover_filtered_beats_wheel_odometry_over_120_s() -> None:
    result = run_robot_scenario("random_mover", seed=0, until_sim_time=120.0)
    assert result.recording is not None
    errors = result.recording.final_errors()
    wheel_pos, wheel_yaw = errors["wheels"]
    filt_pos, filt_yaw = errors["filtered"]
    print(
        f"\nrandom_mover seed 0, 120 s: wheels {wheel_pos:.3f} m / {wheel_yaw:.4f} rad, "
        f"filtered {filt_pos:.3f} m / {filt_yaw:.4f} rad"
    )
    assert filt_pos < wheel_pos
    assert filt_yaw < wheel_yaw
    assert wheel_yaw > 0.05  # the slip really made wheel odometry drift
    # It moved around, logged the pose at 1 Hz and the commands were never refused.
    gt = result.recording.series["ground_truth"]
    assert np.ptp(gt[:, 1]) + np.ptp(gt[:, 2]) > 0.5
    odom_logs = [r for r in result.logs if r.message.startswith("Odom: ")]
    assert len(odom_logs) == 120
    assert result.rejected_commands == []


class _TfProbe(Node):
    """Looks up odom -> base_link (and the camera) once per second during the run."""

    def __init__(self) -> None:
        super().__init__("tf_probe")
        self.buffer = Buffer()
        self.listener = TransformListener(self.buffer, self)
        self.seen: list[tuple[object, object]] = []
        self.failures: list[str] = []
        self.create_timer(1.0, self._tick)

    def _tick(self) -> None:
        try:
            base = self.buffer.lookup_transform("odom", "base_link", Time())
            cam = self.buffer.lookup_transform("odom", "oak_rgb_camera_optical_frame", Time())
        except TransformException as exc:
            self.failures.append(str(exc))
            return
        self.seen.append((base, cam))


def test_transform_listener_lookups_during_a_run() -> None:
    result = run_robot_scenario(
        "p_controller",
        seed=1,
        until_sim_time=6.0,
        extra_nodes=[LaunchNode(_TfProbe, name="tf_probe")],
    )
    probe = result.node("tf_probe")
    assert probe.failures == []
    assert len(probe.seen) == 6
    assert result.recording is not None
    filtered = result.recording.series["filtered"]
    for base, cam in probe.seen:
        stamp = base.header.stamp.sec + 1e-9 * base.header.stamp.nanosec
        row = filtered[np.isclose(filtered[:, 0], stamp, atol=1e-9)]
        assert len(row) == 1  # the TF is the EKF output published with that stamp
        assert base.transform.translation.x == row[0, 1]
        assert base.transform.translation.y == row[0, 2]
        # odom -> camera optical frame = filtered pose composed with
        # docs/specs/rosbot_and_worlds.md's
        # base_link -> oak_rgb_camera_frame offset (-0.0241, 0, 0.1875).
        yaw = row[0, 3]
        ex = row[0, 1] - 0.0241 * math.cos(yaw)
        ey = row[0, 2] - 0.0241 * math.sin(yaw)
        tr = cam.transform.translation
        assert (tr.x, tr.y, tr.z) == pytest.approx((ex, ey, 0.1875), abs=1e-9)
    assert probe.seen[-1][0].transform.translation.x > 0.3  # the robot is on its way


def test_registry_and_errors() -> None:
    assert {"empty_world", "p_controller", "random_mover"} <= set(scenario_names())
    with pytest.raises(ScenarioError, match=r"unknown scenario 'nope'; available: .*p_controller"):
        get_scenario("nope")
    with pytest.raises(ScenarioError, match="already registered"):
        register_scenario("p_controller", lambda params, seed: LaunchDescription())
    with pytest.raises(ScenarioError, match=re.escape("unknown parameter(s) ['k_rhoo']")):
        run_robot_scenario("p_controller", {"k_rhoo": 1.0}, until_sim_time=0.1)
    with pytest.raises(ScenarioError, match=r"cannot start.*k_rho"):
        run_robot_scenario("p_controller", {"k_rho": "fast"}, until_sim_time=0.1)
    with pytest.raises(ScenarioError, match="unknown world"):
        run_robot_scenario("empty_world", {"world": "no_such_world"}, until_sim_time=0.1)


def test_parameter_routing_until_sim_time_and_the_empty_world() -> None:
    result = run_robot_scenario(
        "p_controller",
        {"p_controller.k_rho": 0.2, "goal_x": 2.0, "world": "aruco_box_world"},
        until_sim_time=1.0,
    )
    node = result.node("p_controller")
    assert isinstance(node, PControllerNode)
    assert node.get_parameter("k_rho").value == 0.2
    assert node.controller.goal == pytest.approx((2.0, GOAL_Y, GOAL_YAW))
    assert result.node("world_simulation").world.name == "aruco_box_world"
    assert result.sim_time == pytest.approx(1.0)

    idle = run_robot_scenario("empty_world", seed=2, until_sim_time=3.0)
    assert idle.recording is not None
    for name in ("ground_truth", "wheels"):
        assert np.all(idle.recording.series[name][:, 1:3] == 0.0)
    # The filter only integrates IMU noise: it stays within millimetres of the origin.
    assert np.abs(idle.recording.series["filtered"][:, 1:3]).max() < 5e-3


def test_realtime_paces_to_the_wall_clock() -> None:
    t0 = time.perf_counter()
    result = run_robot_scenario("empty_world", until_sim_time=0.3, realtime=True, record=False)
    assert time.perf_counter() - t0 >= 0.29
    assert result.wall_time >= 0.29


def test_other_teams_can_register_scenarios() -> None:
    def mine(params, seed):
        return LaunchDescription(
            [
                *robot_nodes(params, seed, world="aruco_box_camera_world"),
                scenario_node(PControllerNode, "p_controller", {"goal_x": 1.0}, params),
            ]
        )

    register_scenario("test_only_scenario", mine, description="test", replace=True)
    result = run_robot_scenario("test_only_scenario", {"goal_yaw": 0.5}, until_sim_time=0.5)
    assert result.node("world_simulation").world.name == "aruco_box_camera_world"
    assert result.node("p_controller").controller.goal == pytest.approx((1.0, 0.0, 0.5))
