"""``posekit bag record|play|info|convert``: ros2 bag's everyday verbs (Jazzy) on posekit.bag.

* ``posekit bag record [-o DIR] [TOPICS | --topics T.. | --all | -e REGEX] ...`` records until
  Ctrl-C (or ``--duration`` wall seconds) into a new rosbag2 directory (MCAP, zstd chunks,
  ``<name>_0.mcap``..., metadata version 9 unless ``--metadata-version 8``); default name
  ``rosbag2_YYYY_MM_DD-HH_MM_SS``; ``-b``/``-d`` split the files, ``--exclude-regex`` /
  ``--exclude-topics`` thin the selection, ``--compression-mode file|message`` as rosbag2.
* ``posekit bag play DIR [-r R] [-l] [--topics ..] [-e/-x REGEX] [--remap a:=b] [-p]
  [--start-offset S] ...`` publishes the bag with ``/clock`` at the recorded timing, with
  ros2 bag play's keyboard controls on a terminal and a progress line on stderr.
* ``posekit bag info DIR [-t] [-v]`` prints what ``ros2 bag info`` prints.
* ``posekit bag convert -i DIR [-i DIR..] -o OPTIONS.yaml`` is ``ros2 bag convert``.
* ``posekit bag reindex DIR`` rebuilds a bag whose recorder was killed (no summary, no
  metadata.yaml) from the chunks it wrote (``ros2 bag reindex``; see posekit.bag.reindex).

``bag record`` finishes the bag on SIGTERM as on Ctrl-C.

Like the other command-line tools these talk to other processes, so their transport is
``--transport NAME``, else $POSEKIT_TRANSPORT, else Zenoh. Errors print one line on stderr
and exit with 1 (2 for bad usage).
"""

from __future__ import annotations

import argparse
import datetime
import os
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any, NoReturn, TextIO

__all__ = ["convert", "info", "play", "record", "reindex"]


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


def default_bag_name(now: datetime.datetime | None = None) -> str:
    """rosbag2's default output name: ``rosbag2_YYYY_MM_DD-HH_MM_SS`` in local time."""
    return (now or datetime.datetime.now()).strftime("rosbag2_%Y_%m_%d-%H_%M_%S")


def _warn_record_overrides(ns: argparse.Namespace, topics: list[str], every: bool,
                           every_service: bool) -> None:
    """ros2 bag's warnings when --all, --all-topics or --all-services override a selection."""
    if every_service and ns.services:
        sys.stderr.write("[WARN] [ros2bag]: --all or --all-services will override --services\n")
    if every and topics:
        sys.stderr.write("[WARN] [ros2bag]: --all or --all-topics will override --topics\n")
    if (every or every_service) and ns.regex:
        sys.stderr.write("[WARN] [ros2bag]: --all, --all-topics or --all-services will "
                         "override --regex\n")


def _custom_data(pairs: Sequence[str]) -> dict[str, str] | None:
    """``--custom-data`` KEY=VALUE pairs as a mapping; None after reporting a malformed one."""
    custom: dict[str, str] = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep or not key:
            sys.stderr.write(f"posekit bag record: error: --custom-data needs KEY=VALUE, "
                             f"got {pair!r}\n")
            return None
        custom[key] = value
    return custom


