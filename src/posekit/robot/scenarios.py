"""The ROSbot's named scenarios (``posekit launch NAME``), registered when this is imported.

==================  ===========================================================================
name                nodes
==================  ===========================================================================
``empty_world``     world_simulation (``empty_world``), wheel_odometry, ekf_node
``p_controller``    the same + p_controller with the course launch's goal (5, 5, pi/2)
``random_mover``    the same + random_mover (seeded from the run seed)
==================  ===========================================================================

The scenario framework (registry, parameter routing, starting and stepping a run) is
:mod:`posekit.launch.scenarios`; this module adds the robot's part: :func:`robot_nodes`, the
simulated ROSbot stack every scenario of the course starts from, and
:func:`run_robot_scenario`, which runs any registered scenario (they all hold the robot) and
measures what the robot did (odometry, goal reached, rejected commands, plot). ``seed``
seeds the simulator (slip, IMU) and the random mover through
:func:`posekit.robot.headless.sub_seeds`, so a scenario is reproducible message for message.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

from posekit.launch import LaunchDescription, LaunchRun, Node
from posekit.launch.scenarios import (
    ScenarioError,
    ScenarioResult,
    register_scenario,
    run_scenario,
    scenario_node,
    scenario_value,
)
from posekit.robot.headless import sub_seeds
from posekit.robot.nodes import (
    EkfNode,
    OdometryRecorder,
    OdometryRecording,
    PControllerNode,
    RandomMoverNode,
    WheelOdometryNode,
    WorldSimulation,
)
from posekit.worlds import WorldError, load_world

__all__ = [
    "DEFAULT_GOAL",
    "RobotScenarioResult",
    "robot_nodes",
    "run_robot_scenario",
]

#: The course's p_controller.launch.py goal (x m, y m, yaw rad) in odom.
DEFAULT_GOAL: tuple[float, float, float] = (5.0, 5.0, math.pi / 2)


def robot_nodes(
    params: Mapping[str, Any], seed: int, *, world: str = "empty_world"
) -> list[Node]:
    """The simulated ROSbot stack: ``world_simulation`` (in ``world`` unless the user's
    ``world`` parameter says otherwise), ``wheel_odometry`` and ``ekf_node``, both starting
    at the world's spawn pose."""
    world_name = str(scenario_value(params, "world_simulation", "world", world))
    try:
        spawn = load_world(world_name).spawn
    except WorldError as exc:
        raise ScenarioError(str(exc)) from exc
    sx, sy, syaw = spawn
    initial_state = [0.0] * 15
    initial_state[0], initial_state[1], initial_state[5] = sx, sy, syaw
    return [
        scenario_node(WorldSimulation, "world_simulation", {"world": world, "seed": seed}, params),
        scenario_node(
            WheelOdometryNode,
            "wheel_odometry",
            {"initial_x": sx, "initial_y": sy, "initial_yaw": syaw},
            params,
        ),
        # RViz2's "2D Pose Estimate" (initialpose) resets the EKF, as robot_localization
        # is commonly launched (set_pose:=initialpose).
        scenario_node(EkfNode, "ekf_node", {"initial_state": initial_state}, params,
                      remappings=[("set_pose", "/initialpose")]),
    ]


def _empty_world(params: Mapping[str, Any], seed: int) -> LaunchDescription:
    return LaunchDescription(robot_nodes(params, seed))


def _p_controller(params: Mapping[str, Any], seed: int) -> LaunchDescription:
    gx, gy, gyaw = DEFAULT_GOAL
    return LaunchDescription(
        [
            *robot_nodes(params, seed),
            scenario_node(
                PControllerNode,
                "p_controller",
                {"goal_x": gx, "goal_y": gy, "goal_yaw": gyaw},
                params,
            ),
        ]
    )


def _random_mover(params: Mapping[str, Any], seed: int) -> LaunchDescription:
    return LaunchDescription(
        [
            *robot_nodes(params, seed),
            scenario_node(RandomMoverNode, "random_mover", {"seed": sub_seeds(seed)[2]}, params),
        ]
    )


