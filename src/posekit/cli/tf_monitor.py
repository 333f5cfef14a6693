"""``posekit tf monitor [FRAME_A FRAME_B]``: tf2_monitor's report (tf2_ros, Jazzy).

Gathers every ``/tf`` and ``/tf_static`` message and, every 10.5 s as tf2_monitor does
(21 polls 0.5 s apart), prints::

    RESULTS: for all Frames            (or: RESULTS: for A to B / Chain is: A -> B /
                                              Net delay     avg = D: max = M)
    Frames:
    Frame: <child>, published by <no authority available>, Average Delay: D, Max Delay: M
    All Broadcasters:
    Node: <no authority available> F Hz, Average Delay: D Max Delay: M

Delays are the receive time on the tool node's clock minus each transform's stamp, in
seconds, over the last 1000 samples per frame; the rate is messages per second over the last
1000 messages. Numbers are formatted like C++ streams (6 significant digits). As in tf2_monitor
the ``All Broadcasters:`` title goes to stderr. With two frames only the frames of the chain
between them are listed, and the net delay of ``lookup_transform(A, B)`` is low-pass filtered.

Delays are measured on the simulation's clock while one publishes ``/clock``
(``--use-sim-time`` / ``--wall-time`` force either). posekit's additions: ``--period S``
(report every S seconds instead of 10.5), ``--count N`` (exit after N reports),
``--transport``/``--zenoh``.
"""

from __future__ import annotations

import argparse
import re
import sys
import time
from collections import deque
from collections.abc import Sequence
from typing import Any, TextIO

from posekit.cli._graph import add_transport_args, hint_if_alone, session_for
from posekit.cli._session import add_sim_time_args
from posekit.cli.errors import CliError
from posekit.time import stamp_to_seconds

__all__ = ["chain_as_vector", "main"]

AUTHORITY = "<no authority available>"
_HISTORY = 1000
_FRAME_LINE = re.compile(r"^Frame (.+) exists with parent (.+)\.$")


def _num(value: float) -> str:
    """A double as ``std::cout`` prints it by default (``%g``, 6 significant digits)."""
    return f"{value:g}"


def parents_from_buffer(buffer: Any) -> dict[str, str]:
    """child -> parent of every frame with data in ``buffer``."""
    parents: dict[str, str] = {}
    for line in buffer.all_frames_as_string().splitlines():
        match = _FRAME_LINE.match(line.strip())
        if match:
            parents[match.group(1)] = match.group(2)
    return parents


def chain_as_vector(parents: dict[str, str], target: str, source: str) -> list[str]:
    """The frames between ``source`` and ``target`` in the order tf2's ``_chainAsVector``
    (fixed frame == target) lists them: up from the source to the common ancestor, then
    down to the target."""
    chain: list[str] = []
    frame: str | None = source
    top = source
    while frame is not None:
        chain.append(frame)
        parent = parents.get(frame)
        if parent is None:
            top = frame
            break
        if frame == target:
            return chain
        top, frame = frame, parent
        if len(chain) > 1000:
            raise CliError("the tf tree contains a loop")
    reverse: list[str] = []
    frame = target
    while frame is not None and frame != top:
        reverse.append(frame)
        parent = parents.get(frame)
        if parent is None:
            break
        if frame == source:
            return reverse
        frame = parent
    m, n = len(reverse), len(chain)
    while m > 0 and n > 0:
        m -= 1
        n -= 1
        if chain[n] != reverse[m]:
            break
    if n > 0:
        del chain[n - 1:]
    if m < len(reverse):
        chain.extend(reversed(reverse[: m + 1]))
    return chain


def _wait_for_chain(session: Any, buffer: Any, frame_a: str, frame_b: str,
                    timeout_s: float | None, err: TextIO) -> None:
    """Spin until ``frame_a -> frame_b`` can be looked up, logging why not once a second
    (as tf2_monitor); CliError after ``timeout_s`` (None: wait until it can)."""
    from posekit.time import Time

    deadline = None if timeout_s is None else time.monotonic() + timeout_s
    last_log = -1e9
    while True:
        ok, reason = buffer.can_transform_core(frame_a, frame_b, Time())
        if ok:
            return
        if deadline is not None and time.monotonic() > deadline:
            raise CliError(f"timed out waiting for transform {frame_a} -> {frame_b}: {reason}")
        if time.monotonic() - last_log >= 1.0:
            session.node.get_logger().info(
                f"Waiting for transform {frame_a} ->  {frame_b}: {reason}")
            if last_log < 0:
                hint_if_alone(session, err)
            last_log = time.monotonic()
        session.spin_for(0.1)