def record(argv: Sequence[str], *, context: Any = None) -> int:
    """``posekit bag record``; ``context`` (tests) replaces the tool's own context."""
    parser = _Parser(prog="posekit bag record",
                     description="Record topics into a rosbag2 directory (MCAP storage).")
    parser.add_argument("topics_positional", nargs="*", metavar="TOPIC",
                        help="topics to record (as ros2 bag's deprecated positional form)")
    parser.add_argument("--topics", nargs="+", default=[], metavar="TOPIC",
                        help="space-delimited list of topics to record")
    parser.add_argument("--services", nargs="+", default=[], metavar="SERVICE",
                        help="space-delimited list of services to record (their events, "
                             "<service>/_service_event; introspection must be on)")
    parser.add_argument("--topic-types", nargs="+", default=[], metavar="TYPE",
                        help="space-delimited list of topic types to record")
    parser.add_argument("-a", "--all", action="store_true",
                        help="record all topics and services (discovered continuously; not "
                             "/clock nor hidden topics)")
    parser.add_argument("--all-topics", action="store_true",
                        help="record all topics (not hidden topics)")
    parser.add_argument("--all-services", action="store_true",
                        help="record all services via their service event topics")
    parser.add_argument("-e", "--regex", default="",
                        help="record only topics and services containing the provided regular "
                             "expression (--all, --all-topics or --all-services override it)")
    parser.add_argument("--exclude-regex", default="",
                        help="exclude topics and services containing the provided regular "
                             "expression; works on top of --all, --all-topics, "
                             "--all-services, --topics, --services or --regex")
    parser.add_argument("--exclude-topic-types", nargs="+", default=[], metavar="TYPE",
                        help="space-delimited list of topic types not to record; works on top "
                             "of --all, --all-topics, --topics or --regex")
    parser.add_argument("--exclude-topics", nargs="+", default=[], metavar="TOPIC",
                        help="space-delimited list of topics not to record; works on top of "
                             "--all, --all-topics, --topics or --regex")
    parser.add_argument("--exclude-services", nargs="+", default=[], metavar="SERVICE",
                        help="space-delimited list of services not to record; works on top of "
                             "--all, --all-services, --services or --regex")
    parser.add_argument("--include-hidden-topics", action="store_true",
                        help="also record hidden topics (with --all or --regex)")
    parser.add_argument("-o", "--output", default=None,
                        help="bag directory to create (default: rosbag2_YYYY_MM_DD-HH_MM_SS)")
    parser.add_argument("-s", "--storage", default="mcap", choices=("mcap",),
                        help="storage identifier (posekit writes MCAP)")
    parser.add_argument("-b", "--max-bag-size", type=int, default=0,
                        help="maximum size in bytes before the bagfile will be split "
                             "(default 0: no splitting)")
    parser.add_argument("-d", "--max-bag-duration", type=int, default=0,
                        help="maximum duration in seconds before the bagfile will be split "
                             "(default 0: no splitting); with -b, whichever comes first")
    parser.add_argument("--compression-mode", default="none",
                        choices=("none", "file", "message"),
                        help="compression of the storage: none (default; MCAP chunks are "
                             "still zstd-compressed unless --no-compression), file or message")
    parser.add_argument("--compression-format", default="", choices=("", "zstd"),
                        help="compression format for --compression-mode file|message "
                             "(zstd, the only one; the default with a mode)")
    parser.add_argument("--no-compression", action="store_true",
                        help="store MCAP chunks uncompressed (default: zstd)")
    parser.add_argument("--custom-data", nargs="*", default=[], metavar="KEY=VALUE",
                        help="key=value pairs stored under custom_data in metadata.yaml")
    parser.add_argument("--node-name", default="rosbag2_recorder",
                        help="name of the recorder node (default rosbag2_recorder)")
    parser.add_argument("--metadata-version", type=int, choices=(8, 9), default=9,
                        help="metadata.yaml version (default 9, ROS 2 Jazzy)")
    parser.add_argument("--stamp", choices=("receive", "header"), default="receive",
                        help="message timestamp: receive time (default, as rosbag2) or "
                             "header.stamp")
    parser.add_argument("--duration", type=float, default=None,
                        help="stop after this many wall seconds (default: until Ctrl-C)")
    _transport_option(parser)
    ns = _parse(parser, argv)
    if isinstance(ns, int):
        return ns
    topics = list(ns.topics_positional) + list(ns.topics)
    every = ns.all or ns.all_topics
    every_service = ns.all or ns.all_services
    problem = _record_usage_problem(ns, topics, every)
    if problem:
        sys.stderr.write(parser.format_usage() + f"posekit bag record: error: {problem}\n")
        return 2
    _warn_record_overrides(ns, topics, every, every_service)
    output = ns.output or default_bag_name()
    if Path(output).is_dir():
        sys.stderr.write(f"posekit bag record: error: Output folder '{output}' already exists.\n")
        return 1
    custom = _custom_data(ns.custom_data)
    if custom is None:
        return 2
    compression: str | None = "zstd"
    if ns.compression_mode != "none":
        compression = ns.compression_mode
    elif ns.no_compression:
        compression = None

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
                output,
                None if every else (topics or None),
                all_topics=every,
                services=None if every_service else ns.services,
                all_services=every_service,
                exclude_services=ns.exclude_services,
                topic_types=ns.topic_types,
                exclude_topic_types=ns.exclude_topic_types,
                context=ctx,
                node_name=ns.node_name,
                version=ns.metadata_version,
                compression=compression,
                stamp=ns.stamp,
                include_hidden=ns.include_hidden_topics,
                exclude=["/clock", *ns.exclude_topics],
                regex=None if (every or every_service) else (ns.regex or None),
                exclude_regex=ns.exclude_regex or None,
                max_bag_size=ns.max_bag_size,
                max_bag_duration=ns.max_bag_duration,
            )
            for key, value in custom.items():
                recorder.set_custom_data(key, value)
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
            f"{output}\n"
        )
        return 0
    finally:
        if own:
            ctx.try_shutdown()