register_scenario(
    "empty_world", _empty_world, description="the ROSbot in the empty world (no controller)"
)
register_scenario(
    "p_controller",
    _p_controller,
    description="empty world + the course's P controller to (5, 5, pi/2)",
)
register_scenario(
    "random_mover", _random_mover, description="empty world + random 2 Hz velocity commands"
)


@dataclass
class RobotScenarioResult(ScenarioResult):
    """A :class:`~posekit.launch.scenarios.ScenarioResult` plus what the robot did.

    ``goal_reached_time`` the sim time (s) of the first ``goal_reached`` (None if never);
    ``recording`` the odometry series (if recorded); ``rejected_commands`` ``(t_s, reason)``
    of the simulator's last refused commands and ``rejected_count`` all of them;
    ``plot_path`` the PNG written (if asked).
    """

    goal_reached_time: float | None = None
    recording: OdometryRecording | None = None
    rejected_commands: list[tuple[float, str]] = field(default_factory=list)
    rejected_count: int = 0
    plot_path: Path | None = None


def _goal_reached(run: LaunchRun) -> bool:
    node = run.node("odometry_recorder")
    return isinstance(node, OdometryRecorder) and bool(node.goal_reached_times)


def run_robot_scenario(
    name: str,
    params: Mapping[str, Any] | None = None,
    seed: int = 0,
    until_sim_time: float | None = None,
    realtime: bool = False,
    *,
    stop_on_goal: bool = False,
    record: bool = True,
    plot_path: str | Path | None = None,
    publish_clock: bool | None = None,
    extra_nodes: Sequence[Node] = (),
    step: float = 0.1,
    on_start: Sequence[Callable[[LaunchRun], Any]] = (),
    transport: str | None = None,
    max_log_records: int = 10_000,
) -> RobotScenarioResult:
    """Run scenario ``name`` (:func:`posekit.launch.scenarios.run_scenario`, whose arguments
    these are too) and return a :class:`RobotScenarioResult`.

    Args:
        record: add an ``odometry_recorder`` node and keep every odometry sample (leave it
            off for long runs that need no plot: memory grows with the run).
        stop_on_goal: also stop at the first ``goal_reached`` (checked every ``step``
            simulated seconds; needs ``record``).
        plot_path: write the odometry PNG (:func:`posekit.robot.plot.plot_odometry`) there
            at the end (needs ``record``).
    """
    if (plot_path is not None or stop_on_goal) and not record:
        raise ScenarioError("plot_path and stop_on_goal need record=True")
    recorder_entry = [Node(OdometryRecorder, name="odometry_recorder")] if record else []
    base = run_scenario(
        name,
        params,
        seed,
        until_sim_time,
        realtime,
        stop_when=_goal_reached if stop_on_goal else None,
        publish_clock=publish_clock,
        extra_nodes=[*recorder_entry, *extra_nodes],
        step=step,
        on_start=on_start,
        transport=transport,
        max_log_records=max_log_records,
    )
    run = base.run
    assert run is not None
    recording: OdometryRecording | None = None
    if record:
        recorder = run.node("odometry_recorder")
        assert isinstance(recorder, OdometryRecorder)
        recording = recorder.recording()
    rejected: list[tuple[float, str]] = []
    rejected_count = 0
    for n in run.nodes:
        if isinstance(n, WorldSimulation):
            rejected.extend((t_ns / 1e9, reason) for t_ns, reason in n.rejected)
            rejected_count += n.rejected_count
    goal_time = recording.goal_reached[0] if recording and recording.goal_reached else None
    if recording is None:  # not recorded: the controller knows when it got there
        reached = [n.goal_reached_ns for n in run.nodes
                   if isinstance(n, PControllerNode) and n.goal_reached_ns is not None]
        goal_time = min(reached) / 1e9 if reached else None
    written: Path | None = None
    if plot_path is not None and recording is not None:
        from posekit.robot.plot import plot_odometry

        written = plot_odometry(
            recording, plot_path,
            title=f"{name} (seed {seed}, {base.sim_time:.1f} s simulated)",
        )
    return RobotScenarioResult(
        **{f.name: getattr(base, f.name) for f in fields(ScenarioResult)},
        goal_reached_time=goal_time,
        recording=recording,
        rejected_commands=rejected,
        rejected_count=rejected_count,
        plot_path=written,
    )
