"""Simulated seconds per wall-clock second of the headless ROSbot loop (P-controller scenario).

The reference is real time: Gazebo runs the course's worlds at a real-time factor of 1, so
the printed ratio *is* the speed-up over the lecture's simulator. The scenario is the
``p_controller`` launch (empty world, goal (5, 5, pi/2), default noise, no cameras): 100 Hz
drive + slip, 25 Hz IMU, 20 Hz wheel odometry, 20 Hz EKF, 20 Hz controller.

Run:  .venv/bin/python benchmarks/sim.py [--duration 60] [--repeats 5]
"""

from __future__ import annotations

import argparse
import math
import platform
import statistics
import time

from posekit.robot.headless import run_headless

GOAL_RATIO = 200.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=60.0, help="simulated seconds per run")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    run_headless(scenario="p_controller", duration=2.0, seed=args.seed)  # warm-up (imports)
    ratios = []
    reached = None
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        res = run_headless(
            scenario="p_controller",
            duration=args.duration,
            seed=args.seed,
            goal=(5.0, 5.0, math.pi / 2),
        )
        wall = time.perf_counter() - t0
        ratios.append(args.duration / wall)
        reached = res.goal_reached_time
    best, median = max(ratios), statistics.median(ratios)
    print(f"python {platform.python_version()} on {platform.machine()}")
    print(
        f"p_controller scenario, {args.duration:.0f} s simulated x {args.repeats} runs "
        f"(goal reached at t = {reached} s)"
    )
    print(f"simulated s / wall s: median {median:.0f}x, best {best:.0f}x real time")
    print(f"goal >= {GOAL_RATIO:.0f}x: {'met' if median >= GOAL_RATIO else 'NOT met'}")


if __name__ == "__main__":
    main()
