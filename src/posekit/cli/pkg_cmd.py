"""``posekit pkg list|executables``: ``ros2 pkg``'s two listing verbs over ``posekit run``'s table.

``list`` prints the package names ``posekit run`` knows, sorted; ``executables [PACKAGE]``
prints ``package executable`` lines, sorted (``Package 'x' not found`` on stderr, exit 1,
for an unknown one), as ros2pkg prints them. The table is
:data:`posekit.demos.lecture.EXECUTABLES`.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from typing import TextIO

__all__ = ["main_executables", "main_list"]


def main_list(argv: Sequence[str], *, out: TextIO | None = None) -> int:
    """``posekit pkg list``."""
    from posekit.demos.lecture import EXECUTABLES

    argparse.ArgumentParser(prog="posekit pkg list",
                            description="Output a list of available packages").parse_args(argv)
    out = out or sys.stdout
    for package in sorted({package for package, _ in EXECUTABLES}):
        out.write(f"{package}\n")
    return 0


def main_executables(argv: Sequence[str], *, out: TextIO | None = None,
                     err: TextIO | None = None) -> int:
    """``posekit pkg executables [PACKAGE]``."""
    from posekit.demos.lecture import EXECUTABLES

    parser = argparse.ArgumentParser(prog="posekit pkg executables",
                                     description="Output a list of package specific executables")
    parser.add_argument("package_name", nargs="?", help="The package name")
    ns = parser.parse_args(argv)
    out, err = out or sys.stdout, err or sys.stderr
    found = sorted((p, e) for p, e in EXECUTABLES if ns.package_name in (None, p))
    if not found:
        err.write(f"Package '{ns.package_name}' not found\n")
        return 1
    for package, executable in found:
        out.write(f"{package} {executable}\n")
    return 0
