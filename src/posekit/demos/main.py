"""The main demo that ``make demo`` (and ``posekit demo``) runs.

:mod:`posekit.demos.marker_demo`: the lecture's ArUco marker listener, simulated end to end.
Arguments are passed on (``--seconds``, ``--output-dir``, ``--seed``).
"""

from __future__ import annotations

import sys
from collections.abc import Sequence


def main(argv: Sequence[str] | None = None) -> int:
    """Run the main demo; returns the exit code."""
    from posekit.demos.marker_demo import main as marker_demo

    return marker_demo(list(argv) if argv is not None else [])


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