def _record_usage_problem(ns: argparse.Namespace, topics: list[str], every: bool) -> str:
    """rosbag2 Jazzy's argument checks of ``ros2 bag record``, with its wording."""
    if not (every or ns.all_services or ns.services or topics or ns.topic_types or ns.regex):
        return ("Need to specify at least one option out of --all, --all-topics, "
                "--all-services, --services, --topics, --topic-types or --regex")
    if ns.exclude_regex and not (every or ns.topic_types or ns.all_services or ns.regex):
        return ("--exclude-regex argument requires either --all, --all-topics, --topic-types, "
                "--all-services or --regex")
    if ns.exclude_topics and not (every or ns.topic_types or ns.regex):
        return ("--exclude-topics argument requires either --all, --all-topics, "
                "--topic-types or --regex")
    if ns.exclude_topic_types and not (every or ns.topic_types or ns.regex):
        return "--exclude-topic-types argument requires either --all, --all-topics or --regex"
    if ns.exclude_services and not (ns.all or ns.all_services or ns.regex):
        return "--exclude-services argument requires either --all, --all-services or --regex"
    if ns.compression_format and ns.compression_mode == "none":
        return "Invalid choice: Cannot specify compression format without a compression mode."
    if ns.max_bag_size < 0 or ns.max_bag_duration < 0:
        return "--max-bag-size and --max-bag-duration must be >= 0"
    if ns.duration is not None and not ns.duration >= 0:
        return f"--duration must be >= 0, got {ns.duration}"
    return ""


KEYBOARD_HELP = (
    "Press SPACE for Pause/Resume",
    "Press CURSOR_RIGHT for Play Next Message",
    "Press CURSOR_UP for Increase Rate 10%",
    "Press CURSOR_DOWN for Decrease Rate 10%",
)
#: terminal key sequences -> player action, as ros2 bag play's keyboard handler
KEYS = {" ": "toggle", "\x1b[C": "next", "\x1b[A": "faster", "\x1b[B": "slower"}


def handle_key(player: Any, key: str) -> str | None:
    """Apply one key of ros2 bag play's keyboard controls to ``player``; returns the action."""
    action = KEYS.get(key)
    if action == "toggle":
        player.toggle_pause()
    elif action == "next":
        player.play_next()
    elif action == "faster":
        player.set_rate(player.rate * 1.1)
    elif action == "slower":
        player.set_rate(player.rate * 0.9)
    return action


