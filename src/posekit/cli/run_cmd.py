"""``posekit run PACKAGE EXECUTABLE [ARGS...]``: the lecture's ``ros2 run`` lines.

A demo executable (``posekit run robot_control_demo random_mover``) starts that node against
a running world in another process: it follows the world's ``/clock`` and talks to it over
the network transport. Parameters: ``name:=value``, ``-p name:=value`` or ``--ros-args
-p name:=value``; ``--until-sim-time S`` stops after S simulated seconds, ``--seed N``
seeds a random node. The ROS tools of the lecture map to posekit's
(``posekit run tf2_ros tf2_echo odom base_link`` is ``posekit tf echo odom base_link``);
``posekit run --list`` shows every known executable.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence

__all__ = ["main"]


def _usage() -> str:
    return "usage: posekit run PACKAGE EXECUTABLE [name:=value ...] [--until-sim-time S]\n"


def main(argv: Sequence[str]) -> int:
    """Run ``posekit run``; returns the exit code."""
    args = list(argv)
    if args and args[0] in ("-h", "--help"):
        sys.stdout.write(_usage() + __doc__.split("\n\n", 1)[1])
        return 0
    from posekit.demos.lecture import EXECUTABLES, resolve_run
    from posekit.launch.scenarios import ScenarioError

    if args and args[0] == "--list":
        for (package, executable), target in sorted(EXECUTABLES.items()):
            what = ("posekit " + " ".join(target)) if isinstance(target, tuple) else target
            sys.stdout.write(f"{package + ' ' + executable:<48}{what}\n")
        return 0
    if len(args) < 2 or args[0].startswith("-") or args[1].startswith("-"):
        sys.stderr.write("posekit run: expected PACKAGE EXECUTABLE (posekit run --list names "
                         "them)\n")
        return 2
    try:
        target = resolve_run(args[0], args[1])
    except ScenarioError as exc:
        sys.stderr.write(f"posekit run: {exc}\n")
        return 2
    rest = args[2:]
    if isinstance(target, tuple):
        from posekit.cli.main import main as posekit_main

        return posekit_main([*target, *rest])
    # A ROS 2 command line passes node parameters after --ros-args as -p name:=value.
    rest = [a for a in rest if a != "--ros-args"]
    from posekit.cli.launch_cmd import main as launch_main

    return launch_main([target, *rest])
