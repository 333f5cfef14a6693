"""``posekit launch SCENARIO|FILE.py|PACKAGE FILE.launch.py``: run a scenario or a launch file.

Options and ``name:=value`` assignments may come in any order
(``posekit launch p_controller --until-sim-time 30 k_rho:=1.0``).

Targets: a scenario name (``posekit launch --list``), the lecture's launch files
(``posekit launch rosbot_gazebo empty_world.launch.py``, ``posekit launch robot_control_demo
p_controller.launch.py``), or your own launch file ``FILE.py`` (its folder is importable).

Visibility: by default the launch's nodes keep their deterministic in-process delivery *and*
are visible on the network transport (Zenoh unless ``--transport dds`` or $POSEKIT_TRANSPORT
says otherwise), so ``posekit topic list``, ``node list``, ``tf echo`` or your own node in
another terminal see and talk to them; the run then also publishes ``/clock`` (and refuses to
start when another simulation already does). ``--isolated`` (or POSEKIT_TRANSPORT=inprocess)
keeps everything in this process: no network, no ``/clock``, the fastest mode. Without the
network transport's package installed, a launch that did not ask for it runs isolated and
says so in one line.

Scenario options: ``--param name:=value`` (or bare ``name:=value``; ``node.name:=value`` reaches one
node), ``--seed N``, ``--until-sim-time S`` (stop after S simulated seconds), ``--realtime`` (pace
to the wall clock; default is as fast as possible; a paced run that falls behind logs its real-time
factor), ``--no-clock`` (never publish ``/clock``, which a run visible to other processes publishes
by default), ``--record DIR`` (a ROS 2 bag), ``--viewer`` (serve the browser viewer; ``--host``,
``--port``, ``--allow-host``, ``--allow-origin`` as ``posekit view``), ``--plot PNG`` (odometry
plot), ``--save-images DIR`` (debug images as PNG, rqt_image_view's role), ``--show-args`` (the
parameters and their defaults, as ``ros2 launch -s`` lists launch arguments). Every option applies
to launch files as well (``--seed`` as the file's ``seed`` launch argument).
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from posekit.cli.errors import report

__all__ = ["main", "network_transport"]


class _UsageError(Exception):
    """A user mistake reported as one line."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> Any:
        raise _UsageError(message)


def _parser(prog: str = "posekit launch") -> argparse.ArgumentParser:
    parser = _Parser(prog=prog, description=__doc__,
                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("words", nargs="*", metavar="TARGET [name:=value ...]",
                        help="scenario, FILE.py or PACKAGE FILE.launch.py, then name:=value "
                             "parameters / launch arguments")
    parser.add_argument("--param", "-p", action="append", default=[], metavar="NAME:=VALUE")
    parser.add_argument("--seed", type=int, default=None)
    parser.add_argument("--until-sim-time", type=float, default=None, metavar="SECONDS")
    parser.add_argument("--realtime", action="store_true")
    parser.add_argument("--no-clock", action="store_true",
                        help="never publish /clock (default: published at every simulated "
                             "step while the nodes are visible to other processes)")
    parser.add_argument("--isolated", action="store_true",
                        help="no network: nodes in this process only, no /clock (fastest)")
    parser.add_argument("--transport", default=None, choices=("inprocess", "zenoh", "dds"),
                        help="network transport to be visible on (default: "
                             "$POSEKIT_TRANSPORT or zenoh; inprocess = --isolated; dds joins "
                             "ROS 2 systems on DDS)")
    parser.add_argument("--zenoh", action="store_true", help="same as --transport zenoh")
    parser.add_argument("--record", default=None, metavar="DIR")
    parser.add_argument("--viewer", action="store_true")
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=8765)
    from posekit.cli.view_cmd import add_access_options

    add_access_options(parser)
    parser.add_argument("--plot", default=None, metavar="PNG")
    parser.add_argument("--save-images", default=None, metavar="DIR",
                        help="write the debug and camera images as PNG files into DIR")
    parser.add_argument("--show-args", "-s", action="store_true",
                        help="list the parameters / launch arguments with defaults and exit")
    parser.add_argument("--list", action="store_true", help="list the scenarios and exit")
    return parser


def _parse_assignment(text: str) -> tuple[str, Any]:
    from posekit.runtime.parameters import parse_parameter_value

    name, sep, value = text.partition(":=")
    if not sep or not name:
        raise _UsageError(f"parameters look like name:=value, got {text!r}")
    return name, parse_parameter_value(value)