def _keyboard_thread(player: Any, fd: int) -> Any:
    """Read keys from the terminal ``fd`` (cbreak mode) until the player stops."""
    import select
    import termios
    import threading
    import tty

    saved = termios.tcgetattr(fd)
    tty.setcbreak(fd)

    def run() -> None:
        pending = ""
        while not player._stopped:
            ready, _, _ = select.select([fd], [], [], 0.1)
            if not ready:
                pending = ""
                continue
            data = os.read(fd, 16).decode(errors="replace")
            if not data:
                return
            pending += data
            while pending:
                for key in KEYS:
                    if pending.startswith(key):
                        handle_key(player, key)
                        pending = pending[len(key):]
                        break
                else:
                    if pending.startswith("\x1b") and len(pending) < 3:
                        break  # the rest of an arrow key is on its way
                    pending = pending[1:]

    thread = threading.Thread(target=run, name="bag-play-keyboard", daemon=True)
    thread.start()

    def restore() -> None:
        termios.tcsetattr(fd, termios.TCSADRAIN, saved)

    return restore


def _progress_printer(player: Any, hz: float, err: TextIO) -> Any:
    """``progress(bag_ns, paused)`` writing one updating status line at most ``hz`` times/s."""
    last = [0.0]
    duration = max(player.duration_ns, 0) / 1e9

    def progress(bag_ns: int, paused: bool) -> None:
        now = time.monotonic()
        if hz <= 0 or now - last[0] < 1.0 / hz:
            return
        last[0] = now
        state = "PAUSED " if paused else "RUNNING"
        elapsed = (bag_ns - player.start_ns) / 1e9
        err.write(f" [{state}]  Bag Time: {bag_ns / 1e9:13.6f}  "
                  f"Duration: {elapsed:.6f}/{duration:.6f}\r")
        err.flush()

    return progress


def _remaps(pairs: Sequence[str]) -> dict[str, str]:
    out: dict[str, str] = {}
    for pair in pairs:
        old, sep, new = pair.partition(":=")
        if not sep or not old or not new:
            raise _UsageError(f"posekit bag play: error: --remap needs old:=new, got {pair!r}")
        out[old] = new
    return out


def _play_topics(bag: str, ns: argparse.Namespace) -> list[str] | None:
    """The recorded topics the selection options pick, as rosbag2 Jazzy's player does (None: all).

    ``--topics``, ``--services``, ``-e``, ``-x``, ``--exclude-topics`` and
    ``--exclude-services``: topic options select among topics and service options among service
    event topics (``--topics`` alone still plays every recorded service), the regular
    expressions apply to both. A regular expression must match a *whole* name (a topic's, or a
    service's event topic ``/svc/_service_event``), as the player's ``std::regex_match`` does;
    ``record``'s expressions only need to match part of a name (``std::regex_search``).
    """
    import re

    from posekit.bag.info import SERVICE_EVENT_SUFFIX, is_service_event_topic

    if not (ns.topics or ns.services or ns.regex or ns.exclude_regex or ns.exclude_topics
            or ns.exclude_services):
        return None
    from posekit.bag import bag_info

    try:
        include = re.compile(ns.regex) if ns.regex else None
        exclude = re.compile(ns.exclude_regex) if ns.exclude_regex else None
    except re.error as exc:
        raise _UsageError(f"posekit bag play: error: invalid regular expression: {exc}") \
            from None

    def events(services: list[str]) -> set[str]:
        return {"/" + s.strip("/").removesuffix(SERVICE_EVENT_SUFFIX.lstrip("/")).rstrip("/")
                + SERVICE_EVENT_SUFFIX for s in services}

    recorded_topics = bag_info(bag).topics
    # A listed topic the bag lacks is the player's error ("not in bag"), as before.
    chosen = [t for t in ns.topics if t not in {r.name for r in recorded_topics}]
    for recorded in recorded_topics:
        topic = recorded.name
        if is_service_event_topic(topic, recorded.msgtype):
            listed, excluded = events(ns.services), events(ns.exclude_services)
        else:
            listed, excluded = set(ns.topics), set(ns.exclude_topics)
        picked = (not listed and include is None) or topic in listed or (
            include is not None and include.fullmatch(topic) is not None)
        if picked and topic not in excluded and not (
                exclude is not None and exclude.fullmatch(topic)):
            chosen.append(topic)
    if not chosen:
        raise _UsageError("posekit bag play: error: no recorded topic matches the selection")
    return chosen


