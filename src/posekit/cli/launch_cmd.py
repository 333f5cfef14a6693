"""``posekit launch SCENARIO|FILE.py``: run a named scenario or a launch file in one process.

Scenario options: ``--param name:=value`` (or bare ``name:=value``; ``node.name:=value``
reaches one node), ``--seed N``, ``--until-sim-time S`` (stop after S simulated seconds),
``--realtime`` (pace to the wall clock; default is as fast as possible), ``--transport
zenoh|dds`` (nodes on the Zenoh or DDS transport so other processes, ``posekit`` tools and, over
DDS, real ROS 2 nodes see them; ``--zenoh`` is ``--transport zenoh``), ``--record DIR`` (a
ROS 2 bag), ``--viewer`` (serve the browser viewer), ``--plot PNG`` (odometry plot),
``--save-images DIR`` (debug images as PNG, rqt_image_view's role).
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

__all__ = ["main"]


def _parse_assignment(text: str) -> tuple[str, Any]:
    from posekit.runtime.parameters import parse_parameter_value

    if ":=" not in text:
        raise argparse.ArgumentTypeError(f"parameters look like name:=value, got {text!r}")
    name, value = text.split(":=", 1)
    return name, parse_parameter_value(value)


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="posekit launch", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("target", help="scenario name, or a launch file (FILE.py)")
    parser.add_argument("assignments", nargs="*", type=_parse_assignment,
                        help="name:=value parameters (scenario) or launch arguments (file)")
    parser.add_argument("--param", "-p", action="append", default=[], type=_parse_assignment,
                        metavar="NAME:=VALUE")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--until-sim-time", type=float, default=None, metavar="SECONDS")
    parser.add_argument("--realtime", action="store_true")
    parser.add_argument("--zenoh", action="store_true", help="same as --transport zenoh")
    parser.add_argument("--transport", default=None, choices=("inprocess", "zenoh", "dds"),
                        help="carry the nodes' messages over this transport (dds: join ROS 2 "
                             "systems on DDS)")
    parser.add_argument("--record", default=None, metavar="DIR")
    parser.add_argument("--viewer", action="store_true")
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=8765)
    parser.add_argument("--plot", default=None, metavar="PNG")
    parser.add_argument("--save-images", default=None, metavar="DIR",
                        help="write the debug and camera images as PNG files into DIR")
    parser.add_argument("--list", action="store_true", help="list the scenarios and exit")
    return parser


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
            server = attach_to_run(run, host=ns.host, port=ns.port)
            servers.append(server)
            sys.stdout.write(f"viewer: http://{ns.host}:{ns.port}/\n")
            sys.stdout.flush()

        hooks.append(start_viewer)
    return hooks


def main(argv: Sequence[str]) -> int:
    """Run ``posekit launch``; returns the exit code."""
    argv = list(argv)
    if "--list" in argv:
        from posekit.demos.scenarios import get_scenario, scenario_names

        for name in scenario_names():
            sys.stdout.write(f"{name:<28}{get_scenario(name).description}\n")
        return 0
    ns = _parser().parse_args(argv)
    from posekit.cli._extras import require

    problem = require("posekit launch", [
        (flag, extra) for flag, extra, given in (
            ("--plot", "plot", ns.plot), ("--viewer", "viewer", ns.viewer),
            ("--zenoh", "zenoh", ns.zenoh), ("--transport dds", "dds", ns.transport == "dds"),
            ("--transport zenoh", "zenoh", ns.transport == "zenoh"), ("--record", "bag", ns.record),
            ("--save-images", "vision", ns.save_images),
        ) if given
    ])
    if problem:  # before anything runs, not after a whole simulation
        sys.stderr.write(problem + "\n")
        return 2
    if ns.zenoh or ns.transport:
        os.environ["POSEKIT_TRANSPORT"] = "zenoh" if ns.zenoh else ns.transport
    params = dict(ns.assignments + ns.param)

    if ns.target.endswith(".py") or Path(ns.target).is_file():
        from posekit.launch import LaunchDescriptionError, run_launch_file

        try:
            run_launch_file(ns.target, duration=ns.until_sim_time, sim_time=True,
                            real_time_factor=1.0 if ns.realtime else None,
                            launch_arguments=params)
        except LaunchDescriptionError as exc:
            sys.stderr.write(f"posekit launch: {exc}\n")
            return 2
        return 0

    from posekit.demos.scenarios import run_scenario
    from posekit.robot.scenarios import ScenarioError

    servers: list[Any] = []
    try:
        # A viewer is for watching: pace the run to the wall clock.
        result = run_scenario(
            ns.target, params, seed=ns.seed, until_sim_time=ns.until_sim_time,
            realtime=ns.realtime or ns.viewer, plot_path=ns.plot, on_start=_hooks(ns, servers),
            record=ns.plot is not None,  # odometry is kept in memory only for the plot
        )
    except ScenarioError as exc:
        sys.stderr.write(f"posekit launch: {exc}\n")
        return 2
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
