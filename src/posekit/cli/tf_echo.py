"""``posekit tf echo SOURCE TARGET [RATE] [--count N]``: tf2_echo with its exact output.

``--use-sim-time`` / ``--wall-time`` choose the clock (default: the simulation's ``/clock``
when one is published, as tf2_echo with ``use_sim_time``).

As in tf2_ros, the FIRST argument is tf2's target frame: ``posekit tf echo map base`` prints
the pose of ``base`` in ``map`` (the transform that takes data from ``base`` into ``map``).
"""

from __future__ import annotations

import math
import re
import sys
import time
from collections.abc import Sequence
from typing import Any, TextIO

from posekit.tf2 import matrix_from_quat, rpy_from_quat

__all__ = ["USAGE", "format_echo_block", "main", "parse_rate"]

USAGE = (
    "Usage: tf2_echo source_frame target_frame [echo_rate]\n\n"
    "This will echo the transform from the coordinate frame of the source_frame\n"
    "to the coordinate frame of the target_frame. \n"
    "Note: This is the transform to get data from target_frame into the source_frame.\n"
    "Default echo rate is 1 if echo_rate is not given.\n"
)

_STOF_PREFIX = re.compile(
    r"\s*[+-]?(?:(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|inf(?:inity)?|nan)", re.IGNORECASE
)


class RateError(ValueError):
    """RATE is not a float (``exit_code`` 2) or has trailing characters (3), as tf2_echo."""

    def __init__(self, text: str, exit_code: int) -> None:
        super().__init__(f"Failed to convert rate argument '{text}' to a floating-point number")
        self.exit_code = exit_code


def parse_rate(text: str) -> float:
    """Parse RATE like tf2_echo's ``std::stof`` with a check for trailing junk."""
    match = _STOF_PREFIX.match(text)
    if match is None:
        raise RateError(text, 2)
    if match.end() != len(text):
        raise RateError(text, 3)
    return float(match.group(0))


def format_echo_block(sec: int, nanosec: int, translation: Sequence[float],
                      quat_xyzw: Sequence[float]) -> str:
    """One tf2_echo block for the transform ``T_target_source`` stamped ``sec.nanosec``.

    RPY comes from tf2's ``Matrix3x3::getEulerYPR`` of the quaternion; numbers are fixed with
    three decimals; the nanoseconds are printed unpadded, exactly as tf2_echo does.
    """
    q = (float(quat_xyzw[0]), float(quat_xyzw[1]), float(quat_xyzw[2]), float(quat_xyzw[3]))
    m = matrix_from_quat(q)
    roll, pitch, yaw = rpy_from_quat(q)
    tx, ty, tz = (float(v) for v in translation)

    def fixed(values: Sequence[float]) -> str:
        return ", ".join(f"{v:.3f}" for v in values)

    def row(values: Sequence[float]) -> str:
        return "".join(" " + f"{v:6.3f}" for v in values)

    lines = [
        f"At time {sec}.{nanosec}",
        f"- Translation: [{fixed((tx, ty, tz))}]",
        f"- Rotation: in Quaternion [{fixed(q)}]",
        f"- Rotation: in RPY (radian) [{fixed((roll, pitch, yaw))}]",
        f"- Rotation: in RPY (degree) [{fixed([math.degrees(a) for a in (roll, pitch, yaw)])}]",
        "- Matrix:",
        row((m[0], m[1], m[2], tx)),
        row((m[3], m[4], m[5], ty)),
        row((m[6], m[7], m[8], tz)),
        row((0.0, 0.0, 0.0, 1.0)),
    ]
    return "\n".join(lines) + "\n"


#: posekit's options, printed after tf2_echo's usage by ``--help``
OPTIONS = (
    "\nposekit options:\n"
    "  --count N          exit after printing N transforms\n"
    "  --transport NAME   posekit transport (default: $POSEKIT_TRANSPORT or zenoh)\n"
    "  --zenoh            same as --transport zenoh\n"
    "  --use-sim-time     use the simulation's /clock (default: when one publishes it)\n"
    "  --wall-time        use the wall clock even when a simulation publishes /clock\n"
    "  -h, --help         show this help and exit\n"
)


