"""``posekit run PACKAGE EXECUTABLE [ARGS...]``: the lecture's ``ros2 run`` lines.

A demo executable (``posekit run robot_control_demo random_mover``) starts that node against
a running world in another process: it follows the world's ``/clock`` and talks to it over
the network transport. Parameters: ``name:=value`` or ``-p name:=value`` (checked against
what the nodes declare); ``--until-sim-time S`` stops after S simulated seconds, ``--seed N``
seeds a random node. As with ``ros2 run``, everything between ``--ros-args`` and ``--`` (or
the end) reaches the node(s) as their ROS arguments: ``-p [node:]name:=value``,
``--params-file FILE`` (sections matched by fully qualified node name, wildcards included),
``-r from:=to``, ``-r __node:=NAME``, ``-r __ns:=/NS``, ``--log-level [name:=]LEVEL``
(see :mod:`posekit.runtime.arguments`); they win over the demo's own names and parameters.
The ROS tools of the lecture map to posekit's (``posekit run tf2_ros tf2_echo odom
base_link`` is ``posekit tf echo odom base_link``, which takes posekit's options, not
``--ros-args``); ``posekit run --list`` shows every known executable.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence

__all__ = ["main"]

_PROG = "posekit run"


def _usage() -> str:
    return ("usage: posekit run PACKAGE EXECUTABLE [name:=value ...] [--until-sim-time S] "
            "[--ros-args ROS_ARGS ...]\n")


def main(argv: Sequence[str]) -> int:
    """Run ``posekit run``; returns the exit code."""
    args = list(argv)
    if args and args[0] in ("-h", "--help"):
        sys.stdout.write(_usage() + __doc__.split("\n\n", 1)[1])
        return 0
    from posekit.demos.lecture import EXECUTABLES, resolve_run
    from posekit.launch.scenarios import ScenarioError
    from posekit.runtime.arguments import (
        ROS_ARGS_FLAG,
        RCLError,
        UnknownROSArgsError,
        parse_arguments,
    )

    if args and args[0] == "--list":
        for (package, executable), target in sorted(EXECUTABLES.items()):
            what = ("posekit " + " ".join(target)) if isinstance(target, tuple) else target
            sys.stdout.write(f"{package + ' ' + executable:<48}{what}\n")
        return 0
    if len(args) < 2 or args[0].startswith("-") or args[1].startswith("-"):
        sys.stderr.write(f"{_PROG}: expected PACKAGE EXECUTABLE (posekit run --list names "
                         "them)\n")
        return 2
    try:
        target = resolve_run(args[0], args[1])
    except ScenarioError as exc:
        sys.stderr.write(f"{_PROG}: {exc}\n")
        return 2
    rest = args[2:]
    if isinstance(target, tuple):
        if ROS_ARGS_FLAG in rest:
            sys.stderr.write(f"{_PROG}: {args[0]} {args[1]} is 'posekit {' '.join(target)}', "
                             "which takes no --ros-args (see its --help for its options)\n")
            return 2
        from posekit.cli.main import main as posekit_main

        return posekit_main([*target, *rest])
    ros_arguments = None
    if ROS_ARGS_FLAG in rest:
        try:
            parsed = parse_arguments(rest)
        except (RCLError, UnknownROSArgsError) as exc:
            sys.stderr.write(f"{_PROG}: --ros-args: {exc}\n")
            return 2
        rest, ros_arguments = parsed.unparsed, parsed
    from posekit.cli.launch_cmd import main as launch_main

    return launch_main([target, *rest], prog=_PROG, ros_arguments=ros_arguments)
