"""``posekit plot odometry|topic``: plots of runs and recordings, as PNG files.

* ``posekit plot odometry RECORDING [-o OUT.png] [--topics T ...]``: ground truth vs wheel vs
  filtered odometry (paths, position and yaw errors against ground truth). RECORDING is a
  rosbag2 directory or an ``.mcap`` file (every ``nav_msgs/msg/Odometry``, ``PoseStamped``
  or ``PoseWithCovarianceStamped`` topic is a series), or an ``.npz`` saved by the odometry
  recorder. ``--scenario NAME`` runs a scenario first instead.
* ``posekit plot topic RECORDING /topic --field pose.pose.position.x [--field ...]``: the
  chosen numeric fields of one topic against time (PlotJuggler's view of a bag), with
  ``--header-stamp`` to use ``header.stamp`` instead of the bag timestamp.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

__all__ = ["main_odometry", "main_topic"]


def main_odometry(argv: Sequence[str]) -> int:
    """Write the odometry plot; returns the exit code."""
    parser = argparse.ArgumentParser(prog="posekit plot odometry", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("recording", nargs="?",
                        help="a rosbag2 directory, an .mcap file, or an .npz saved by an "
                             "odometry recorder")
    parser.add_argument("--topics", nargs="+", default=None, metavar="TOPIC",
                        help="pose topics of the bag to plot (default: all of them)")
    parser.add_argument("--scenario", help="run this scenario and plot its odometry")
    parser.add_argument("--seed", type=int, default=0, help="scenario seed (with --scenario)")
    parser.add_argument("--until-sim-time", type=float, default=60.0, metavar="SECONDS",
                        help="simulated seconds to run (with --scenario; default 60)")
    parser.add_argument("-o", "--output", default="odometry.png",
                        help="PNG to write (default odometry.png)")
    ns = parser.parse_args(list(argv))
    if (ns.recording is None) == (ns.scenario is None):
        parser.error("give either a recording (bag directory, .mcap or .npz) or --scenario NAME")
    from posekit.cli._extras import require

    problem = require("posekit plot", [("plotting", "plot")])
    if problem:  # before a scenario runs
        print(problem, file=sys.stderr)
        return 2

    from posekit.robot.plot import plot_odometry, plot_odometry_file

    if ns.recording is not None:
        recording = Path(ns.recording)
        if recording.is_dir() or recording.suffix == ".mcap":
            from posekit.bag.series import odometry_recording

            path = plot_odometry(odometry_recording(recording, ns.topics), ns.output,
                                 title=f"odometry: {recording.name}")
        else:
            path = plot_odometry_file(recording, ns.output)
    else:
        import posekit.demos.scenarios  # noqa: F401 - registers every scenario
        from posekit.robot.scenarios import run_robot_scenario

        result = run_robot_scenario(ns.scenario, seed=ns.seed, until_sim_time=ns.until_sim_time,
                              plot_path=ns.output)
        assert result.plot_path is not None
        path = result.plot_path
    sys.stdout.write(f"wrote {path}\n")
    return 0


def main_topic(argv: Sequence[str]) -> int:
    """``posekit plot topic RECORDING TOPIC --field F [--field F ...]``."""
    parser = argparse.ArgumentParser(
        prog="posekit plot topic",
        description="Plot numeric fields of one recorded topic against time, as a PNG.")
    parser.add_argument("recording", help="a rosbag2 directory or an .mcap file")
    parser.add_argument("topic", help="the topic, e.g. /odometry/filtered")
    parser.add_argument("--field", "-f", action="append", required=True, dest="fields",
                        help="a dotted field path, e.g. pose.pose.position.x (repeatable)")
    parser.add_argument("--header-stamp", action="store_true",
                        help="x axis from header.stamp (default: the bag timestamp)")
    parser.add_argument("--subplots", action="store_true",
                        help="one panel per field (default: all fields on one axes)")
    parser.add_argument("-o", "--output", default="topic.png",
                        help="PNG to write (default topic.png)")
    ns = parser.parse_args(list(argv))
    from posekit.cli._extras import require

    problem = require("posekit plot topic", [("plotting", "plot"), ("reading bags", "bag")])
    if problem:
        print(problem, file=sys.stderr)
        return 2

    from posekit.bag.series import field_series
    from posekit.robot.plot import _pyplot

    t, values = field_series(ns.recording, ns.topic, ns.fields, header_stamp=ns.header_stamp)
    plt = _pyplot()
    rows = len(ns.fields) if ns.subplots else 1
    fig, axes = plt.subplots(rows, 1, figsize=(10, 3 + 2 * rows), squeeze=False, sharex=True)
    try:
        elapsed = t - t[0] if len(t) else t
        for i, name in enumerate(ns.fields):
            ax = axes[i if ns.subplots else 0][0]
            ax.plot(elapsed, values[name], label=name, lw=1.2)
            ax.grid(True, alpha=0.3)
            ax.legend(loc="best", fontsize=8)
        start = f"{t[0]:.3f} s" if len(t) else "no messages"
        axes[-1][0].set_xlabel(f"time since the first message [s] (t0 = {start}, "
                               f"{'header.stamp' if ns.header_stamp else 'bag time'})")
        fig.suptitle(f"{ns.topic} ({Path(ns.recording).name})")
        fig.tight_layout()
        out = Path(ns.output)
        out.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(out, dpi=100, format="png")
    finally:
        plt.close(fig)
    sys.stdout.write(f"wrote {out} ({len(t)} messages)\n")
    return 0
