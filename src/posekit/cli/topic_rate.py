"""``posekit topic hz|bw|delay``: ``ros2 topic``'s rate, bandwidth and delay monitors (Jazzy).

* ``hz TOPIC [-w N] [--filter EXPR] [--wall-time]``: at most once per second of message time
  ``average rate: R\\n\\tmin: As max: Bs std dev: Cs window: N`` over the last N inter-arrival
  times, measured on the tool node's clock: the simulation's while one publishes ``/clock``
  (or with ``--use-sim-time``), else, and with ``--wall-time``, the system clock.
* ``bw TOPIC [-w N]``: once a second ``B/s from N messages\\n\\tMessage size mean: ... min: ...
  max: ...`` in B, KB or MB (powers of 1000), message sizes being the CDR serialization.
* ``delay TOPIC [-w N]``: once a second ``average delay: D\\n\\tmin: ... window: N`` of the
  receive time minus ``header.stamp`` (``no new messages`` when none arrived).

posekit's additions: ``--timeout S`` ends the tool cleanly when no message has arrived for S
seconds (also while waiting for the topic to appear; a message ``--filter`` rejects does not
count): exit 1 with a one-line reason if nothing was ever measured, else 0; ``--count N``
exits after N reports.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections import deque
from collections.abc import Callable, Sequence
from typing import Any, TextIO

from posekit.cli._graph import add_transport_args, resolve_topic, session_for, wait_for_topic_type
from posekit.cli._session import add_sim_time_args
from posekit.cli.errors import CliError
from posekit.cli.topic_echo import compile_filter, positive_float, positive_int
from posekit.msgs.yaml_io import message_class
from posekit.time import stamp_to_ns

__all__ = ["bw_report", "delay_report", "hz_report", "main_bw", "main_delay", "main_hz"]

HZ_WINDOW = 10000
BW_WINDOW = 100
DELAY_WINDOW = 10000


def _stats(values: Sequence[int]) -> tuple[float, float]:
    n = len(values)
    mean = sum(values) / n
    return mean, math.sqrt(sum((x - mean) ** 2 for x in values) / n)


def hz_report(deltas_ns: Sequence[int]) -> str:
    """``ros2 topic hz``'s two-line report for inter-arrival times (ns); needs >= 1 delta."""
    mean, std_dev = _stats(deltas_ns)
    rate = 1.0 / mean if mean > 0 else 0.0
    return (
        f"average rate: {rate * 1e9:.3f}\n"
        f"\tmin: {min(deltas_ns) * 1e-9:.3f}s max: {max(deltas_ns) * 1e-9:.3f}s "
        f"std dev: {std_dev * 1e-9:.5f}s window: {len(deltas_ns)}\n"
    )


def delay_report(delays_ns: Sequence[int]) -> str:
    """``ros2 topic delay``'s two-line report for delays (ns); needs >= 1 delay."""
    mean, std_dev = _stats(delays_ns)
    return (
        f"average delay: {mean * 1e-9:.3f}\n"
        f"\tmin: {min(delays_ns) * 1e-9:.3f}s max: {max(delays_ns) * 1e-9:.3f}s "
        f"std dev: {std_dev * 1e-9:.5f}s window: {len(delays_ns)}\n"
    )


def bw_report(bytes_per_s: float, sizes: Sequence[int]) -> str:
    """``ros2 topic bw``'s two-line report (units chosen by the rate, as ros2 does)."""
    mean = sum(sizes) / len(sizes)
    if bytes_per_s < 1000:
        unit: Callable[[float], str] = lambda b: f"{b:.0f} B"  # noqa: E731
    elif bytes_per_s < 1_000_000:
        unit = lambda b: f"{b / 1000:.2f} KB"  # noqa: E731
    else:
        unit = lambda b: f"{b / 1000 / 1000:.2f} MB"  # noqa: E731
    return (f"{unit(bytes_per_s)}/s from {len(sizes)} messages\n"
            f"\tMessage size mean: {unit(mean)} min: {unit(min(sizes))} max: {unit(max(sizes))}\n")


