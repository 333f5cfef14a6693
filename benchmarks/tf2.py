"""Benchmark posekit.tf2 against pytransform3d's TransformManager / TemporalTransformManager.

Run: ``.venv/bin/python benchmarks/tf2.py`` (``--quick`` for a smoke run). Not a test: it prints
medians and ratios measured in one run on this machine; goals are in docs/performance.md.

Scene: a chain f0 -> f1 -> f2 -> f3 -> f4 (4 hops), every edge dynamic with 100 samples
10 ms apart (yaw and translation changing). "1-hop" is lookup(f0 <- f1), "4-hop" is
lookup(f0 <- f4); "latest" asks for Time() (tf2's latest common time), "interpolated" for a
stamp between samples. pytransform3d's equivalents: TransformManager.get_transform on the
newest samples (latest) and TemporalTransformManager.get_transform_at_time (interpolated,
its ScLERP); note its argument order is (from, to) = (source, target).
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from posekit.msgs.geometry_msgs import TransformStamped
from posekit.tf2 import Buffer
from posekit.time import Time

S = 1_000_000_000
FRAMES = ["f0", "f1", "f2", "f3", "f4"]
N_SAMPLES = 100
T0 = 1_700_000_000 * S
DT = 10_000_000


def sample(
    edge: int, i: int
) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
    yaw = 0.02 * i + 0.5 * edge
    roll = 0.01 * i
    q = (math.sin(roll / 2), 0.0, math.sin(yaw / 2), math.cos(yaw / 2))
    n = math.sqrt(sum(c * c for c in q))
    return (0.5 + 0.01 * i, 0.1 * edge, 0.02), (q[0] / n, q[1] / n, q[2] / n, q[3] / n)


def make_msg(
    parent: str, child: str, ns: int, t: tuple[float, ...], q: tuple[float, ...]
) -> TransformStamped:
    m = TransformStamped()
    m.header.frame_id = parent
    m.child_frame_id = child
    m.header.stamp.sec, m.header.stamp.nanosec = divmod(ns, S)
    tr = m.transform
    tr.translation.x, tr.translation.y, tr.translation.z = t
    tr.rotation.x, tr.rotation.y, tr.rotation.z, tr.rotation.w = q
    return m


def per_call_us(fn: Callable[[], Any], calls: int, rounds: int) -> float:
    """Median over rounds of the mean CPU time per call, in microseconds.

    CPU time of this process (``time.process_time_ns``), not wall time: the benchmark machine
    is shared, and wall time would mostly measure how long we waited for a core.
    """
    fn()
    times = []
    for _ in range(rounds):
        start = time.process_time_ns()
        for _ in range(calls):
            fn()
        times.append((time.process_time_ns() - start) / calls / 1e3)
    return statistics.median(times)


def build_posekit() -> tuple[Buffer, list[TransformStamped]]:
    buf = Buffer()
    msgs = []
    for i in range(N_SAMPLES):
        for e in range(4):
            t, q = sample(e, i)
            msgs.append(make_msg(FRAMES[e], FRAMES[e + 1], T0 + i * DT, t, q))
    for m in msgs:
        buf.set_transform(m, "bench")
    return buf, msgs


def build_pytransform3d() -> tuple[Any, Any]:
    from pytransform3d.transform_manager import (
        NumpyTimeseriesTransform,
        TemporalTransformManager,
        TransformManager,
    )
    from pytransform3d.transformations import transform_from_pq

    ttm = TemporalTransformManager()
    tm = TransformManager()
    times = (np.arange(N_SAMPLES) * DT) / S  # seconds since T0 (float time axis)
    for e in range(4):
        pqs = []
        for i in range(N_SAMPLES):
            t, q = sample(e, i)
            pqs.append([*t, q[3], q[0], q[1], q[2]])  # pytransform3d pq: x y z qw qx qy qz
        pqs_arr = np.array(pqs)
        # pytransform3d names transforms from -> to: child -> parent
        ttm.add_transform(FRAMES[e + 1], FRAMES[e], NumpyTimeseriesTransform(times, pqs_arr))
        tm.add_transform(FRAMES[e + 1], FRAMES[e], transform_from_pq(pqs_arr[-1]))
    return tm, ttm


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="few rounds (smoke run)")
    args = parser.parse_args()
    calls, rounds = (200, 3) if args.quick else (2000, 15)
    n_batch = 10_000 if args.quick else 100_000

    buf, _ = build_posekit()
    tm, ttm = build_pytransform3d()
    t_interp = Time(nanoseconds=T0 + 50 * DT + 3_456_789)
    t_interp_s = (50 * DT + 3_456_789) / S
    latest = Time()

    rows: list[tuple[str, float, float | None, str]] = []

    def row(name: str, ours: float, ref: float | None, unit: str) -> None:
        rows.append((name, ours, ref, unit))

    for hops, target, source in ((1, "f0", "f1"), (4, "f0", "f4")):
        ours = per_call_us(
            lambda t=target, s=source: buf.lookup_transform(t, s, latest), calls, rounds
        )
        ref = per_call_us(lambda t=target, s=source: tm.get_transform(s, t), calls, rounds)
        row(f"lookup {hops}-hop latest", ours, ref, "us/call")
        ours = per_call_us(
            lambda t=target, s=source: buf.lookup_transform(t, s, t_interp), calls, rounds
        )
        ref = per_call_us(
            lambda t=target, s=source: ttm.get_transform_at_time(s, t, t_interp_s),
            max(calls // 10, 20),
            rounds,
        )
        row(f"lookup {hops}-hop interpolated", ours, ref, "us/call")

    # set_transform: re-inserting stored samples (the exact-duplicate path) and fresh stamps
    fresh_buf = Buffer()
    fresh = [
        make_msg("a", "b", T0 + i * DT, (1.0, 2.0, 3.0), (0.0, 0.0, 0.6, 0.8))
        for i in range(calls * rounds + 1)
    ]
    it = iter(fresh)
    ours = per_call_us(lambda: fresh_buf.set_transform(next(it), "bench"), calls, rounds)
    from pytransform3d.transformations import transform_from_pq

    a2b = transform_from_pq(np.array([1.0, 2.0, 3.0, 0.8, 0.0, 0.0, 0.6]))
    ref = per_call_us(lambda: tm.add_transform("b", "a", a2b), calls, rounds)
    row("set_transform (new stamp)", ours, ref, "us/call")

    stamps_ns = T0 + np.arange(n_batch, dtype=np.int64) * ((N_SAMPLES - 1) * DT) // (n_batch - 1)
    stamps_s = (stamps_ns - T0) / S
    batch_rounds = 3 if args.quick else 7
    ours = per_call_us(lambda: buf.lookup_transforms("f0", "f4", stamps_ns), 1, batch_rounds)
    ref = per_call_us(lambda: ttm.get_transform_at_time("f4", "f0", stamps_s), 1, batch_rounds)
    row(f"lookup_transforms 4-hop, {n_batch} stamps", n_batch / ours, n_batch / ref, "M lookups/s")

    print(f"posekit.tf2 vs pytransform3d (python {sys.version.split()[0]}, numpy {np.__version__})")
    print(f"{'case':42s} {'posekit':>12s} {'pytransform3d':>14s} {'speed-up':>9s}  unit")
    for name, ours_v, ref_v, unit in rows:
        if unit.startswith("M"):
            speed = ours_v / ref_v if ref_v else float("nan")
        else:
            speed = ref_v / ours_v if ref_v else float("nan")
        ref_txt = f"{ref_v:14.2f}" if ref_v is not None else f"{'-':>14s}"
        print(f"{name:42s} {ours_v:12.2f} {ref_txt} {speed:8.1f}x  {unit}")
    print("goals: 4-hop interpolated <= 5 us, set_transform <= 3 us, lookup_transforms >= 1.5 M/s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
