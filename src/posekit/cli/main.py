"""``posekit`` entry point: dispatches ``posekit GROUP [COMMAND] ARGS`` to the tool modules.

Each tool parses its own arguments (several reproduce ROS tools' hand-written parsers byte for
byte), so this module only routes and imports a tool when it is used.
"""

from __future__ import annotations

import contextlib
import importlib
import signal
import sys
import threading
from collections.abc import Iterator, Sequence

__all__ = ["main"]

# (group, command) -> "module:function"; command None means the group is the command.
_COMMANDS: dict[tuple[str, str | None], tuple[str, str]] = {
    ("tf", "echo"): ("posekit.cli.tf_echo:main", "print a transform like tf2_echo"),
    ("tf", "static"): ("posekit.cli.tf_static:main", "static_transform_publisher"),
    ("tf", "frames"): ("posekit.cli.view_frames:main", "view_frames: write frames_*.gv/.pdf"),
    ("tf", "tree"): ("posekit.cli.view_frames:main_tree", "print the frame tree"),
    ("topic", "list"): ("posekit.cli.topic_cmd:main_list", "list topics (-t: with types)"),
    ("topic", "info"): ("posekit.cli.topic_cmd:main_info", "type and endpoint counts of a topic"),
    ("topic", "echo"): ("posekit.cli.topic_cmd:main_echo", "print a topic's messages"),
    ("topic", "hz"): ("posekit.cli.topic_cmd:main_hz", "average receive rate of a topic"),
    ("topic", "pub"): ("posekit.cli.topic_cmd:main_pub", "publish a message (YAML values)"),
    ("node", "list"): ("posekit.cli.node_cmd:main_list", "list nodes on the graph"),
    ("action", "list"): ("posekit.cli.action_cmd:main_list", "list actions (-t: with types)"),
    ("action", "info"): ("posekit.cli.action_cmd:main_info", "clients and servers of an action"),
    ("action", "send_goal"): ("posekit.cli.action_cmd:main_send_goal",
                              "send an action goal (YAML), -f: print feedback"),
    ("interface", None): ("posekit.cli.interface_cmd:main", "list|show|proto msg/srv/action types"),
    ("param", "list"): ("posekit.cli.param_cmd:main_list", "list a node's parameters"),
    ("param", "get"): ("posekit.cli.param_cmd:main_get", "print a parameter's value"),
    ("param", "set"): ("posekit.cli.param_cmd:main_set", "set a parameter (YAML value)"),
    ("param", "delete"): ("posekit.cli.param_cmd:main_delete", "delete a parameter"),
    ("param", "describe"): ("posekit.cli.param_cmd:main_describe", "describe parameters"),
    ("param", "dump"): ("posekit.cli.param_cmd:main_dump", "print a node's parameters as YAML"),
    ("param", "load"): ("posekit.cli.param_cmd:main_load", "set parameters from a YAML file"),
    ("service", "list"): ("posekit.cli.service_cmd:main_list", "list services (-t: types)"),
    ("service", "type"): ("posekit.cli.service_cmd:main_type", "print a service's type"),
    ("service", "find"): ("posekit.cli.service_cmd:main_find", "services of a type"),
    ("service", "call"): ("posekit.cli.service_cmd:main_call", "call a service (YAML values)"),
    ("router", None): ("posekit.cli.router_cmd:main", "run a zenoh router until Ctrl-C"),
    ("bag", "record"): ("posekit.cli.bag_cmd:record", "record topics to a ROS 2 bag (MCAP)"),
    ("bag", "play"): ("posekit.cli.bag_cmd:play", "play a bag back on sim time"),
    ("bag", "info"): ("posekit.cli.bag_cmd:info", "summarise a bag like ros2 bag info"),
    ("bag", "reindex"): ("posekit.cli.bag_cmd:reindex", "recover a bag whose recorder died"),
    ("view", None): ("posekit.cli.view_cmd:main", "serve the browser viewer (RViz2's role)"),
    ("plot", "odometry"): ("posekit.cli.plot_cmd:main_odometry", "plot odometry vs truth"),
    ("launch", None): ("posekit.cli.launch_cmd:main", "run a scenario or a launch file"),
    ("run", None): ("posekit.cli.run_cmd:main", "run PACKAGE EXECUTABLE like ros2 run"),
    ("demo", None): ("posekit.demos.main:main", "run the main demo"),
}


def _usage() -> str:
    lines = ["usage: posekit COMMAND [ARGS...]", "", "commands:"]
    for (group, command), (_, text) in sorted(_COMMANDS.items(), key=lambda kv: kv[0][0]):
        name = group if command is None else f"{group} {command}"
        lines.append(f"  {name:<16}{text}")
    return "\n".join(lines) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``posekit`` with ``argv`` (default: the process arguments); returns the exit code."""
    args = list(sys.argv[1:] if argv is None else argv)
    if not args or args[0] in ("-h", "--help", "help"):
        sys.stdout.write(_usage())
        return 0 if args else 2
    group, rest = args[0], args[1:]
    key: tuple[str, str | None] = (group, None)
    if key not in _COMMANDS:
        if not rest or (group, rest[0]) not in _COMMANDS:
            sys.stderr.write(f"posekit: unknown command {' '.join(args[:2])!r}\n\n{_usage()}")
            return 2
        key, rest = (group, rest[0]), rest[1:]
    target = _COMMANDS[key][0]
    module_name, _, function_name = target.partition(":")
    function = getattr(importlib.import_module(module_name), function_name)
    from posekit.runtime.transport import ServicesNotSupportedError, UnknownTransportError

    try:
        with _sigterm_as_interrupt():
            result = function(rest)
    except KeyboardInterrupt:
        return 130
    except (ServicesNotSupportedError, UnknownTransportError) as exc:
        # e.g. a service call on the dds transport, or --transport with a typo: one line
        name = group if key[1] is None else f"{group} {key[1]}"
        sys.stderr.write(f"posekit {name}: {exc}\n")
        return 1
    return int(result or 0)


@contextlib.contextmanager
def _sigterm_as_interrupt() -> Iterator[None]:
    """SIGTERM (``timeout``, systemd, ``docker stop``) stops a tool as Ctrl-C does, so it
    finishes its work (a bag's index and metadata.yaml) instead of dying mid-write."""
    if threading.current_thread() is not threading.main_thread() or (
        signal.getsignal(signal.SIGTERM) is not signal.SIG_DFL
    ):
        yield
        return

    def interrupt(signum: int, frame: object) -> None:
        del signum, frame
        raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, signal.SIG_DFL)


if __name__ == "__main__":
    sys.exit(main())
