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
    ("tf", "monitor"): ("posekit.cli.tf_monitor:main", "tf2_monitor: delays and rates of frames"),
    ("tf", "tree"): ("posekit.cli.view_frames:main_tree", "print the frame tree"),
    ("topic", "list"): ("posekit.cli.topic_list:main_list", "list topics (-t: with types)"),
    ("topic", "info"): ("posekit.cli.topic_list:main_info", "type and endpoint counts of a topic"),
    ("topic", "type"): ("posekit.cli.topic_list:main_type", "print a topic's type"),
    ("topic", "find"): ("posekit.cli.topic_list:main_find", "list the topics of a type"),
    ("topic", "echo"): ("posekit.cli.topic_echo:main_echo", "print a topic's messages"),
    ("topic", "hz"): ("posekit.cli.topic_rate:main_hz", "average receive rate of a topic"),
    ("topic", "bw"): ("posekit.cli.topic_rate:main_bw", "bandwidth used by a topic"),
    ("topic", "delay"): ("posekit.cli.topic_rate:main_delay", "delay of a topic from its header"),
    ("topic", "pub"): ("posekit.cli.topic_pub:main_pub", "publish a message (YAML values)"),
    ("node", "list"): ("posekit.cli.node_cmd:main_list", "list nodes on the graph"),
    ("node", "info"): ("posekit.cli.node_cmd:main_info", "a node's topics, services, actions"),
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
    ("lifecycle", "nodes"): ("posekit.cli.lifecycle_cmd:main_nodes", "list lifecycle nodes"),
    ("lifecycle", "get"): ("posekit.cli.lifecycle_cmd:main_get", "a lifecycle node's state"),
    ("lifecycle", "list"): ("posekit.cli.lifecycle_cmd:main_list",
                            "available transitions (-a: all)"),
    ("lifecycle", "set"): ("posekit.cli.lifecycle_cmd:main_set", "trigger a transition"),
    ("service", "list"): ("posekit.cli.service_cmd:main_list", "list services (-t: types)"),
    ("service", "type"): ("posekit.cli.service_cmd:main_type", "print a service's type"),
    ("service", "find"): ("posekit.cli.service_cmd:main_find", "services of a type"),
    ("service", "call"): ("posekit.cli.service_cmd:main_call", "call a service (YAML values)"),
    ("service", "echo"): ("posekit.cli.service_cmd:main_echo",
                          "print a service's introspection events"),
    ("router", None): ("posekit.cli.router_cmd:main", "run a zenoh router until Ctrl-C"),
    ("bag", "record"): ("posekit.cli.bag_cmd:record", "record topics to a ROS 2 bag (MCAP)"),
    ("bag", "play"): ("posekit.cli.bag_cmd:play", "play a bag back on sim time"),
    ("bag", "convert"): ("posekit.cli.bag_cmd:convert", "merge/split/filter bags (YAML options)"),
    ("bag", "info"): ("posekit.cli.bag_cmd:info", "summarise a bag like ros2 bag info"),
    ("bag", "reindex"): ("posekit.cli.bag_cmd:reindex", "recover a bag whose recorder died"),
    ("view", None): ("posekit.cli.view_cmd:main", "serve the browser viewer (RViz2's role)"),
    ("plot", "odometry"): ("posekit.cli.plot_cmd:main_odometry", "plot odometry vs truth"),
    ("plot", "topic"): ("posekit.cli.plot_cmd:main_topic", "plot fields of a recorded topic"),
    ("launch", None): ("posekit.cli.launch_cmd:main", "run a scenario or a launch file"),
    ("run", None): ("posekit.cli.run_cmd:main", "run PACKAGE EXECUTABLE like ros2 run"),
    ("pkg", "list"): ("posekit.cli.pkg_cmd:main_list", "the packages posekit run knows"),
    ("pkg", "executables"): ("posekit.cli.pkg_cmd:main_executables",
                             "their executables (PACKAGE: one package's)"),
    ("demo", None): ("posekit.demos.main:main", "run the main demo"),
}


def _table(rows: list[tuple[str, str]]) -> list[str]:
    """``  name  text`` lines, the texts in one column two spaces after the longest name."""
    width = max(len(name) for name, _ in rows) + 2
    return [f"  {name:<{width}}{text}" for name, text in rows]


def _usage() -> str:
    rows = [(group if command is None else f"{group} {command}", text)
            for (group, command), (_, text) in sorted(_COMMANDS.items(), key=lambda kv: kv[0][0])]
    return "\n".join(["usage: posekit COMMAND [ARGS...]", "", "commands:", *_table(rows)]) + "\n"


def _group_usage(group: str) -> str:
    verbs = [(command, text) for (g, command), (_, text) in _COMMANDS.items()
             if g == group and command is not None]
    lines = [f"usage: posekit {group} VERB [ARGS...]", "", "verbs:", *_table(sorted(verbs))]
    lines += ["", f"Call `posekit {group} <verb> -h` for more detailed usage."]
    return "\n".join(lines) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``posekit`` with ``argv`` (default: the process arguments); returns the exit code.

    Every error a user can cause ends in one line ``posekit <verb>: error: <reason>`` and a
    non-zero exit (see :mod:`posekit.cli.errors`), never in a traceback.
    """
    args = list(sys.argv[1:] if argv is None else argv)
    if not args or args[0] in ("-h", "--help", "help"):
        sys.stdout.write(_usage())
        return 0 if args else 2
    group, rest = args[0], args[1:]
    key: tuple[str, str | None] = (group, None)
    groups = {g for g, _ in _COMMANDS}
    if key not in _COMMANDS:
        if group not in groups:
            sys.stderr.write(_usage() + f"posekit: error: unknown command {group!r}\n")
            return 2
        if not rest or rest[0] in ("-h", "--help"):  # ros2 lists a command's verbs
            sys.stdout.write(_group_usage(group))
            return 0
        if (group, rest[0]) not in _COMMANDS:
            sys.stderr.write(_group_usage(group) +
                             f"posekit {group}: error: unknown verb {rest[0]!r}\n")
            return 2
        key, rest = (group, rest[0]), rest[1:]
    prog = "posekit " + " ".join(k for k in key if k)
    target = _COMMANDS[key][0]
    module_name, _, function_name = target.partition(":")
    try:
        function = getattr(importlib.import_module(module_name), function_name)
        with _sigterm_as_interrupt():
            result = function(rest)
    except KeyboardInterrupt:
        return 130
    except SystemExit:  # argparse's usage errors and --help have printed their text
        raise
    except Exception as exc:
        from posekit.cli.errors import report

        return report(exc, prog)
    return int(result or 0)


@contextlib.contextmanager
def _sigterm_as_interrupt() -> Iterator[None]:
    """Make SIGTERM stop a tool as Ctrl-C does.

    SIGTERM comes from ``timeout``, systemd or ``docker stop``; the tool then finishes its work
    (a bag's index and metadata.yaml) instead of dying mid-write.
    """
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