def play(argv: Sequence[str], *, context: Any = None, err: TextIO | None = None) -> int:
    """``posekit bag play``; ``context`` (tests) replaces the tool's own context."""
    err = err or sys.stderr
    parser = _Parser(prog="posekit bag play",
                     description="Publish a bag at its recorded timing, with /clock.")
    parser.add_argument("bag", help="rosbag2 directory")
    parser.add_argument("-r", "--rate", type=float, default=1.0,
                        help="rate at which to play back messages (> 0)")
    parser.add_argument("-l", "--loop", action="store_true",
                        help="start back at the beginning on reaching the end, indefinitely")
    parser.add_argument("--topics", nargs="+", default=[], metavar="TOPIC",
                        help="space-delimited list of topics to play")
    parser.add_argument("-e", "--regex", default="",
                        help="play only topics and services whose whole name matches the "
                             "regular expression")
    parser.add_argument("-x", "--exclude-regex", default="",
                        help="regular expression excluding topics and services whose whole "
                             "name matches it from replay")
    parser.add_argument("--exclude-topics", nargs="+", default=[], metavar="TOPIC",
                        help="space-delimited list of topics not to play")
    parser.add_argument("--services", nargs="+", default=[], metavar="SERVICE",
                        help="space-delimited list of services to play (their recorded "
                             "events)")
    parser.add_argument("--exclude-services", nargs="+", default=[], metavar="SERVICE",
                        help="space-delimited list of services not to play")
    parser.add_argument("--publish-service-requests", action="store_true",
                        help="publish recorded service requests instead of recorded service "
                             "events")
    parser.add_argument("--service-requests-source", default="service_introspection",
                        choices=("service_introspection", "client_introspection"),
                        help="the events the requests to replay come from (with "
                             "--publish-service-requests): the servers' (default) or the "
                             "clients'")
    parser.add_argument("--remap", "-m", nargs="+", default=[], metavar="OLD:=NEW",
                        help="topics to remap: old_topic1:=new_topic1 old_topic2:=new_topic2")
    parser.add_argument("--clock", type=float, nargs="?", const=40.0, default=100.0,
                        metavar="HZ",
                        help="/clock messages per second (posekit publishes /clock by default "
                             "at 100 Hz; --clock alone: 40 Hz, as ros2)")
    parser.add_argument("--no-clock", action="store_true", help="do not publish /clock")
    parser.add_argument("-d", "--delay", type=float, default=0.0,
                        help="sleep duration before play (each loop), in seconds")
    parser.add_argument("-p", "--start-paused", action="store_true",
                        help="start the playback player in a paused state")
    parser.add_argument("--start-offset", type=float, default=0.0,
                        help="start the playback player this many seconds into the bag")
    parser.add_argument("--disable-keyboard-controls", action="store_true",
                        help="disables keyboard controls for playback")
    parser.add_argument("--progress-bar", type=float, default=3.0, metavar="HZ",
                        help="status line updates per second on stderr (0: none; default 3)")
    _transport_option(parser)
    ns = _parse(parser, argv)
    if isinstance(ns, int):
        return ns
    try:
        remap = _remaps(ns.remap)
        topics = _play_topics(ns.bag, ns)
    except _UsageError as exc:
        err.write(parser.format_usage() + f"{exc}\n")
        return 2

    from posekit.bag import BagError, Player
    from posekit.runtime.executors import SingleThreadedExecutor

    try:
        ctx, own = _context(context, _transport_name(ns))
    except Exception as exc:
        sys.stderr.write(f"posekit bag play: cannot start the transport: {exc}\n")
        return 1
    restore: Any = None
    try:
        try:
            player = Player(ns.bag, context=ctx, topics=topics, rate=ns.rate,
                            loop=ns.loop, publish_clock=not ns.no_clock,
                            clock_frequency=ns.clock, start_offset=ns.start_offset,
                            start_paused=ns.start_paused, remap=remap, delay=ns.delay,
                            publish_service_requests=ns.publish_service_requests,
                            service_requests_source=ns.service_requests_source)
        except BagError as exc:
            err.write(f"posekit bag play: {exc}\n")
            return 1
        executor = SingleThreadedExecutor(context=ctx)
        if not ns.disable_keyboard_controls and sys.stdin.isatty():
            logger = player.node.get_logger()
            logger.info("Adding keyboard callbacks.")
            for line in KEYBOARD_HELP:
                logger.info(line)
            restore = _keyboard_thread(player, sys.stdin.fileno())
        try:
            player.play(executor, progress=_progress_printer(player, ns.progress_bar, err)
                        if ns.progress_bar > 0 else None)
        except KeyboardInterrupt:
            pass
        except BagError as exc:
            err.write(f"posekit bag play: {exc}\n")
            return 1
        finally:
            if ns.progress_bar > 0:
                err.write("\n")
            executor.shutdown()
            player.close()
        if player.missing:
            err.write(
                f"posekit bag play: {ns.bag} is damaged: {player.missing} of the messages "
                "its metadata lists could not be read (posekit bag info / reindex)\n"
            )
            return 1
        return 0
    finally:
        if restore is not None:
            restore()
        if own:
            ctx.try_shutdown()