def _parser(verb: str, description: str, window: int, topic_help: str) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog=f"posekit topic {verb}", description=description)
    parser.add_argument("topic_name", help=topic_help)
    parser.add_argument("--window", "-w", dest="window_size", type=positive_int, default=window,
                        metavar="WINDOW",
                        help=f"window size, in # of messages, for calculating rate "
                             f"(default: {window})")
    parser.add_argument("--timeout", type=positive_float, default=None, metavar="S",
                        help="exit when no message arrived for S seconds (posekit addition)")
    parser.add_argument("--count", type=positive_int, default=None,
                        help="exit after N reports (posekit addition)")
    add_transport_args(parser)
    add_sim_time_args(parser)
    return parser


def _once_per_second(first_after: float = 0.0) -> Callable[[], bool]:
    """True at most once per wall second (ros2's 1 s report timer), first after
    ``first_after`` seconds."""
    next_at = [time.monotonic() + first_after]

    def due() -> bool:
        now = time.monotonic()
        if now < next_at[0]:
            return False
        next_at[0] = now + 1.0
        return True

    return due


class _Window:
    """The last N samples of ros2's hz/delay monitors, restarted when time jumps back."""

    def __init__(self, size: int, out: TextIO) -> None:
        self.values: deque[int] = deque(maxlen=size)
        self.t0 = -1
        self.tn = 0
        self._out = out

    def add(self, now: int, value: Callable[[int], int]) -> None:
        """Record ``value(now)`` for a message received at ``now`` (ns; not the first)."""
        if now == 0:
            if self.values:
                self._out.write("time has reset, resetting counters\n")
                self.values.clear()
            return
        if self.t0 < 0 or self.t0 > now:
            self.t0 = self.tn = now
            self.values.clear()
        else:
            self.values.append(value(now))
            self.tn = now


class _Monitor:
    """Subscribe to a topic, call ``sample`` per message and ``tick`` after each spin."""

    def __init__(self, ns: argparse.Namespace, verb: str, context: Any, err: TextIO,
                 timeout_s: float | None) -> None:
        self.ns = ns
        self.verb = verb
        self.context = context
        self.err = err
        self.limit_s = ns.timeout if timeout_s is None else timeout_s
        self.reports = 0
        self.received = 0
        self._last_rx = time.monotonic()

    def run(self, sample: Callable[[Any, Any], bool], tick: Callable[[Any], bool],
            needs_field: str | None = None) -> int:
        """Spin until ``--count`` reports, Ctrl-C, or ``--timeout`` without a measured message
        (``sample`` returns False for a message it did not measure)."""
        from posekit.runtime.qos import qos_profile_sensor_data

        with session_for(self.ns, self.context) as session:
            # the node clock is the simulation's while one publishes /clock (or with
            # --use-sim-time), as ros2's tools measure with their node's ROS clock
            session.follow_sim_time(self.ns.use_sim_time)
            topic = resolve_topic(session, self.ns.topic_name)
            type_name = wait_for_topic_type(session, topic, self.err, self.limit_s)
            if type_name is None:
                raise CliError(f"topic [{topic}] did not appear within {self.limit_s:g} s")

            msg_cls = message_class(type_name)
            if needs_field is not None and needs_field not in getattr(
                    msg_cls, "__dataclass_fields__", {}):
                raise CliError(f"messages of type {type_name} have no {needs_field}; "
                               f"{self.verb} needs {needs_field}.stamp")
            failure: list[CliError] = []

            def on_message(msg: Any) -> None:
                if failure:
                    return
                try:
                    measured = sample(session, msg)
                except CliError as exc:  # a --filter failing on a message
                    failure.append(exc)
                    return
                if measured:
                    self.received += 1
                    self._last_rx = time.monotonic()

            session.node.create_subscription(msg_cls, topic, on_message,
                                             qos_profile_sensor_data)
            self._last_rx = time.monotonic()
            while session.context.ok():
                session.spin_for(0.05)
                if failure:
                    raise failure[0]
                if tick(session):
                    self.reports += 1
                if self.ns.count is not None and self.reports >= self.ns.count:
                    break
                if self.limit_s is not None and time.monotonic() - self._last_rx > self.limit_s:
                    if self.received == 0:
                        raise CliError(f"no message measured on [{topic}] within "
                                       f"{self.limit_s:g} s")
                    self.err.write(f"no message measured on [{topic}] for {self.limit_s:g} s; "
                                   "exiting\n")
                    break
        return 0