def _count(text: str | None) -> int:
    from posekit.cli.errors import CliError

    try:
        value = int(text) if text is not None else -1
    except ValueError:
        value = -1
    if value < 1:
        raise CliError(f"--count needs a positive integer, got {text!r}", 2)
    return value


def _split_options(
    argv: Sequence[str],
) -> tuple[list[str], int | None, str | None, bool | None]:
    positional: list[str] = []
    count: int | None = None
    transport: str | None = None
    use_sim_time: bool | None = None  # None: follow /clock when a simulation publishes it
    it = iter(argv)
    for token in it:
        if token == "--count":
            count = _count(next(it, None))
        elif token.startswith("--count="):
            count = _count(token.split("=", 1)[1])
        elif token == "--transport":
            transport = next(it, None)
        elif token == "--zenoh":
            transport = "zenoh"
        elif token in ("--use-sim-time", "--wall-time"):
            use_sim_time = token == "--use-sim-time"
        else:
            positional.append(token)
    return positional, count, transport, use_sim_time


def main(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
         err: TextIO | None = None, timeout_s: float | None = None) -> int:
    """Run tf2_echo; ``context`` lets tests and launch files share a posekit context."""
    out = out or sys.stdout
    err = err or sys.stderr
    if any(a in ("-h", "--help") for a in argv):
        out.write(USAGE + OPTIONS)
        return 0
    positional, count, transport, use_sim_time = _split_options(argv)
    if len(positional) not in (2, 3):
        out.write(USAGE)
        return 1
    rate = 1.0
    if len(positional) == 3:
        try:
            rate = parse_rate(positional[2])
        except RateError as exc:
            err.write(f"{exc}\n")
            return exc.exit_code
    target, source = positional[0], positional[1]

    from posekit.cli._graph import hint_if_alone
    from posekit.cli._session import ToolSession
    from posekit.tf2 import Buffer, TransformException
    from posekit.time import Time

    with ToolSession("tf2_echo", context=context, transport=transport) as session:
        session.follow_sim_time(use_sim_time)  # "Failure at" times in sim time, as tf2_echo
        buffer = Buffer()
        session.listen_tf(buffer)
        deadline = None if timeout_s is None else time.monotonic() + timeout_s
        last_wait_log = -math.inf
        while True:
            ok, reason = buffer.can_transform_core(target, source, Time())
            if ok:
                break
            if deadline is not None and time.monotonic() > deadline:
                err.write(f"Timed out waiting for transform {target} -> {source}: {reason}\n")
                return 1
            if time.monotonic() - last_wait_log >= 1.0:
                session.node.get_logger().info(
                    f"Waiting for transform {target} ->  {source}: {reason}"
                )
                if last_wait_log == -math.inf:  # once: nobody to hear from at all?
                    hint_if_alone(session, err)
                last_wait_log = time.monotonic()
            session.spin_for(0.05)
        printed = 0
        period = 1.0 / rate if rate > 0 else 1.0
        while count is None or printed < count:
            session.spin_for(0.0)
            try:
                t = buffer.lookup_transform(target, source, Time())
                tr, rot = t.transform.translation, t.transform.rotation
                out.write(format_echo_block(
                    t.header.stamp.sec, t.header.stamp.nanosec,
                    (tr.x, tr.y, tr.z), (rot.x, rot.y, rot.z, rot.w),
                ))
            except TransformException as exc:
                now = session.node.get_clock().now().nanoseconds / 1e9
                out.write(
                    f"Failure at {now}\nException thrown:{exc}\nThe current list of frames is:\n"
                    f"{buffer.all_frames_as_string()}\n"
                )
            out.flush()
            printed += 1
            if count is not None and printed >= count:
                break
            session.spin_for(period)
    return 0