def info(argv: Sequence[str], *, out: TextIO | None = None) -> int:
    """``posekit bag info DIR [-t] [-v]``."""
    parser = _Parser(prog="posekit bag info", description="Print a bag's summary.")
    parser.add_argument("bag", help="rosbag2 directory")
    parser.add_argument("-t", "--topic-name", action="store_true",
                        help="only display topic names")
    parser.add_argument("-v", "--verbose", action="store_true",
                        help="display request/response information for services (and the "
                             "metadata version, compression and offered QoS)")
    ns = _parse(parser, argv)
    if isinstance(ns, int):
        return ns
    from posekit.bag import BagError, bag_info, format_info
    from posekit.bag.info import is_service_event_topic, service_counts

    out = out or sys.stdout
    try:
        summary = bag_info(ns.bag)
        counts = service_counts(ns.bag) if ns.verbose else None
    except BagError as exc:
        sys.stderr.write(f"posekit bag info: {exc}\n")
        return 1
    if ns.topic_name and ns.verbose:
        out.write("Warning! You have set both the '-t' and '-v' parameters. The '-t' parameter "
                  "will be ignored.\n")
    if ns.topic_name and not ns.verbose:
        out.write("".join(f"{t.name}\n" for t in summary.topics
                          if not is_service_event_topic(t.name, t.msgtype)))
        return 0
    out.write(format_info(summary, verbose=ns.verbose, service_counts=counts))
    return 0


def convert(argv: Sequence[str]) -> int:
    """``posekit bag convert -i BAG [STORAGE] [-i ...] -o OUTPUT_OPTIONS.yaml``."""
    parser = _Parser(prog="posekit bag convert",
                     description="Merge, split, select and recompress bags (ros2 bag convert).")
    parser.add_argument("-i", "--input", required=True, action="append", nargs="+",
                        metavar=("uri", "storage_id"),
                        help="URI (and optional storage ID) of an input bag; repeatable")
    parser.add_argument("-o", "--output-options", required=True,
                        help="YAML file with a top-level 'output_bags' list of output bag "
                             "options (uri, storage_id, max_bagfile_size, "
                             "max_bagfile_duration, compression_mode, compression_format, "
                             "all_topics, topics, regex, exclude_regex, exclude_topics, "
                             "include_hidden_topics)")
    ns = _parse(parser, argv)
    if isinstance(ns, int):
        return ns
    for entry in ns.input:
        if len(entry) > 2:
            sys.stderr.write(parser.format_usage() + "posekit bag convert: error: --input "
                             f"expects 1 or 2 arguments, {len(entry)} provided\n")
            return 2
        if len(entry) == 2 and entry[1] not in ("", "mcap", "sqlite3"):
            sys.stderr.write(f"posekit bag convert: error: unknown storage id {entry[1]!r}\n")
            return 2

    from posekit.bag.convert import convert as rewrite
    from posekit.bag.convert import load_output_options

    counts = rewrite([entry[0] for entry in ns.input], load_output_options(ns.output_options))
    for uri, count in counts.items():
        sys.stderr.write(f"posekit bag convert: wrote {count} messages to {uri}\n")
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