def _frame_lines(delays: dict[str, deque[float]], chain: list[str] | None) -> list[str]:
    """The report's ``Frame: ...`` lines, sorted by frame (only the chain's, if given)."""
    lines = []
    for frame in sorted(delays):
        if chain is not None and frame not in chain:
            continue
        values = delays[frame]
        lines.append(f"Frame: {frame}, published by {AUTHORITY}, Average Delay: "
                     f"{_num(sum(values) / len(values))}, Max Delay: "
                     f"{_num(max(0.0, *values))}")
    return lines


def main(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
         err: TextIO | None = None, timeout_s: float | None = None) -> int:
    """Run tf2_monitor; ``timeout_s`` (tests) bounds the wait for the chain."""
    from posekit.msgs.tf2_msgs import TFMessage
    from posekit.tf2 import Buffer
    from posekit.tf2_ros import DynamicListenerQoS, StaticListenerQoS
    from posekit.time import Time

    out = out or sys.stdout
    err = err or sys.stderr
    parser = argparse.ArgumentParser(
        prog="posekit tf monitor",
        description="tf2_monitor: delays and rates of the transforms on /tf and /tf_static, "
                    "for all frames or the chain between two frames")
    parser.add_argument("frames", nargs="*", metavar="FRAME",
                        help="framea frameb: monitor only the chain between them")
    parser.add_argument("--period", type=float, default=10.5,
                        help="seconds between reports (default 10.5, as tf2_monitor)")
    parser.add_argument("--count", type=int, default=None, help="exit after N reports")
    add_transport_args(parser)
    add_sim_time_args(parser)
    ns = parser.parse_args(list(argv))
    if len(ns.frames) not in (0, 2):
        raise CliError("usage: posekit tf monitor [framea frameb]", 2)
    if not ns.period > 0:
        raise CliError(f"--period must be positive, got {ns.period}", 2)
    specific = len(ns.frames) == 2
    frame_a, frame_b = ns.frames if specific else ("", "")

    delays: dict[str, deque[float]] = {}
    offsets: deque[float] = deque(maxlen=_HISTORY)
    arrivals: deque[float] = deque(maxlen=_HISTORY)

    with session_for(ns, context) as session:
        session.follow_sim_time(ns.use_sim_time)  # a simulation's stamps are sim time
        buffer = Buffer()
        session.listen_tf(buffer)
        clock = session.node.get_clock()

        def now_s() -> float:
            return float(clock.now().nanoseconds) * 1e-9

        def on_tf(msg: Any) -> None:
            now = now_s()
            total = 0.0
            for t in msg.transforms:
                offset = now - stamp_to_seconds(t.header.stamp)
                delays.setdefault(t.child_frame_id, deque(maxlen=_HISTORY)).append(offset)
                total += offset
            offsets.append(total / max(1, len(msg.transforms)))
            arrivals.append(now)

        session.node.create_subscription(TFMessage, "/tf", on_tf, DynamicListenerQoS())
        session.node.create_subscription(TFMessage, "/tf_static", on_tf, StaticListenerQoS())
        chain: list[str] = []
        if specific:
            _wait_for_chain(session, buffer, frame_a, frame_b, timeout_s, err)
            chain = chain_as_vector(parents_from_buffer(buffer), frame_b, frame_a)
            out.write(f"Gathering data on {frame_a} -> {frame_b} for 10 seconds...\n")
        else:
            out.write("Gathering data on all frames for 10 seconds...\n")
        out.flush()
        avg_diff = max_diff = 0.0
        reports = 0
        next_report = time.monotonic() + ns.period
        while session.context.ok() and (ns.count is None or reports < ns.count):
            if specific:
                t = buffer.lookup_transform(frame_a, frame_b, Time())
                diff = now_s() - stamp_to_seconds(t.header.stamp)
                avg_diff = 0.01 * diff + 0.99 * avg_diff
                max_diff = max(max_diff, diff)
            session.spin_for(min(0.5, max(0.0, next_report - time.monotonic())))
            if time.monotonic() < next_report:
                continue
            next_report += ns.period
            reports += 1
            lines = ["", "", ""]
            if specific:
                lines += [f"RESULTS: for {frame_a} to {frame_b}",
                          "Chain is: " + " -> ".join(chain),
                          f"Net delay     avg = {_num(avg_diff)}: max = {_num(max_diff)}"]
            else:
                lines.append("RESULTS: for all Frames")
            lines += ["", "Frames:"]
            lines += _frame_lines(delays, chain if specific else None)
            out.write("\n".join(lines) + "\n")
            out.flush()
            err.write("\nAll Broadcasters:\n")
            err.flush()
            if offsets:
                span = max(1e-8, arrivals[-1] - arrivals[0])
                out.write(f"Node: {AUTHORITY} {_num(len(arrivals) / span)} Hz, Average Delay: "
                          f"{_num(sum(offsets) / len(offsets))} Max Delay: "
                          f"{_num(max(0.0, *offsets))}\n")
            out.flush()
    return 0
