"""Benchmark posekit.tf2 against tf2's C++ core and pytransform3d.

Run: ``.venv/bin/python benchmarks/tf2.py`` (``--quick`` for a smoke run, ``--no-pytransform3d``
for the tf2 comparison alone). Not a test: it prints times and ratios measured in one run on
this machine; goals are in docs/performance.md.

Scene: a chain world -> f1 -> f2 -> f3 -> f4 (4 hops), every edge dynamic with 100 samples
10 ms apart (yaw and translation changing). "1-hop" is lookup(world <- f1), "4-hop" is
lookup(world <- f4), "reversed" lookup(f4 <- world); "latest" asks for Time() (tf2's latest
common time), "interpolated" for a stamp between samples.

Two references:

* tf2 C++ (first table): the real tf2 ``BufferCore`` through the ``tf2_py`` binding of
  Debian's ``python3-tf2`` (ROS 1 messages, ``/usr/bin/python3``), run in a child process
  with the same scene. Rounds alternate between posekit (``Buffer``, what user code calls) and
  the child, op by op, and each figure is the best round (CPU time of its own process per
  call). Where ``/usr/bin/python3`` cannot import ``tf2_py`` the table is skipped with the
  reason.
* pytransform3d (second table): TransformManager.get_transform on the newest samples (latest)
  and TemporalTransformManager.get_transform_at_time (interpolated, its ScLERP); its argument
  order is (from, to) = (source, target). Medians of rounds.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from posekit.msgs.geometry_msgs import TransformStamped
from posekit.tf2 import Buffer
from posekit.time import Time

S = 1_000_000_000
FRAMES = ["world", "f1", "f2", "f3", "f4"]
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


# The tf2 C++ side, run by /usr/bin/python3 in a child process. It reads one JSON command per
# line on stdin and answers one JSON line: {"scene": [[parent, child, ns, t, q], ...]} builds
# the buffer; {"op": name, "calls": n} runs one timed round of n calls and answers the mean
# CPU time per call in us. set_transform rounds use fresh, increasing stamps (tf2 warns on
# every repeated stamp); the child's stderr goes to a file that is only shown on failure.
TF2_CPP_CHILD = r"""
import json, sys, time
import rospy, tf2_py
from geometry_msgs.msg import TransformStamped