def network_transport(ns: argparse.Namespace) -> str | None:
    """The network transport a launch is visible on, or None (isolated).

    An explicit choice (``--zenoh``, ``--transport``, $POSEKIT_TRANSPORT) whose package is
    missing is a one-line error; the implicit default (zenoh) without its package means an
    isolated run, said in one line.
    """
    from posekit.cli._extras import require
    from posekit.runtime.transport import registered_transports

    if ns.isolated:
        return None
    explicit = "zenoh" if ns.zenoh else (
        ns.transport or os.environ.get("POSEKIT_TRANSPORT", "").strip())
    chosen = (explicit or "zenoh").rpartition("+")[2]
    if chosen == "inprocess":
        return None
    if chosen not in registered_transports():
        raise _UsageError(f"unknown transport {chosen!r}; known: "
                          f"{', '.join(registered_transports())}")
    what = ("--zenoh" if ns.zenoh else f"--transport {chosen}" if ns.transport
            else f"POSEKIT_TRANSPORT={chosen}" if explicit else "the default network (zenoh)")
    problem = require("posekit launch", [(what, chosen)]) if chosen in ("zenoh", "dds") else None
    if problem and explicit:
        raise _UsageError(problem.removeprefix("posekit launch: "))
    if problem:
        prog = getattr(ns, "prog", "posekit launch")
        sys.stderr.write(f"{prog}: running isolated (not visible to other processes): "
                         f"{problem.removeprefix('posekit launch: ')}\n")
        return None
    return chosen


def _hooks(ns: argparse.Namespace, servers: list[Any]) -> list[Callable[[Any], Any]]:
    hooks: list[Callable[[Any], Any]] = []
    if ns.record:
        from posekit.bag.recorder import attach_recorder

        hooks.append(lambda run: attach_recorder(run, ns.record))
    if ns.save_images:
        from posekit.vision.nodes.image_saver import attach_image_saver

        hooks.append(lambda run: attach_image_saver(run, ns.save_images))
    if ns.viewer:
        from posekit.cli.view_cmd import attach_to_run

        def start_viewer(run: Any) -> None:
            server = attach_to_run(run, host=ns.host, port=ns.port,
                                   allow_hosts=ns.allow_host, allow_origins=ns.allow_origin)
            servers.append(server)
            sys.stdout.write(f"viewer: http://{ns.host}:{ns.port}/\n")
            sys.stdout.flush()

        hooks.append(start_viewer)
    return hooks


def _show_args(arguments: list[tuple[str, Any, str]]) -> None:
    """Print like ``ros2 launch -s``."""
    if not arguments:
        sys.stdout.write("No arguments.\n")
        return
    lines = ["Arguments (pass arguments as '<name>:=<value>'):", ""]
    for name, default, description in arguments:
        lines.append(f"    '{name}':")
        lines.append(f"        {description or 'no description given'}")
        lines.append("        (default: " + ("no default" if default is None
                                             else f"'{_format_value(default)}'") + ")")
        lines.append("")
    sys.stdout.write("\n".join(lines))


def _format_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_format_value(v) for v in value) + "]"
    return str(value)


def _scenario_arguments(name: str, params: dict[str, Any], seed: int) -> list[tuple[str, Any,
                                                                                    str]]:
    """Every parameter the scenario's nodes declare (``node.name`` where defaults differ)."""
    from posekit.launch import start
    from posekit.launch.scenarios import get_scenario
    from posekit.runtime.context import Context

    run = start(get_scenario(name).factory(params, seed), context=Context(),
                transport="inprocess", publish_clock=False)
    try:
        declared: dict[str, list[tuple[str, Any]]] = {}
        for node in run.nodes:
            for pname, param in sorted(node.get_parameters_by_prefix("").items()):
                if pname != "use_sim_time":
                    declared.setdefault(pname, []).append((node.get_name(), param.value))
    finally:
        run.shutdown()
    out: list[tuple[str, Any, str]] = []
    for pname, owners in sorted(declared.items()):
        values = {repr(v) for _, v in owners}
        if len(values) == 1:
            out.append((pname, owners[0][1],
                        "parameter of " + ", ".join(n for n, _ in owners)))
        else:
            out.extend((f"{n}.{pname}", v, f"parameter of {n}") for n, v in owners)
    return out


def main(argv: Sequence[str], *, prog: str = "posekit launch",
         ros_arguments: Any = None) -> int:
    """Run ``posekit launch``; returns the exit code.

    ``prog`` names the command in its messages (``posekit run`` runs through here);
    ``ros_arguments`` (a parsed :class:`~posekit.runtime.arguments.RosArguments`) reach every
    node the launch starts, as a process's ``--ros-args`` reach its nodes.
    """
    try:
        return _main(list(argv), prog, ros_arguments)
    except _UsageError as exc:
        sys.stderr.write(f"{prog}: {exc}\n")
        return 2


