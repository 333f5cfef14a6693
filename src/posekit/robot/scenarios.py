"""Named scenarios (``posekit launch NAME``): the course's launch files as launch descriptions.

A scenario is a factory ``(params, seed) -> LaunchDescription`` registered under a name:

==================  ===========================================================================
name                nodes
==================  ===========================================================================
``empty_world``     world_simulation (``empty_world``), wheel_odometry, ekf_node
``p_controller``    the same + p_controller with the course launch's goal (5, 5, pi/2)
``random_mover``    the same + random_mover (seeded from the run seed)
==================  ===========================================================================

``run_scenario(name, params, seed, until_sim_time, realtime)`` starts one in a fresh context
on a :class:`~posekit.runtime.sim_executor.SimulatedTimeExecutor` (as fast as possible, or paced
to the wall clock with ``realtime``) and returns a :class:`ScenarioResult`.

Parameters (``--param name:=value``): a plain ``name`` goes to every node of the scenario
that declares it (``world``, ``k_rho``, ``wheel_separation`` ...); ``node.name`` targets one
node (``random_mover.publish_rate:=4``). A name no node declares raises
:class:`ScenarioError` listing the known ones. ``seed`` seeds the simulator (slip, IMU) and
the random mover through :func:`posekit.robot.headless.sub_seeds`, so a scenario is
reproducible message for message.

Adding a scenario (e.g. the vision team's ArUco demos)::

    from posekit.launch import LaunchDescription, Node
    from posekit.robot.scenarios import register_scenario, robot_nodes, scenario_node

    def aruco_box_world(params, seed):
        return LaunchDescription([
            *robot_nodes(params, seed, world="aruco_box_world"),
            scenario_node(MyDetector, "aruco_detector", {"marker_size": 0.194}, params),
        ])

    register_scenario("aruco_box_world", aruco_box_world, description="...")
"""

from __future__ import annotations

import math
import time
from collections import deque
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from posekit.launch import LaunchDescription, LaunchRun, Node, start
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
from posekit.robot.worlds import WorldError, load_world
from posekit.runtime.context import Context
from posekit.runtime.logging import LogRecord, add_sink, remove_sink
from posekit.runtime.parameters import ParameterException
from posekit.runtime.sim_executor import ClockConflictError, SimulatedTimeExecutor

__all__ = [
    "DEFAULT_GOAL",
    "Scenario",
    "ScenarioError",
    "ScenarioFactory",
    "ScenarioResult",
    "get_scenario",
    "register_scenario",
    "robot_nodes",
    "run_scenario",
    "scenario_names",
    "scenario_node",
    "start_scenario",
]

#: The course's p_controller.launch.py goal (x m, y m, yaw rad) in odom.
DEFAULT_GOAL: tuple[float, float, float] = (5.0, 5.0, math.pi / 2)

#: ``factory(params, seed) -> LaunchDescription``.
ScenarioFactory = Callable[[Mapping[str, Any], int], LaunchDescription]


class ScenarioError(ValueError):
    """Unknown scenario, unknown parameter, or a scenario that cannot start (with the reason)."""


@dataclass(frozen=True)
class Scenario:
    """A registered scenario: its ``name``, ``factory`` and a one-line ``description``."""

    name: str
    factory: ScenarioFactory
    description: str = ""
    #: True for a demo that runs against a running world in another process: its nodes
    #: follow that world's ``/clock`` and it starts no simulation of its own.
    follows_clock: bool = False


_REGISTRY: dict[str, Scenario] = {}


def register_scenario(
    name: str, factory: ScenarioFactory, *, description: str = "", replace: bool = False,
    follows_clock: bool = False,
) -> Scenario:
    """Register ``factory`` under ``name`` (ScenarioError if taken, unless ``replace``);
    ``follows_clock``: see :attr:`Scenario.follows_clock`."""
    if not name or not isinstance(name, str):
        raise ScenarioError(f"scenario names must be non-empty strings, got {name!r}")
    if name in _REGISTRY and not replace:
        raise ScenarioError(f"scenario '{name}' is already registered")
    scenario = Scenario(name, factory, description, follows_clock)
    _REGISTRY[name] = scenario
    return scenario


def scenario_names() -> list[str]:
    """Registered scenario names, sorted."""
    return sorted(_REGISTRY)


def get_scenario(name: str) -> Scenario:
    """The scenario called ``name`` (ScenarioError listing the known ones otherwise)."""
    try:
        return _REGISTRY[name]
    except KeyError:
        raise ScenarioError(
            f"unknown scenario '{name}'; available: {', '.join(scenario_names())}"
        ) from None


