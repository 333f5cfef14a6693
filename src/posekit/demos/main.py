"""The main demo that ``make demo`` (and ``posekit demo``) runs."""

from __future__ import annotations

import sys
from collections.abc import Sequence


def main(argv: Sequence[str] | None = None) -> int:
    """Run the main demo; returns the exit code."""
    from posekit.demos.pose_walkthrough import main as walkthrough

    walkthrough()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