def _main(argv: list[str], prog: str = "posekit launch", ros_arguments: Any = None) -> int:
    if "--list" in argv:
        import posekit.demos.scenarios  # registers every scenario
        from posekit.launch.scenarios import get_scenario, scenario_names

        for name in scenario_names():
            sys.stdout.write(f"{name:<38}{get_scenario(name).description}\n")
        return 0
    ns = _parser(prog).parse_intermixed_args(argv)
    ns.prog, ns.ros_arguments = prog, ros_arguments
    from posekit.cli._extras import require
    from posekit.demos.scenarios import SCENARIO_EXTRAS

    target = next((w for w in ns.words if ":=" not in w), "")
    scenario_extra = SCENARIO_EXTRAS.get(target)
    problem = require("posekit launch", [
        *([(f"scenario {target}", scenario_extra)] if scenario_extra else []),
        *((flag, extra) for flag, extra, given in (
            ("--plot", "plot", ns.plot), ("--viewer", "viewer", ns.viewer),
            ("--record", "bag", ns.record), ("--save-images", "vision", ns.save_images),
        ) if given),
    ])
    if problem:  # before anything runs, not after a whole simulation
        raise _UsageError(problem.removeprefix("posekit launch: "))
    words = [w for w in ns.words if ":=" not in w or w.startswith("/") or w.endswith(".py")]
    assignments = [_parse_assignment(w) for w in ns.words if w not in words]
    params = dict(assignments + [_parse_assignment(p) for p in ns.param])
    if not words:
        raise _UsageError("which scenario? (posekit launch --list names them)")
    network = network_transport(ns)
    transport = "inprocess" if network is None else f"inprocess+{network}"

    if len(words) == 1 and (words[0].endswith(".py") or Path(words[0]).is_file()) and (
        Path(words[0]).is_file() or not words[0].endswith(".launch.py")
    ):
        if ros_arguments is not None:
            raise _UsageError("--ros-args apply to the nodes of posekit run")
        return _launch_file(ns, words[0], params, transport, network)

    import posekit.demos.scenarios  # noqa: F401 - registers every scenario
    from posekit.demos.lecture import resolve_launch
    from posekit.launch.scenarios import ScenarioError

    try:
        name = resolve_launch(words)
        if ns.show_args:
            _show_args(_scenario_arguments(name, params, ns.seed or 0))
            return 0
        return _launch_scenario(ns, name, params, transport, network)
    except ScenarioError as exc:
        sys.stderr.write(f"{prog}: {exc}\n")
        return 2


def _launch_scenario(ns: argparse.Namespace, name: str, params: dict[str, Any],
                     transport: str, network: str | None) -> int:
    from posekit.launch.scenarios import ScenarioError, get_scenario
    from posekit.robot.scenarios import run_robot_scenario

    seed = ns.seed or 0
    if get_scenario(name).follows_clock:
        if network is None:
            raise ScenarioError(f"'{name}' runs against a running world (start one in another "
                                "terminal, e.g. posekit launch empty_world --realtime); it "
                                "needs the network, not --isolated")
        for option in ("plot", "realtime", "no_clock"):
            if getattr(ns, option):
                raise ScenarioError(f"--{option.replace('_', '-')} applies to a launch that "
                                    f"runs a simulation; '{name}' follows a running world's "
                                    "clock")
        return _follow(ns, name, params, seed, transport)
    if ns.ros_arguments is not None:
        raise ScenarioError(f"--ros-args apply to the nodes of posekit run; '{name}' runs a "
                            "simulation (pass its parameters as name:=value)")
    servers: list[Any] = []
    try:
        # A viewer is for watching: pace the run to the wall clock.
        result = run_robot_scenario(
            name, params, seed=seed, until_sim_time=ns.until_sim_time,
            realtime=ns.realtime or ns.viewer, plot_path=ns.plot, on_start=_hooks(ns, servers),
            transport=transport, record=ns.plot is not None,  # odometry kept only for the plot
            publish_clock=False if ns.no_clock else None,
        )
    finally:
        for server in servers:
            server.stop()
    lines = [f"{result.name}: {result.sim_time:.2f} s simulated in {result.wall_time:.2f} s "
             f"wall ({result.speedup:.0f}x real time), seed {result.seed}"]
    if result.goal_reached_time is not None:
        lines.append(f"goal reached at t = {result.goal_reached_time:.2f} s")
    if result.rejected_count:
        lines.append(f"{result.rejected_count} cmd_vel messages rejected")
    if result.plot_path is not None:
        lines.append(f"odometry plot: {result.plot_path}")
    if ns.record:
        lines.append(f"bag: {ns.record}")
    if ns.save_images:
        lines.append(f"images: {ns.save_images}")
    sys.stdout.write("\n".join(lines) + "\n")
    return 0