# ---------------------------------------------------------------------------- building blocks
def scenario_node(
    factory: Callable[..., Any] | str,
    name: str,
    defaults: Mapping[str, Any] | None,
    params: Mapping[str, Any],
    *,
    remappings: Sequence[tuple[str, str] | str] = (),
) -> Node:
    """A launch :class:`~posekit.launch.Node` called ``name`` whose parameters are
    ``defaults``, then every plain user parameter, then the user's ``name.param`` ones
    (nodes ignore parameters they do not declare; :func:`start_scenario` checks that each
    user parameter was used by some node)."""
    merged: dict[str, Any] = dict(defaults or {})
    prefix = name + "."
    scoped: dict[str, Any] = {}
    for key, value in params.items():
        if key.startswith(prefix):
            scoped[key[len(prefix):]] = value
        else:
            merged[key] = value
    merged.update(scoped)
    return Node(factory, name=name, parameters=[merged], remappings=list(remappings))


def _user_value(params: Mapping[str, Any], node: str, key: str, default: Any) -> Any:
    return params.get(f"{node}.{key}", params.get(key, default))


def robot_nodes(
    params: Mapping[str, Any], seed: int, *, world: str = "empty_world"
) -> list[Node]:
    """The simulated ROSbot stack: ``world_simulation`` (in ``world`` unless the user's
    ``world`` parameter says otherwise), ``wheel_odometry`` and ``ekf_node``, both starting
    at the world's spawn pose."""
    world_name = str(_user_value(params, "world_simulation", "world", world))
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
        scenario_node(EkfNode, "ekf_node", {"initial_state": initial_state}, params),
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


# ---------------------------------------------------------------------------- running
def _check_parameters(run: LaunchRun, params: Mapping[str, Any]) -> None:
    nodes = {n.get_name(): n for n in run.nodes}
    unknown = []
    for key in params:
        if any(n.has_parameter(key) for n in nodes.values()):
            continue
        head, _, rest = key.partition(".")
        if rest and head in nodes and nodes[head].has_parameter(rest):
            continue
        unknown.append(key)
    if unknown:
        known = sorted(
            {
                p
                for n in nodes.values()
                for p in n.get_parameters_by_prefix("")
                if p != "use_sim_time"
            }
        )
        raise ScenarioError(
            f"unknown parameter(s) {unknown}; the nodes ({', '.join(nodes)}) declare: "
            f"{', '.join(known)} (use node.name:=value to target one node)"
        )


def start_scenario(
    name: str,
    params: Mapping[str, Any] | None = None,
    seed: int = 0,
    *,
    realtime: bool = False,
    record: bool = True,
    publish_clock: bool | None = None,
    extra_nodes: Sequence[Node] = (),
    transport: str | None = None,
) -> LaunchRun:
    """Build and start scenario ``name`` in a fresh context; nothing has run yet (step
    ``run.executor``, a :class:`SimulatedTimeExecutor`, then ``run.shutdown()``).

    ``record`` adds an ``odometry_recorder``; ``extra_nodes`` are appended launch entries.
    ``publish_clock``: None (default) publishes ``/clock`` at every step exactly when the
    run's nodes are visible to other processes, and refuses to start (ScenarioError) when
    another simulation already publishes ``/clock`` there; True/False force it. Nodes of the
    run get the time from the executor directly either way.
    ``transport`` names the context's transport (default: the in-process bus, or
    $POSEKIT_TRANSPORT); ``"inprocess+zenoh"`` keeps in-process delivery and makes the run
    visible to other processes.

    A :attr:`Scenario.follows_clock` scenario (a demo against a running world) gets a
    wall-clock executor instead, its nodes following ``/clock`` from another process; its
    transport must reach that process (ScenarioError otherwise).
    """
    params = dict(params or {})
    scenario = get_scenario(name)
    if scenario.follows_clock and (transport or "inprocess") == "inprocess":
        raise ScenarioError(
            f"'{name}' runs against a running world in another process (it starts no "
            "simulation); it needs a network transport, not the isolated in-process bus"
        )
    description = scenario.factory(params, int(seed))
    if record:
        description.add_action(Node(OdometryRecorder, name="odometry_recorder"))
    for entry in extra_nodes:
        description.add_action(entry)
    try:
        run = start(
            description,
            sim_time=True,
            real_time_factor=1.0 if realtime else None,
            context=Context(),
            publish_clock=publish_clock,
            own_clock=not scenario.follows_clock,
            transport=transport,
        )
    except (ParameterException, ValueError, TypeError, ClockConflictError) as exc:
        raise ScenarioError(f"scenario '{name}' cannot start: {exc}") from exc
    try:
        _check_parameters(run, params)
    except ScenarioError:
        run.shutdown()
        raise
    return run


