"""Simulated seconds per wall-clock second of the ROSbot P-controller scenario.

The reference is real time: Gazebo runs the course's worlds at a real-time factor of 1, so
the printed ratio *is* the speed-up over the lecture's simulator. The scenario is the
``p_controller`` launch (empty world, goal (5, 5, pi/2), default noise, no cameras): 100 Hz
drive + slip, 25 Hz IMU, 20 Hz wheel odometry, 20 Hz EKF, 20 Hz controller. Two paths run
in the same process, alternately:

* ``headless``: the models in one fixed-step loop (posekit.robot.headless, no runtime);
* ``nodes``: ``run_scenario("p_controller")`` -- five posekit nodes (world_simulation,
  wheel_odometry, ekf_node, p_controller) on the stepped sim-time executor and the in-process
  bus, as ``posekit launch p_controller`` runs it (no recorder, no /clock); ``nodes+rec``
  adds the odometry recorder that ``--plot`` uses.

``--profile`` prints where the node path spends its time (cProfile self time grouped by
package).

Run:  .venv/bin/python benchmarks/sim.py [--duration 60] [--repeats 5] [--profile]
"""

from __future__ import annotations

import argparse
import collections
import cProfile
import math
import platform
import pstats
import statistics
import time

from posekit.robot.headless import run_headless
from posekit.robot.scenarios import run_scenario
from posekit.runtime.logging import LogRecord, add_sink, remove_sink

GOAL_RATIO = 200.0


def _headless(duration: float, seed: int) -> tuple[float, float | None]:
    t0 = time.perf_counter()
    res = run_headless(
        scenario="p_controller", duration=duration, seed=seed, goal=(5.0, 5.0, math.pi / 2)
    )
    return duration / (time.perf_counter() - t0), res.goal_reached_time


def _nodes(duration: float, seed: int, record: bool) -> tuple[float, float | None]:
    t0 = time.perf_counter()
    res = run_scenario("p_controller", seed=seed, until_sim_time=duration, record=record)
    wall = time.perf_counter() - t0  # includes building the nodes
    reached_ns = res.node("p_controller").goal_reached_ns
    return duration / wall, None if reached_ns is None else reached_ns / 1e9


def _group(filename: str) -> str:
    path = filename.replace("\\", "/")
    for key, label in (
        ("posekit/robot/nodes/", "robot nodes (node glue)"),
        ("posekit/robot/", "robot models"),
        ("posekit/runtime/bus", "runtime bus (message copies)"),
        ("posekit/runtime/", "runtime executor/clock/entities"),
        ("posekit/msgs/", "message classes"),
        ("posekit/tf2", "tf2"),
        ("numpy", "numpy"),
    ):
        if key in path:
            return label
    return "other (builtins, dataclass inits, math)"


def _profile(duration: float, seed: int) -> None:
    profiler = cProfile.Profile()
    profiler.enable()
    run_scenario("p_controller", seed=seed, until_sim_time=duration, record=False)
    profiler.disable()
    stats = pstats.Stats(profiler)
    groups: collections.Counter[str] = collections.Counter()
    raw = stats.stats  # type: ignore[attr-defined]
    for (filename, _line, _name), (_cc, _nc, tottime, _ct, _callers) in raw.items():
        groups[_group(filename)] += tottime
    total = sum(groups.values())
    print(f"\nnode path, cProfile self time by package ({duration:.0f} s simulated):")
    for label, seconds in groups.most_common():
        print(f"  {100 * seconds / total:5.1f} %  {label}")
    print("\ntop functions by self time:")
    stats.sort_stats("tottime").print_stats(12)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=60.0, help="simulated seconds per run")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--profile", action="store_true", help="profile the node path")
    args = parser.parse_args()

    quiet: list[LogRecord] = []
    add_sink(quiet.append)
    from posekit.runtime.logging import _stderr_sink  # keep the benchmark output readable

    remove_sink(_stderr_sink)
    try:
        _headless(2.0, args.seed)  # warm-up (imports)
        _nodes(2.0, args.seed, True)
        ratios: dict[str, list[float]] = {"headless": [], "nodes": [], "nodes+rec": []}
        goals: dict[str, float | None] = {}
        for _ in range(args.repeats):
            r, goals["headless"] = _headless(args.duration, args.seed)
            ratios["headless"].append(r)
            r, goals["nodes"] = _nodes(args.duration, args.seed, False)
            ratios["nodes"].append(r)
            r, goals["nodes+rec"] = _nodes(args.duration, args.seed, True)
            ratios["nodes+rec"].append(r)
        print(f"python {platform.python_version()} on {platform.machine()}")
        print(
            f"p_controller scenario, {args.duration:.0f} s simulated x {args.repeats} runs "
            "(simulated s / wall s, i.e. times real time)"
        )
        for name, values in ratios.items():
            median = statistics.median(values)
            print(
                f"  {name:10s} median {median:6.0f}x  best {max(values):6.0f}x  "
                f"(goal reached at t = {goals[name]} s)"
            )
        paired = [n / h for n, h in zip(ratios["nodes"], ratios["headless"], strict=True)]
        print(f"  nodes / headless speed (paired runs, median): {statistics.median(paired):.2f}")
        for name in ("headless", "nodes"):
            met = statistics.median(ratios[name]) >= GOAL_RATIO
            print(f"goal >= {GOAL_RATIO:.0f}x ({name}): {'met' if met else 'NOT met'}")
        if args.profile:
            _profile(args.duration, args.seed)
    finally:
        remove_sink(quiet.append)
        add_sink(_stderr_sink)


if __name__ == "__main__":
    main()