def _follow(ns: argparse.Namespace, name: str, params: dict[str, Any], seed: int,
            transport: str) -> int:
    """A demo against a running world: its nodes follow that world's /clock."""
    from posekit.launch.scenarios import start_scenario

    run = start_scenario(name, params, seed, transport=transport, arguments=ns.ros_arguments)
    _run_started(ns, run, before=lambda started: _wait_for_clock(started, ns.prog))
    return 0


def _run_started(ns: argparse.Namespace, run: Any,
                 before: Callable[[Any], None] | None = None) -> None:
    """Attach the option hooks to a started launch, run it, and shut everything down.

    The hooks are the recorder, the image saver and the viewer; the run lasts until
    ``--until-sim-time`` (or Ctrl-C).
    """
    from posekit.launch.runner import run_until

    servers: list[Any] = []
    try:
        for hook in _hooks(ns, servers):
            hook(run)
        if before is not None:
            before(run)
        run_until(run, ns.until_sim_time, sim_time=True)
    except KeyboardInterrupt:
        pass
    finally:
        for server in servers:
            server.stop()
        run.shutdown()


CLOCK_HINT_AFTER_S = 5.0


def _wait_for_clock(run: Any, prog: str = "posekit launch") -> None:
    """Spin until the first node's clock moves; after a few seconds say what is missing."""
    import time

    clock = run.nodes[0].get_clock()
    hinted = False
    start = time.monotonic()
    while run.context.ok() and clock.now().nanoseconds == 0:
        run.executor.spin_once(timeout_sec=0.1)
        if not hinted and time.monotonic() - start > CLOCK_HINT_AFTER_S:
            hinted = True
            sys.stderr.write(f"{prog}: no /clock yet: these nodes follow a running "
                             "world's sim time; start one in another terminal (posekit launch "
                             "empty_world --realtime) on the same network\n")
            sys.stderr.flush()


def _own_clock(description: Any, params: dict[str, Any], network: str | None) -> bool | None:
    """Whether a launch file's run owns its sim clock (None: decide from the graph).

    As ``ros2 launch`` of nodes next to a running Gazebo: a launch with no world of its own
    follows the ``/clock`` already on the network, and with ``use_sim_time:=true`` follows
    the one to come; a launch that runs a world owns the clock (and is refused while
    another simulation publishes one). Isolated, there is no other clock to follow.
    """
    if description.has_clock_source():
        return True
    if network is None:
        if params.get("use_sim_time") is True:
            raise _UsageError("use_sim_time:=true follows a running simulation's /clock, "
                              "which an isolated launch cannot hear (drop --isolated)")
        return True
    return False if params.get("use_sim_time") is True else None


def _launch_file(ns: argparse.Namespace, path: str, params: dict[str, Any], transport: str,
                 network: str | None) -> int:
    from posekit.launch import (
        DeclareLaunchArgument,
        LaunchDescriptionError,
        load_launch_file,
        start,
    )
    from posekit.launch import Node as LaunchNode

    try:
        description = load_launch_file(path)
    except LaunchDescriptionError as exc:
        sys.stderr.write(f"posekit launch: {exc}\n")
        return 2
    declared = {e.name: e for e in description.entities if isinstance(e, DeclareLaunchArgument)}
    if ns.show_args:
        _show_args([(a.name, a.default_value, a.description) for a in declared.values()])
        return 0
    if ns.seed is not None:
        if "seed" not in declared:
            raise _UsageError(f"--seed: {path} declares no 'seed' launch argument (a launch "
                              "file seeds its nodes through its own arguments)")
        params.setdefault("seed", ns.seed)
    recorder_node: Any = None
    if ns.plot:
        from posekit.robot.nodes import OdometryRecorder

        description.add_action(LaunchNode(OdometryRecorder, name="odometry_recorder"))
    try:
        run = start(description, sim_time=True,
                    real_time_factor=1.0 if ns.realtime or ns.viewer else None,
                    launch_arguments=params, transport=transport,
                    publish_clock=False if ns.no_clock else None,
                    own_clock=_own_clock(description, params, network))
    except LaunchDescriptionError as exc:  # e.g. a parameter file it names: read before
        return report(exc, "posekit launch")  # any node starts, reported as a node's error
    if ns.plot:
        recorder_node = run.node("odometry_recorder")
    if run.follows_clock:
        sys.stderr.write(f"posekit launch: {path} runs no world of its own: its nodes follow "
                         "the running simulation's /clock\n")
        sys.stderr.flush()
        _run_started(ns, run, before=_wait_for_clock)
    else:
        _run_started(ns, run)
    if recorder_node is not None:
        from posekit.robot.plot import PlotError, plot_odometry

        try:
            written = plot_odometry(recorder_node.recording(), ns.plot, title=Path(path).name)
        except PlotError as exc:
            sys.stderr.write(f"posekit launch: --plot: {exc} (does {path} run the robot?)\n")
            return 2
        sys.stdout.write(f"odometry plot: {written}\n")
    return 0
