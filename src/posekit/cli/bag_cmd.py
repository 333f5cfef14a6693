"""``posekit bag record|play|info``: ros2 bag's three everyday verbs on posekit.bag.

* ``posekit bag record -o DIR [TOPICS... | --all]`` records until Ctrl-C (or ``--duration``
  wall seconds) into a new rosbag2 directory (MCAP, zstd chunks, metadata version 9 unless
  ``--metadata-version 8``).
* ``posekit bag play DIR [--rate R] [--loop]`` publishes the bag with ``/clock`` at the
  recorded timing (wall clock scaled by R) until the end (or Ctrl-C with ``--loop``).
* ``posekit bag info DIR [-v]`` prints what ``ros2 bag info`` prints.
* ``posekit bag reindex DIR`` rebuilds a bag whose recorder was killed (no summary, no
  metadata.yaml) from the chunks it wrote (``ros2 bag reindex``; see posekit.bag.reindex).

``bag record`` finishes the bag on SIGTERM as on Ctrl-C.

Like the other command-line tools these talk to other processes, so their transport is
``--transport NAME``, else $POSEKIT_TRANSPORT, else Zenoh. Errors print one line on stderr
and exit with 1 (2 for bad usage).
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from typing import Any, NoReturn, TextIO

__all__ = ["info", "play", "record", "reindex"]


class _UsageError(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:
        raise _UsageError(f"{self.prog}: error: {message}")


def _parse(parser: _Parser, argv: Sequence[str]) -> argparse.Namespace | int:
    from posekit.cli._extras import require

    try:
        ns = parser.parse_args(list(argv))
    except _UsageError as exc:
        sys.stderr.write(parser.format_usage() + f"{exc}\n")
        return 2
    except SystemExit as exc:  # --help
        return int(exc.code or 0)
    problem = require(parser.prog, [("ROS 2 bags", "bag")])
    if problem:
        sys.stderr.write(problem + "\n")
        return 2
    return ns


def _transport_option(parser: argparse.ArgumentParser) -> None:
    from posekit.cli._session import add_transport_option

    add_transport_option(parser)


def _transport_name(ns: argparse.Namespace) -> str | None:
    from posekit.cli._session import transport_option

    return transport_option(ns)


def _context(context: Any, transport: str | None) -> tuple[Any, bool]:
    if context is not None:
        return context, False
    from posekit.cli._session import tool_transport
    from posekit.runtime.context import Context

    ctx = Context()
    ctx.init(transport=tool_transport(transport))
    return ctx, True


def record(argv: Sequence[str], *, context: Any = None) -> int:
    """``posekit bag record``; ``context`` (tests) replaces the tool's own context."""
    parser = _Parser(prog="posekit bag record",
                     description="Record topics into a rosbag2 directory (MCAP storage).")
    parser.add_argument("topics", nargs="*", help="topics to record")
    parser.add_argument("-a", "--all", action="store_true",
                        help="record every topic (discovered continuously; not /clock)")
    parser.add_argument("-o", "--output", required=True, help="bag directory to create")
    parser.add_argument("--metadata-version", type=int, choices=(8, 9), default=9,
                        help="metadata.yaml version (default 9, ROS 2 Jazzy)")
    parser.add_argument("--no-compression", action="store_true",
                        help="store MCAP chunks uncompressed (default: zstd)")
    parser.add_argument("--stamp", choices=("receive", "header"), default="receive",
                        help="message timestamp: receive time (default, as rosbag2) or "
                             "header.stamp")
    parser.add_argument("--include-hidden-topics", action="store_true",
                        help="with --all, also record hidden topics")
    parser.add_argument("--duration", type=float, default=None,
                        help="stop after this many wall seconds (default: until Ctrl-C)")
    _transport_option(parser)
    ns = _parse(parser, argv)
    if isinstance(ns, int):
        return ns
    if bool(ns.topics) == bool(ns.all):
        sys.stderr.write(parser.format_usage() +
                         "posekit bag record: give topics to record or --all (not both)\n")
        return 2
    if ns.duration is not None and not ns.duration >= 0:
        sys.stderr.write(f"posekit bag record: --duration must be >= 0, got {ns.duration}\n")
        return 2

    from posekit.bag import BagError, Recorder
    from posekit.runtime.executors import SingleThreadedExecutor

    try:
        ctx, own = _context(context, _transport_name(ns))
    except Exception as exc:
        sys.stderr.write(f"posekit bag record: cannot start the transport: {exc}\n")
        return 1
    try:
        try:
            recorder = Recorder(
                ns.output,
                ns.topics or None,
                context=ctx,
                version=ns.metadata_version,
                compression=None if ns.no_compression else "zstd",
                stamp=ns.stamp,
                include_hidden=ns.include_hidden_topics,
            )
        except BagError as exc:
            sys.stderr.write(f"posekit bag record: {exc}\n")
            return 1
        executor = SingleThreadedExecutor(context=ctx)
        executor.add_node(recorder.node)
        try:
            if ns.duration is None:
                executor.spin()
            else:
                end = time.monotonic() + ns.duration
                while ctx.ok() and (left := end - time.monotonic()) > 0:
                    executor.spin_once(timeout_sec=left)
        except KeyboardInterrupt:
            pass
        finally:
            executor.shutdown()
            counts = recorder.close()
        total = sum(counts.values())
        sys.stderr.write(
            f"posekit bag record: wrote {total} messages on {len(counts)} topics to "
            f"{ns.output}\n"
        )
        return 0
    finally:
        if own:
            ctx.try_shutdown()