def msg(parent, child, ns, t, q):
    m = TransformStamped()
    m.header.frame_id = parent
    m.child_frame_id = child
    m.header.stamp = rospy.Time(ns // 1000000000, ns % 1000000000)
    tr = m.transform
    tr.translation.x, tr.translation.y, tr.translation.z = t
    tr.rotation.x, tr.rotation.y, tr.rotation.z, tr.rotation.w = q
    return m

buf = None
fresh = None
out = sys.stdout
for line in sys.stdin:
    cmd = json.loads(line)
    if "scene" in cmd:
        buf = tf2_py.BufferCore(rospy.Duration(cmd["cache_s"]))
        for row in cmd["scene"]:
            buf.set_transform(msg(*row), "bench")
        fresh = tf2_py.BufferCore(rospy.Duration(cmd["cache_s"]))
        latest = rospy.Time(0)
        t_interp = rospy.Time(cmd["t_interp"] // 1000000000, cmd["t_interp"] % 1000000000)
        varying = [rospy.Time(ns // 1000000000, ns % 1000000000) for ns in cmd["varying"]]
        next_ns = cmd["t0"]
        out.write(json.dumps({"tf2_py": tf2_py.__file__}) + "\n")
        out.flush()
        continue
    op, calls = cmd["op"], cmd["calls"]
    lookup = buf.lookup_transform_core
    if op == "set_transform":
        msgs = []
        for _ in range(calls):
            msgs.append(msg("a", "b", next_ns, (1.0, 2.0, 3.0), (0.0, 0.0, 0.6, 0.8)))
            next_ns += cmd["dt"]
        it = iter(msgs)
        set_transform = fresh.set_transform
        start = time.process_time_ns()
        for m in it:
            set_transform(m, "bench")
        took = time.process_time_ns() - start
    else:
        target, source, when = cmd["target"], cmd["source"], cmd["when"]
        if when == "varying":
            stamps = varying[:calls]
            start = time.process_time_ns()
            for stamp in stamps:
                lookup(target, source, stamp)
            took = time.process_time_ns() - start
        else:
            stamp = latest if when == "latest" else t_interp
            start = time.process_time_ns()
            for _ in range(calls):
                lookup(target, source, stamp)
            took = time.process_time_ns() - start
    out.write(json.dumps({"us": took / calls / 1e3}) + "\n")
    out.flush()
"""

TF2_PYTHON = "/usr/bin/python3"

# (name, target, source, when) of the lookups compared with tf2 C++: "latest" = Time(),
# "fixed" = the same interpolated stamp every call, "varying" = a different interpolated
# stamp every call (posekit then cannot answer from the path's memo of its last result)
TF2_LOOKUPS = (
    ("lookup 1 hop, latest", "world", "f1", "latest"),
    ("lookup 4 hops, interpolated", "world", "f4", "fixed"),
    ("lookup 4 hops, interpolated, reversed", "f4", "world", "fixed"),
    ("lookup 4 hops, interp., new stamp per call", "world", "f4", "varying"),
    ("lookup 4 hops, interp., reversed, new stamp", "f4", "world", "varying"),
)


class Tf2Cpp:
    """The child process holding tf2's C++ BufferCore (see TF2_CPP_CHILD)."""

    def __init__(self, scene: list[list[Any]], t_interp_ns: int, varying: list[int]) -> None:
        # closed by close(), which the caller's finally runs
        self._stderr = tempfile.TemporaryFile()  # noqa: SIM115
        self._proc = subprocess.Popen(
            [TF2_PYTHON, "-c", TF2_CPP_CHILD],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=self._stderr,
            text=True,
        )
        reply = self._ask(
            {"scene": scene, "cache_s": 10, "t_interp": t_interp_ns, "t0": T0, "dt": DT,
             "varying": varying}
        )
        self.origin = str(reply["tf2_py"])

    def _ask(self, cmd: dict[str, Any]) -> dict[str, Any]:
        assert self._proc.stdin is not None
        assert self._proc.stdout is not None
        self._proc.stdin.write(json.dumps(cmd) + "\n")
        self._proc.stdin.flush()
        line = self._proc.stdout.readline()
        if not line:
            self._stderr.seek(0)
            tail = self._stderr.read().decode(errors="replace").strip().splitlines()[-5:]
            raise RuntimeError("tf2 C++ child failed: " + " | ".join(tail))
        reply: dict[str, Any] = json.loads(line)
        return reply

    def round_us(self, op: str, calls: int, **args: Any) -> float:
        """Mean CPU us per call of one round of ``calls`` calls in the child."""
        return float(self._ask({"op": op, "calls": calls, "dt": DT, **args})["us"])

    def close(self) -> None:
        if self._proc.stdin is not None:
            self._proc.stdin.close()
        try:
            self._proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self._proc.kill()
            self._proc.wait()
        self._stderr.close()


def tf2_cpp_unavailable() -> str | None:
    """Why the tf2 C++ comparison cannot run here, or None if it can."""
    if not os.path.exists(TF2_PYTHON):
        return f"{TF2_PYTHON} does not exist"
    probe = subprocess.run(
        [TF2_PYTHON, "-c", "import tf2_py, rospy, geometry_msgs.msg"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    if probe.returncode:
        last = (probe.stderr.strip().splitlines() or ["unknown error"])[-1]
        return f"{TF2_PYTHON} cannot import tf2_py ({last}); apt-get install python3-tf2"
    return None


def compare_tf2_cpp(calls: int, rounds: int) -> None:
    """Print posekit vs tf2 C++ for the single-call operations, rounds interleaved."""
    why = tf2_cpp_unavailable()
    if why is not None:
        print(f"tf2 C++ comparison skipped: {why}")
        return
    buf, msgs = build_posekit()
    scene = [
        [
            m.header.frame_id,
            m.child_frame_id,
            m.header.stamp.sec * S + m.header.stamp.nanosec,
            [m.transform.translation.x, m.transform.translation.y, m.transform.translation.z],
            [m.transform.rotation.x, m.transform.rotation.y, m.transform.rotation.z,
             m.transform.rotation.w],
        ]
        for m in msgs
    ]
    t_interp_ns = T0 + 50 * DT + 3_456_789
    # distinct stamps strictly inside the samples, none on a sample
    varying_ns = [T0 + DT // 2 + (i * 7_919_003) % ((N_SAMPLES - 2) * DT) for i in range(calls)]
    cpp = Tf2Cpp(scene, t_interp_ns, varying_ns)
    try:
        latest = Time()
        t_interp = Time(nanoseconds=t_interp_ns)
        varying = [Time(nanoseconds=ns) for ns in varying_ns]
        fresh_buf = Buffer()
        next_ns = [T0]

        def posekit_round(op: str, target: str = "", source: str = "", when: str = "") -> float:
            if op == "set_transform":
                batch = []
                for _ in range(calls):
                    batch.append(make_msg("a", "b", next_ns[0], (1.0, 2.0, 3.0),
                                          (0.0, 0.0, 0.6, 0.8)))
                    next_ns[0] += DT
                set_transform = fresh_buf.set_transform
                start = time.process_time_ns()
                for m in batch:
                    set_transform(m, "bench")
                return (time.process_time_ns() - start) / calls / 1e3
            lookup = buf.lookup_transform
            if when == "varying":
                lookup(target, source, t_interp)
                start = time.process_time_ns()
                for stamp in varying:
                    lookup(target, source, stamp)
                return (time.process_time_ns() - start) / calls / 1e3
            stamp = latest if when == "latest" else t_interp
            lookup(target, source, stamp)
            start = time.process_time_ns()
            for _ in range(calls):
                lookup(target, source, stamp)
            return (time.process_time_ns() - start) / calls / 1e3

        ops: list[tuple[str, str, dict[str, Any]]] = [
            (name, "lookup", {"target": tg, "source": sc, "when": when})
            for name, tg, sc, when in TF2_LOOKUPS
        ]
        ops.append(("set_transform (new stamp)", "set_transform", {}))
        best: dict[str, list[float]] = {name: [math.inf, math.inf] for name, _, _ in ops}
        for _ in range(rounds):
            for name, op, args in ops:
                ours = posekit_round(
                    op, args.get("target", ""), args.get("source", ""), args.get("when", "")
                )
                ref = cpp.round_us(op, calls, **args)
                best[name][0] = min(best[name][0], ours)
                best[name][1] = min(best[name][1], ref)
    finally:
        cpp.close()
    print(f"posekit.tf2 Buffer vs tf2 C++ BufferCore ({cpp.origin} under {TF2_PYTHON})")
    print(f"best of {rounds} interleaved rounds of {calls} calls, CPU us per call of each process")
    print(f"{'operation':42s} {'posekit':>9s} {'tf2 C++':>9s} {'tf2/posekit':>12s}")
    for name, (ours, ref) in best.items():
        print(f"{name:42s} {ours:9.2f} {ref:9.2f} {ref / ours:11.2f}x")
    print("goal: every ratio >= 1.0 (posekit at least as fast as tf2's C++ core via tf2_py)")


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
    parser.add_argument(
        "--no-pytransform3d", action="store_true", help="only the tf2 C++ comparison"
    )
    args = parser.parse_args()
    calls, rounds = (200, 3) if args.quick else (2000, 15)
    n_batch = 10_000 if args.quick else 100_000

    compare_tf2_cpp(calls, 3 if args.quick else 7)
    if args.no_pytransform3d:
        return 0
    print()

    buf, _ = build_posekit()
    tm, ttm = build_pytransform3d()
    t_interp = Time(nanoseconds=T0 + 50 * DT + 3_456_789)
    t_interp_s = (50 * DT + 3_456_789) / S
    latest = Time()

    rows: list[tuple[str, float, float | None, str]] = []

    def row(name: str, ours: float, ref: float | None, unit: str) -> None:
        rows.append((name, ours, ref, unit))

    for hops, target, source in ((1, "world", "f1"), (4, "world", "f4")):
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
    ours = per_call_us(lambda: buf.lookup_transforms("world", "f4", stamps_ns), 1, batch_rounds)
    ref = per_call_us(lambda: ttm.get_transform_at_time("f4", "world", stamps_s), 1, batch_rounds)
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
