"""``posekit plot odometry``: ground truth vs wheel vs filtered odometry as a PNG.

Either from a saved recording (``posekit plot odometry RUN.npz -o OUT.png``) or by running a
scenario first (``posekit plot odometry --scenario random_mover --until-sim-time 120``).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

__all__ = ["main_odometry"]


def main_odometry(argv: Sequence[str]) -> int:
    """Write the odometry plot; returns the exit code."""
    parser = argparse.ArgumentParser(prog="posekit plot odometry", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("recording", nargs="?", help="an .npz saved by an odometry recorder")
    parser.add_argument("--scenario", help="run this scenario and plot its odometry")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--until-sim-time", type=float, default=60.0, metavar="SECONDS")
    parser.add_argument("-o", "--output", default="odometry.png")
    ns = parser.parse_args(list(argv))
    if (ns.recording is None) == (ns.scenario is None):
        parser.error("give either a recording file or --scenario NAME")
    from posekit.cli._extras import require

    problem = require("posekit plot", [("plotting", "plot")])
    if problem:  # before a scenario runs
        print(problem, file=sys.stderr)
        return 2

    from posekit.robot.plot import PlotError, plot_odometry_file

    try:
        if ns.recording is not None:
            path = plot_odometry_file(ns.recording, ns.output)
        else:
            from posekit.demos.scenarios import run_scenario
            from posekit.robot.scenarios import ScenarioError

            try:
                result = run_scenario(ns.scenario, seed=ns.seed,
                                      until_sim_time=ns.until_sim_time, plot_path=ns.output)
            except ScenarioError as exc:
                sys.stderr.write(f"posekit plot: {exc}\n")
                return 2
            assert result.plot_path is not None
            path = result.plot_path
    except PlotError as exc:
        sys.stderr.write(f"posekit plot: {exc}\n")
        return 1
    sys.stdout.write(f"wrote {path}\n")
    return 0
