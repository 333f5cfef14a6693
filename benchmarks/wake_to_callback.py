"""A lone DDS message's path in the subscriber: from the wait set's wake-up to the callback.

Run: ``.venv/bin/python benchmarks/wake_to_callback.py`` (6 rounds, about 40 s);
``--rounds N``, ``--messages N``, ``--steps`` (posekit's wake-up to callback split at the
take, the decode and the executor's selection; the marks themselves add about 1 us each).

Two subscriber processes receive the same ``geometry_msgs/TransformStamped`` stream, one
message per millisecond from one publisher process (cyclonedds' C layer writing rosbags'
CDR, as ``benchmarks/transport.py``'s ``raw``), so each message arrives alone in caches gone
cold:

* ``raw``: a Cyclone wait set loop that takes the sample, decodes it with rosbags and calls
  the callback (``benchmarks/transport.py``'s ``raw`` mode);
* ``posekit``: a ``Node`` subscription run by ``SingleThreadedExecutor.spin()``.

Each prints the median over the messages (the first tenth left out) of the one-way latency
(receive wall clock minus the stamp written before publishing) and of the time from the
return of its wait set's wait to the callback. The process started first is served first
by the publisher's writer (it matched first): both orders alternate between rounds, and the
table shows them apart.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from typing import Any

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import transport as bench

RATE_HZ = 1000.0


def child_pub(count: int) -> None:
    publish, _, _ = bench._endpoints("dds", "raw", "tf", "pub", "")
    assert publish is not None
    period, next_at = 1.0 / RATE_HZ, time.perf_counter()
    for _ in range(count):
        publish()
        next_at += period
        ahead = next_at - time.perf_counter() - bench.PACING_SPIN_S
        if ahead > 0:
            time.sleep(ahead)
        while time.perf_counter() < next_at:
            pass
    sys.stdin.read()  # until the subscribers are done


def child_sub(mode: str, count: int, steps: bool) -> None:
    now = time.perf_counter_ns
    marks: dict[str, int] = {}
    rows: list[dict[str, int]] = []
    latencies: list[int] = []

    def mark(name: str) -> None:
        marks[name] = now()

    def on_stamp(sec: int, nsec: int) -> None:
        wall = time.time_ns()
        marks["callback"] = now()
        rows.append(dict(marks))
        marks.clear()
        latencies.append(wall - (sec * 1_000_000_000 + nsec))

    def wrap(owner: Any, name: str, before: str | None, after: str) -> None:
        original = getattr(owner, name)

        def wrapper(*args: Any, **kwargs: Any) -> Any:
            if before:
                mark(before)
            result = original(*args, **kwargs)
            mark(after)
            return result

        setattr(owner, name, wrapper)

    if mode == "raw":
        import cyclonedds.core

        wrap(cyclonedds.core.WaitSet, "wait", None, "wake")
        _, serve, _ = bench._endpoints("dds", "raw", "tf", "sub", "", on_stamp)
    else:
        from posekit.transport import dds_transport

        wrap(dds_transport._DdsWaiter, "wait", None, "wake")
        if steps:
            from posekit.runtime.executors import Executor

            wrap(dds_transport, "ddspy_take", None, "taken")
            decoder = dds_transport.cdr_decoder

            def timed_decoder(msg_type: Any) -> Any:
                decode = decoder(msg_type)

                def timed(data: bytes) -> Any:
                    mark("decode")
                    message = decode(data)
                    mark("decoded")
                    return message

                return timed

            dds_transport.cdr_decoder = timed_decoder  # type: ignore[assignment]
            wrap(Executor, "_take_ready", "select", "selected")
        _, serve, _ = bench._endpoints("dds", "posekit", "tf", "sub", "", on_stamp)
    assert serve is not None
    print("ready", flush=True)
    give_up = time.monotonic() + 60
    serve(lambda: len(latencies) >= count or time.monotonic() > give_up)
    skip = count // 10
    out: dict[str, float] = {"latency": statistics.median(latencies[skip:]) / 1000}
    kept = [row for row in rows[skip:] if "wake" in row]
    for name in ("taken", "decode", "decoded", "select", "selected", "callback"):
        values = [row[name] - row["wake"] for row in kept if name in row]
        if values:
            out[name] = statistics.median(values) / 1000
    print(json.dumps(out), flush=True)


def round_of(order: list[str], count: int, steps: bool, domain: int) -> dict[str, Any]:
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("ZENOH_", "ROS_", "RMW_", "POSEKIT_", "CYCLONEDDS_"))}
    env.update(ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
               BENCH_SUBSCRIBERS=str(len(order)))
    me = [sys.executable, os.path.abspath(__file__)]
    subs = {}
    for mode in order:
        argv = [*me, "--child", "sub", mode, str(count)] + (["--steps"] if steps else [])
        subs[mode] = proc = subprocess.Popen(argv, env=env, stdout=subprocess.PIPE, text=True)
        assert proc.stdout is not None
        assert proc.stdout.readline().strip() == "ready"
    pub = subprocess.Popen([*me, "--child", "pub", str(count)], env=env,
                           stdin=subprocess.PIPE, text=True)
    results = {}
    for mode, proc in subs.items():
        out, _ = proc.communicate(timeout=120)
        results[mode] = json.loads(out.strip().splitlines()[-1])
    assert pub.stdin is not None
    pub.stdin.close()
    pub.wait(timeout=30)
    return results


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--rounds", type=int, default=6)
    parser.add_argument("--messages", type=int, default=3000)
    parser.add_argument("--steps", action="store_true")
    parser.add_argument("--child", nargs="+", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        if args.child[0] == "pub":
            child_pub(int(args.child[1]))
        else:
            child_sub(args.child[1], int(args.child[2]), args.steps)
        return
    print(f"python {sys.version.split()[0]}; load average at start {os.getloadavg()[0]:.1f}")
    by_place: dict[tuple[str, str], list[dict[str, float]]] = {}
    for index in range(args.rounds):
        order = ["raw", "posekit"] if index % 2 == 0 else ["posekit", "raw"]
        results = round_of(order, args.messages, args.steps, 60 + index % 20)
        for place, mode in zip(("first", "second"), order, strict=True):
            by_place.setdefault((mode, place), []).append(results[mode])
        print(f"  round {index + 1}: " + ", ".join(
            f"{m} {results[m]['latency']:.0f}us (wake->callback {results[m]['callback']:.1f})"
            for m in order), flush=True)
    print(f"\nmedians over rounds, us ({args.messages} messages at {RATE_HZ:.0f} Hz each)")
    columns = ["latency", "taken", "decode", "decoded", "select", "selected", "callback"]
    print(f"{'mode':<9}{'started':<9}" + "".join(f"{c:>10}" for c in columns))
    for (mode, place), rows in sorted(by_place.items()):
        cells = [statistics.median(r[c] for r in rows) if all(c in r for r in rows) else None
                 for c in columns]
        print(f"{mode:<9}{place:<9}" + "".join(
            f"{'':>10}" if v is None else f"{v:>10.1f}" for v in cells))
    print(f"load average at end {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