def main_hz(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
            err: TextIO | None = None, timeout_s: float | None = None) -> int:
    """``topic hz TOPIC [-w N] [--filter EXPR] [--wall-time]``."""
    out = out or sys.stdout
    err = err or sys.stderr
    parser = _parser("hz", "Print the average publishing rate to screen", HZ_WINDOW,
                     "Name of the ROS topic to listen to (e.g. '/chatter')")
    parser.add_argument("--filter", dest="filter_expr", default=None, metavar="EXPR",
                        help="only measure messages matching the specified Python expression")
    ns = parser.parse_args(list(argv))
    accept = compile_filter(ns.filter_expr)
    window = _Window(ns.window_size, out)
    printed = [0]

    def now_ns(session: Any) -> int:
        if ns.use_sim_time is False:  # --wall-time
            return time.time_ns()
        return int(session.node.get_clock().now().nanoseconds)

    def sample(session: Any, msg: Any) -> bool:
        if accept is not None and not accept(msg):
            return False
        window.add(now_ns(session), lambda now: now - window.tn)
        return True

    def tick(_session: Any) -> bool:
        if not window.values:
            return False
        if printed[0] == 0:
            printed[0] = window.tn
            return False
        if window.tn < printed[0] + 1_000_000_000:
            return False
        out.write(hz_report(list(window.values)))
        out.flush()
        printed[0] = window.tn
        return True

    return _Monitor(ns, "hz", context, err, timeout_s).run(sample, tick)


def main_bw(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
            err: TextIO | None = None, timeout_s: float | None = None) -> int:
    """``topic bw TOPIC [-w N]``: received bytes per second (CDR sizes)."""
    from posekit.msgs.cdr import to_cdr

    out = out or sys.stdout
    err = err or sys.stderr
    ns = _parser("bw", "Display bandwidth used by topic", BW_WINDOW,
                 "Topic name to monitor for bandwidth utilization").parse_args(list(argv))
    samples: deque[tuple[int, int]] = deque(maxlen=ns.window_size)
    due = _once_per_second()
    out.write(f"Subscribed to [{ns.topic_name}]\n")

    def sample(session: Any, msg: Any) -> bool:
        samples.append((int(session.node.get_clock().now().nanoseconds), len(to_cdr(msg))))
        return True

    def tick(session: Any) -> bool:
        if not due() or len(samples) < 2:
            return False
        t_now = int(session.node.get_clock().now().nanoseconds)
        t0 = samples[0][0]
        if t_now <= t0:
            err.write("WARNING: time is reset!\n")
            samples.clear()
            return False
        sizes = [size for _, size in samples]
        out.write(bw_report(sum(sizes) / ((t_now - t0) * 1e-9), sizes))
        out.flush()
        return True

    return _Monitor(ns, "bw", context, err, timeout_s).run(sample, tick)


def main_delay(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
               err: TextIO | None = None, timeout_s: float | None = None) -> int:
    """``topic delay TOPIC [-w N]``: receive time minus ``header.stamp``."""
    out = out or sys.stdout
    err = err or sys.stderr
    ns = _parser("delay", "Display delay of topic from timestamp in header", DELAY_WINDOW,
                 "Topic name to calculate the delay for").parse_args(list(argv))
    window = _Window(ns.window_size, out)
    last = [0]
    due = _once_per_second(1.0)

    def sample(session: Any, msg: Any) -> bool:
        stamp = msg.header.stamp
        stamp_ns = stamp_to_ns(stamp)
        window.add(int(session.node.get_clock().now().nanoseconds), lambda now: now - stamp_ns)
        return True

    def tick(_session: Any) -> bool:
        if not due() or not window.values:
            return False
        if window.tn == last[0]:
            out.write("no new messages\n")
        else:
            out.write(delay_report(list(window.values)))
            last[0] = window.tn
        out.flush()
        return True

    return _Monitor(ns, "delay", context, err, timeout_s).run(sample, tick, "header")