def play(argv: Sequence[str], *, context: Any = None) -> int:
    """``posekit bag play``; ``context`` (tests) replaces the tool's own context."""
    parser = _Parser(prog="posekit bag play",
                     description="Publish a bag at its recorded timing, with /clock.")
    parser.add_argument("bag", help="rosbag2 directory")
    parser.add_argument("-r", "--rate", type=float, default=1.0, help="speed factor (> 0)")
    parser.add_argument("-l", "--loop", action="store_true", help="repeat until Ctrl-C")
    parser.add_argument("--topics", nargs="+", default=None, help="only these topics")
    parser.add_argument("--clock", type=float, default=100.0, metavar="HZ",
                        help="/clock messages per second (default 100)")
    parser.add_argument("--no-clock", action="store_true", help="do not publish /clock")
    _transport_option(parser)
    ns = _parse(parser, argv)
    if isinstance(ns, int):
        return ns

    from posekit.bag import BagError, Player
    from posekit.runtime.executors import SingleThreadedExecutor

    try:
        ctx, own = _context(context, _transport_name(ns))
    except Exception as exc:
        sys.stderr.write(f"posekit bag play: cannot start the transport: {exc}\n")
        return 1
    try:
        try:
            player = Player(ns.bag, context=ctx, topics=ns.topics, rate=ns.rate,
                            loop=ns.loop, publish_clock=not ns.no_clock,
                            clock_frequency=ns.clock)
        except BagError as exc:
            sys.stderr.write(f"posekit bag play: {exc}\n")
            return 1
        executor = SingleThreadedExecutor(context=ctx)
        try:
            player.play(executor)
        except KeyboardInterrupt:
            pass
        except BagError as exc:
            sys.stderr.write(f"posekit bag play: {exc}\n")
            return 1
        finally:
            executor.shutdown()
            player.close()
        if player.missing:
            sys.stderr.write(
                f"posekit bag play: {ns.bag} is damaged: {player.missing} of the messages "
                "its metadata lists could not be read (posekit bag info / reindex)\n"
            )
            return 1
        return 0
    finally:
        if own:
            ctx.try_shutdown()


def info(argv: Sequence[str], *, out: TextIO | None = None) -> int:
    """``posekit bag info DIR [-v]``."""
    parser = _Parser(prog="posekit bag info", description="Print a bag's summary.")
    parser.add_argument("bag", help="rosbag2 directory")
    parser.add_argument("-v", "--verbose", action="store_true",
                        help="also metadata version, compression and offered QoS")
    ns = _parse(parser, argv)
    if isinstance(ns, int):
        return ns
    from posekit.bag import BagError, bag_info, format_info

    try:
        summary = bag_info(ns.bag)
    except BagError as exc:
        sys.stderr.write(f"posekit bag info: {exc}\n")
        return 1
    (out or sys.stdout).write(format_info(summary, verbose=ns.verbose))
    return 0


def reindex(argv: Sequence[str], *, out: TextIO | None = None) -> int:
    """``posekit bag reindex DIR``."""
    parser = _Parser(prog="posekit bag reindex",
                     description="Rebuild a bag whose recorder died from its MCAP chunks.")
    parser.add_argument("bag", help="rosbag2 directory")
    ns = _parse(parser, argv)
    if isinstance(ns, int):
        return ns
    from posekit.bag import BagError
    from posekit.bag import reindex as reindex_bag

    try:
        result = reindex_bag(ns.bag)
    except BagError as exc:
        sys.stderr.write(f"posekit bag reindex: {exc}\n")
        return 1
    stream = out or sys.stdout
    for name, reason in result.truncated.items():
        stream.write(f"{name}: read up to the damage ({reason})\n")
    for topic, reason in result.skipped.items():
        stream.write(f"skipped {topic}: {reason}\n")
    stream.write(f"reindexed {ns.bag}: {result.total} messages on {len(result.counts)} topics "
                 "(originals kept as *.mcap.orig)\n")
    return 0
