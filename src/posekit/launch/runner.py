"""Run a launch description in this process with one executor.

``launch(description, duration=60.0)`` runs in simulated time by default (a
SimulatedTimeExecutor: as fast as the CPU allows, deterministic); ``sim_time=False`` spins a
wall-clock executor; ``own_clock=False`` (with sim time) runs the nodes on sim time that
*another* process owns: a wall-clock executor, every node ``use_sim_time`` following
``/clock`` (a demo started against a running world, as in ROS). ``transport`` names the
context's transport (e.g. ``"inprocess+zenoh"``); a run that owns its clock never takes
``/clock`` from other processes. ``run_launch_file(path)`` loads ``FILE.py`` whose
``generate_launch_description()`` returns a :class:`LaunchDescription`; :func:`main` is the
entry point the ``posekit launch`` CLI calls.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from posekit.launch.description import LaunchDescription, LaunchDescriptionError
from posekit.runtime.arguments import RosArguments
from posekit.runtime.context import Context
from posekit.runtime.executors import Executor, MultiThreadedExecutor, SingleThreadedExecutor
from posekit.runtime.logging import get_logger
from posekit.runtime.node import Node, node_defaults
from posekit.runtime.parameters import parse_parameter_value
from posekit.runtime.sim_executor import SimulatedTimeExecutor, graph_clock_publishers
from posekit.runtime.time_source import CLOCK_TOPIC

__all__ = [
    "LaunchRun", "launch", "load_launch_file", "main", "run_launch_file", "run_until", "start",
]

#: How long :meth:`LaunchRun.shutdown` waits for a callback still running elsewhere (s).
SHUTDOWN_WAIT_S = 10.0


@dataclass
class LaunchRun:
    """A started launch: its context, executor, nodes and the objects the factories returned."""

    context: Context
    executor: Executor
    nodes: list[Node] = field(default_factory=list)
    created: list[Any] = field(default_factory=list)
    #: True when the nodes follow the ``/clock`` of a simulation elsewhere (sim time that
    #: this run does not own: a wall-clock executor; see :func:`start`'s ``own_clock``).
    follows_clock: bool = False

    def node(self, name: str) -> Node:
        """The node called ``name`` (or fully qualified ``/ns/name``)."""
        for n in self.nodes:  # also after the run, when the nodes are destroyed
            fqn = n.fully_qualified_name
            if name in (fqn.rpartition("/")[2], fqn):
                return n
        names = [n.fully_qualified_name.rpartition("/")[2] for n in self.nodes]
        raise KeyError(f"no node named {name!r}; have {names}")

    def shutdown(self, timeout_sec: float = SHUTDOWN_WAIT_S) -> None:
        """Stop the executor, destroy the nodes and shut the context down.

        A thread spinning the executor elsewhere finishes its current callback first (waited
        for up to ``timeout_sec`` s; past that, a warning names the wait and the nodes go
        anyway), so no callback of this run meets a destroyed node.
        """
        if not self.executor.shutdown(timeout_sec):
            get_logger("posekit.launch").warning(
                f"a callback of this run was still running {timeout_sec:g} s after shutdown; "
                "destroying its nodes anyway"
            )
        for n in self.nodes:
            n.destroy_node()
        self.context.try_shutdown()


def _collect_nodes(obj: Any) -> list[Node]:
    if isinstance(obj, Node):
        return [obj]
    if isinstance(obj, list | tuple):
        return [n for item in obj for n in _collect_nodes(item)]
    return []


def start(
    description: LaunchDescription,
    *,
    sim_time: bool = True,
    real_time_factor: float | None = None,
    launch_arguments: Mapping[str, Any] | None = None,
    context: Context | None = None,
    multithreaded: bool = False,
    publish_clock: bool | None = None,
    own_clock: bool | None = True,
    transport: str | None = None,
    arguments: RosArguments | None = None,
) -> LaunchRun:
    """Create every node of ``description`` and add them to one executor.

    The nodes live in a fresh (or given) context; nothing runs until the caller spins/steps
    ``run.executor``.

    ``publish_clock`` (sim time only): publish ``/clock`` at every simulated step, as
    Gazebo does. Default (None): exactly when the run's nodes are visible to other processes
    (a network transport), after :meth:`SimulatedTimeExecutor.claim_clock` made sure no
    other simulation publishes ``/clock`` there (else :class:`ClockConflictError`, with the
    run shut down). The run's own nodes get the time from the executor either way (they do
    not follow ``/clock``), so only outside observers need it.

    ``own_clock=False``: see the module docstring; ``own_clock=None`` (sim time) decides as
    ``ros2 launch`` of nodes next to a running Gazebo would behave: a description with no
    clock source of its own (:meth:`LaunchDescription.has_clock_source`) follows a
    ``/clock`` already published on the context's transport, and owns the clock otherwise
    (a description that runs a world then meets :class:`ClockConflictError` when another
    simulation publishes ``/clock``). ``transport``: the transport name given to
    a context this function initialises. ``arguments``: parsed ``--ros-args`` given to every
    node of the run, as a process's ROS arguments reach its nodes (``posekit run``): they win
    over the description's names, parameters and remappings; their log levels are set here.
    """
    if not isinstance(description, LaunchDescription):
        raise LaunchDescriptionError(f"expected a LaunchDescription, got {description!r}")
    ctx = context or Context()
    if not ctx.ok():
        # A launch's nodes get their arguments from the description.
        ctx.init(args=[], transport=transport)
    if own_clock is None:
        own_clock = not sim_time or description.has_clock_source() or not (
            graph_clock_publishers(ctx.transport()))
    owns_clock = sim_time and own_clock
    if owns_clock:
        ctx.transport().own_topic(CLOCK_TOPIC)
    executor: Executor
    if owns_clock:
        executor = SimulatedTimeExecutor(
            context=ctx, real_time_factor=real_time_factor, publish_clock=publish_clock
        )
    elif multithreaded:
        executor = MultiThreadedExecutor(context=ctx)
    else:
        executor = SingleThreadedExecutor(context=ctx)
    run = LaunchRun(ctx, executor, follows_clock=sim_time and not own_clock)
    if isinstance(executor, SimulatedTimeExecutor):
        try:  # before any node exists: a refused run never shows a node to other processes
            executor.claim_clock(ctx.transport())
        except BaseException:
            run.shutdown()
            raise
    if arguments is not None:
        arguments.apply_log_levels()
    configuration = description.arguments(launch_arguments)
    try:  # every entry's parameter files read before any node exists
        matched = [entry.resolved_parameters(configuration) for entry in description.nodes]
    except BaseException:
        run.shutdown()
        raise
    for entry, entry_parameters in zip(description.nodes, matched, strict=True):
        with node_defaults(
            name=entry.name,
            namespace=entry.namespace,
            # the entry's own parameters (files matched by node name) win over this default
            parameters={"use_sim_time": True} if sim_time else {},
            matched_parameters=entry_parameters,
            remappings=list(entry.remappings),
            context=ctx,
            arguments=arguments,
        ):
            created = entry.factory()()
        nodes = _collect_nodes(created)
        if not nodes:
            raise LaunchDescriptionError(
                f"launch entry {entry.package_or_callable or entry.executable!r} did not "
                f"return a posekit Node (got {created!r})"
            )
        run.created.append(created)
        for n in nodes:
            executor.add_node(n)
            run.nodes.append(n)
    return run


def launch(
    description: LaunchDescription,
    *,
    duration: float | None = None,
    sim_time: bool = True,
    real_time_factor: float | None = None,
    launch_arguments: Mapping[str, Any] | None = None,
    context: Context | None = None,
    shutdown: bool = True,
    publish_clock: bool | None = None,
    own_clock: bool | None = True,
    transport: str | None = None,
) -> LaunchRun:
    """Start ``description`` and run it for ``duration`` seconds; returns the run.

    Sim seconds in sim time; ``None`` = until shutdown / Ctrl-C. The run is already shut down if
    ``shutdown``. ``publish_clock``, ``own_clock``, ``transport``: see :func:`start`.
    """
    run = start(
        description,
        sim_time=sim_time,
        real_time_factor=real_time_factor,
        launch_arguments=launch_arguments,
        context=context,
        publish_clock=publish_clock,
        own_clock=own_clock,
        transport=transport,
    )
    try:
        run_until(run, duration, sim_time=sim_time)
    except KeyboardInterrupt:
        pass
    finally:
        if shutdown:
            run.shutdown()
    return run


def run_until(run: LaunchRun, duration: float | None, *, sim_time: bool = True) -> None:
    """Run a started launch for ``duration`` seconds (None: until the context shuts down).

    On a :class:`SimulatedTimeExecutor` these are simulated seconds it steps through; with
    nodes following another process's ``/clock`` (``own_clock=False``), simulated seconds as
    the first node's clock shows them (waiting for the clock to reach ``duration``); else
    wall seconds.
    """
    executor = run.executor
    if isinstance(executor, SimulatedTimeExecutor):
        if duration is None:
            executor.spin()
        else:
            executor.run_for(duration)
        return
    if duration is None:
        executor.spin()
    elif sim_time and run.nodes:
        clock = run.nodes[0].get_clock()
        while run.context.ok() and clock.now().nanoseconds < duration * 1e9:
            executor.spin_once(timeout_sec=0.05)
    else:
        end = time.monotonic() + duration
        while run.context.ok() and time.monotonic() < end:
            executor.spin_once(timeout_sec=max(0.0, end - time.monotonic()))


def load_launch_file(path: str | Path) -> LaunchDescription:
    """Import ``path`` and call its ``generate_launch_description()``.

    The file's folder goes first on ``sys.path`` (as for ``python FILE.py``), so a launch file
    can import node modules next to it, now and when its nodes are created. An error raised
    while importing the file or generating the description becomes a one-line
    :class:`LaunchDescriptionError` naming the file.
    """
    p = Path(path)
    if not p.is_file():
        raise LaunchDescriptionError(f"launch file {p} does not exist")
    folder = str(p.resolve().parent)
    if folder not in sys.path:
        sys.path.insert(0, folder)
    spec = importlib.util.spec_from_file_location(f"posekit_launch_{p.stem}", p)
    if spec is None or spec.loader is None:
        raise LaunchDescriptionError(f"cannot load {p} as Python")
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
        generate = getattr(module, "generate_launch_description", None)
        if generate is None:
            raise LaunchDescriptionError(f"{p} has no generate_launch_description() function")
        description = generate()
    except LaunchDescriptionError:
        raise
    except Exception as exc:
        raise LaunchDescriptionError(f"{p}: {type(exc).__name__}: {exc}") from exc
    if not isinstance(description, LaunchDescription):
        raise LaunchDescriptionError(
            f"{p}: generate_launch_description() returned {type(description).__name__}, "
            "not a posekit.launch.LaunchDescription"
        )
    return description


def run_launch_file(path: str | Path, **kwargs: Any) -> LaunchRun:
    """load_launch_file + launch (same keyword arguments as :func:`launch`)."""
    return launch(load_launch_file(path), **kwargs)


def main(argv: Sequence[str] | None = None) -> int:
    """``posekit launch FILE.py [name:=value ...] [--duration S] [--wall] [--rtf R]``."""
    parser = argparse.ArgumentParser(prog="posekit launch", description=__doc__)
    parser.add_argument("file", help="launch file with generate_launch_description()")
    parser.add_argument("arguments", nargs="*", help="launch arguments name:=value")
    parser.add_argument("--duration", type=float, default=None,
                        help="seconds to run (simulated seconds unless --wall)")
    parser.add_argument("--wall", action="store_true", help="wall-clock time, not sim time")
    parser.add_argument("--rtf", type=float, default=None,
                        help="pace simulated time at this real-time factor (1.0 = real time)")
    parser.add_argument("--no-clock", action="store_true",
                        help="sim time: never publish /clock (default: published when the "
                             "nodes are visible to other processes)")
    ns = parser.parse_args(argv)
    arguments: dict[str, Any] = {}
    for item in ns.arguments:
        if ":=" not in item:
            parser.error(f"launch arguments look like name:=value, got {item!r}")
        key, value = item.split(":=", 1)
        arguments[key] = parse_parameter_value(value)
    try:
        run_launch_file(
            ns.file,
            duration=ns.duration,
            sim_time=not ns.wall,
            real_time_factor=ns.rtf,
            launch_arguments=arguments,
            publish_clock=False if ns.no_clock else None,
        )
    except LaunchDescriptionError as exc:
        print(f"posekit launch: {exc}", file=sys.stderr)
        return 2
    return 0