@dataclass
class ScenarioResult:
    """What a scenario run produced.

    ``sim_time`` and ``wall_time`` in s; ``goal_reached_time`` the sim time of the first
    ``goal_reached`` (None if never); ``recording`` the odometry series (if recorded);
    ``rejected_commands`` ``(t_s, reason)`` of the simulator's last refused commands and
    ``rejected_count`` all of them; ``logs`` the log records emitted during the run (the
    newest ``max_log_records``); ``plot_path`` the PNG written (if asked); ``run`` the (shut
    down) launch run, whose node objects stay readable (``result.node("world_simulation")``).
    """

    name: str
    seed: int
    params: dict[str, Any]
    sim_time: float
    wall_time: float
    goal_reached_time: float | None
    recording: OdometryRecording | None
    rejected_commands: list[tuple[float, str]]
    logs: list[LogRecord] = field(default_factory=list)
    rejected_count: int = 0
    plot_path: Path | None = None
    run: LaunchRun | None = None

    @property
    def speedup(self) -> float:
        """Simulated seconds per wall-clock second."""
        return self.sim_time / self.wall_time if self.wall_time > 0 else math.inf

    def node(self, name: str) -> Any:
        """The node object called ``name``."""
        if self.run is None:
            raise KeyError(name)
        return self.run.node(name)


def run_scenario(
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
) -> ScenarioResult:
    """Run scenario ``name`` and return a :class:`ScenarioResult`.

    Args:
        params: ``{name: value}`` as from ``--param name:=value`` (see the module docstring).
        seed: run seed (simulator noise and slip, random mover).
        until_sim_time: stop when simulated time reaches this many seconds; None runs until
            Ctrl-C (or ``stop_on_goal``).
        realtime: pace simulated time to the wall clock (default: as fast as possible).
        stop_on_goal: also stop at the first ``goal_reached`` (checked every ``step``
            simulated seconds; needs ``record``).
        plot_path: write the odometry PNG (:func:`posekit.robot.plot.plot_odometry`) there
            at the end (needs ``record``).
        publish_clock, extra_nodes: see :func:`start_scenario`.
        on_start: callables given the started run before any time passes (attach a bag
            recorder or a viewer; whatever they start must end when the run's context does).
        transport: see :func:`start_scenario`.
        max_log_records: log records kept for :attr:`ScenarioResult.logs` (the newest; a
            long run keeps memory flat). ``record=True`` keeps every odometry sample, so
            leave it off for long runs that need no plot.
    """
    if until_sim_time is not None and not until_sim_time >= 0.0:
        raise ScenarioError(f"until_sim_time must be >= 0 s, got {until_sim_time}")
    if (plot_path is not None or stop_on_goal) and not record:
        raise ScenarioError("plot_path and stop_on_goal need record=True")
    if not step > 0.0:
        raise ScenarioError(f"step must be > 0 s, got {step}")
    user_params = dict(params or {})
    run = start_scenario(
        name,
        user_params,
        seed,
        realtime=realtime,
        record=record,
        publish_clock=publish_clock,
        extra_nodes=extra_nodes,
        transport=transport,
    )
    executor = run.executor
    if not isinstance(executor, SimulatedTimeExecutor):
        run.shutdown()
        raise ScenarioError(f"'{name}' follows another process's clock: start it with "
                            "start_scenario() and spin its executor")
    try:
        for hook in on_start:
            hook(run)
    except BaseException:
        run.shutdown()
        raise
    recorder: OdometryRecorder | None = None
    if record:
        node = run.node("odometry_recorder")
        assert isinstance(node, OdometryRecorder)
        recorder = node
    if max_log_records < 0:
        raise ScenarioError(f"max_log_records must be >= 0, got {max_log_records}")
    logs: deque[LogRecord] = deque(maxlen=max_log_records)
    add_sink(logs.append)
    wall0 = time.perf_counter()
    try:
        while run.context.ok():
            now = executor.now_ns / 1e9
            if until_sim_time is not None and now >= until_sim_time - 1e-12:
                break
            target = now + step
            if until_sim_time is not None:
                target = min(target, until_sim_time)
            executor.run_until(target)
            if stop_on_goal and recorder is not None and recorder.goal_reached_times:
                break
    except KeyboardInterrupt:
        pass
    finally:
        wall = time.perf_counter() - wall0
        remove_sink(logs.append)
        run.shutdown()
    sim_time = executor.now_ns / 1e9
    recording = recorder.recording() if recorder is not None else None
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
            recording, plot_path, title=f"{name} (seed {seed}, {sim_time:.1f} s simulated)"
        )
    return ScenarioResult(
        name=name,
        seed=int(seed),
        params=user_params,
        sim_time=sim_time,
        wall_time=wall,
        goal_reached_time=goal_time,
        recording=recording,
        rejected_commands=rejected,
        rejected_count=rejected_count,
        logs=list(logs),
        plot_path=written,
        run=run,
    )
