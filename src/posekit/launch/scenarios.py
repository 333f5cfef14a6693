"""Named scenarios (``posekit launch NAME``).

A registry of launch-description factories, the routing of user parameters to their nodes, and a
stepped runner.

A scenario is a factory ``(params, seed) -> LaunchDescription`` registered under a name with
:func:`register_scenario`. This module owns no scenario itself: the packages above it
register theirs when imported (:mod:`posekit.robot.scenarios` the ROSbot's ``empty_world``,
``p_controller`` and ``random_mover``; :mod:`posekit.vision.scenarios` the ArUco demos;
importing :mod:`posekit.demos.scenarios` registers every one).

``start_scenario(name, params, seed)`` builds one and starts it in a fresh context on a
:class:`~posekit.runtime.sim_executor.SimulatedTimeExecutor`; ``run_scenario(name, params,
seed, until_sim_time, realtime)`` also steps it (as fast as possible, or paced to the wall
clock with ``realtime``) and returns a :class:`ScenarioResult`.

Parameters (``--param name:=value``): a plain ``name`` goes to every node of the scenario
that declares it (``world``, ``k_rho``, ``wheel_separation`` ...); ``node.name`` targets one
node (``random_mover.publish_rate:=4.0``). A name no node declares raises
:class:`ScenarioError` listing the known ones. :func:`scenario_node` applies this routing
to one launch entry.

Adding a scenario (e.g. the vision team's ArUco demos)::

    from posekit.launch import LaunchDescription
    from posekit.launch.scenarios import register_scenario, scenario_node
    from posekit.robot.scenarios import robot_nodes

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
from typing import Any

from posekit.launch.description import LaunchDescription, Node
from posekit.launch.runner import LaunchRun, start
from posekit.runtime.arguments import RosArguments
from posekit.runtime.context import Context
from posekit.runtime.logging import LogRecord, add_sink, remove_sink
from posekit.runtime.parameters import ParameterException
from posekit.runtime.sim_executor import ClockConflictError, SimulatedTimeExecutor

__all__ = [
    "Scenario",
    "ScenarioError",
    "ScenarioFactory",
    "ScenarioResult",
    "get_scenario",
    "register_scenario",
    "run_scenario",
    "scenario_names",
    "scenario_node",
    "scenario_value",
    "start_scenario",
]

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
    """Register ``factory`` under ``name``.

    ScenarioError if the name is taken, unless ``replace``; ``follows_clock``: see
    :attr:`Scenario.follows_clock`.
    """
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


# ---------------------------------------------------------------------------- parameter routing
def scenario_node(
    factory: Callable[..., Any] | str,
    name: str,
    defaults: Mapping[str, Any] | None,
    params: Mapping[str, Any],
    *,
    remappings: Sequence[tuple[str, str] | str] = (),
) -> Node:
    """A launch :class:`~posekit.launch.Node` called ``name``, with the user's parameters routed.

    Its parameters are ``defaults``, then every plain user parameter, then the user's
    ``name.param`` ones (nodes ignore parameters they do not declare; :func:`start_scenario`
    checks that each user parameter was used by some node).
    """
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


def scenario_value(params: Mapping[str, Any], node: str, key: str, default: Any) -> Any:
    """The value node ``node`` will get for parameter ``key`` from the user's ``params``.

    ``node.key``, else ``key``, else ``default``, as :func:`scenario_node` routes it.
    """
    return params.get(f"{node}.{key}", params.get(key, default))


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


# ---------------------------------------------------------------------------- running
def start_scenario(
    name: str,
    params: Mapping[str, Any] | None = None,
    seed: int = 0,
    *,
    realtime: bool = False,
    publish_clock: bool | None = None,
    extra_nodes: Sequence[Node] = (),
    transport: str | None = None,
    arguments: RosArguments | None = None,
) -> LaunchRun:
    """Build and start scenario ``name`` in a fresh context; nothing has run yet.

    Step ``run.executor``, a :class:`SimulatedTimeExecutor`, then call ``run.shutdown()``.

    ``extra_nodes`` are appended launch entries.
    ``publish_clock``: None (default) publishes ``/clock`` at every step exactly when the
    run's nodes are visible to other processes, and refuses to start (ScenarioError) when
    another simulation already publishes ``/clock`` there; True/False force it. Nodes of the
    run get the time from the executor directly either way.
    ``transport`` names the context's transport (default: the in-process bus, or
    $POSEKIT_TRANSPORT); ``"inprocess+zenoh"`` keeps in-process delivery and makes the run
    visible to other processes. ``arguments``: parsed ``--ros-args`` for every node of the
    run (see :func:`~posekit.launch.runner.start`).

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
            arguments=arguments,
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

    ``sim_time`` and ``wall_time`` in s; ``logs`` the log records emitted during the run
    (the newest ``max_log_records``); ``run`` the (shut down) launch run, whose node objects
    stay readable (``result.node("world_simulation")``).
    """

    name: str
    seed: int
    params: dict[str, Any]
    sim_time: float
    wall_time: float
    logs: list[LogRecord] = field(default_factory=list)
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
    stop_when: Callable[[LaunchRun], bool] | None = None,
    publish_clock: bool | None = None,
    extra_nodes: Sequence[Node] = (),
    step: float = 0.1,
    on_start: Sequence[Callable[[LaunchRun], Any]] = (),
    transport: str | None = None,
    max_log_records: int = 10_000,
) -> ScenarioResult:
    """Run scenario ``name`` and return a :class:`ScenarioResult`.

    Args:
        name: the scenario's registered name.
        params: ``{name: value}`` as from ``--param name:=value`` (see the module docstring).
        seed: run seed, passed to the scenario's factory.
        until_sim_time: stop when simulated time reaches this many seconds; None runs until
            Ctrl-C (or ``stop_when``).
        realtime: pace simulated time to the wall clock (default: as fast as possible).
        stop_when: also stop as soon as ``stop_when(run)`` is true (asked every ``step``
            simulated seconds).
        publish_clock: see :func:`start_scenario`.
        extra_nodes: see :func:`start_scenario`.
        step: simulated seconds run between two checks of ``stop_when`` and of the context.
        on_start: callables given the started run before any time passes (attach a bag
            recorder or a viewer; whatever they start must end when the run's context does).
        transport: see :func:`start_scenario`.
        max_log_records: log records kept for :attr:`ScenarioResult.logs` (the newest; a
            long run keeps memory flat).
    """
    if until_sim_time is not None and not until_sim_time >= 0.0:
        raise ScenarioError(f"until_sim_time must be >= 0 s, got {until_sim_time}")
    if not step > 0.0:
        raise ScenarioError(f"step must be > 0 s, got {step}")
    if max_log_records < 0:
        raise ScenarioError(f"max_log_records must be >= 0, got {max_log_records}")
    user_params = dict(params or {})
    run = start_scenario(
        name,
        user_params,
        seed,
        realtime=realtime,
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
            if stop_when is not None and stop_when(run):
                break
    except KeyboardInterrupt:
        pass
    finally:
        wall = time.perf_counter() - wall0
        remove_sink(logs.append)
        run.shutdown()
    return ScenarioResult(
        name=name,
        seed=int(seed),
        params=user_params,
        sim_time=executor.now_ns / 1e9,
        wall_time=wall,
        logs=list(logs),
        run=run,
    )
