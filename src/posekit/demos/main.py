"""The main demo that ``make demo`` runs."""

from __future__ import annotations

from posekit.demos.pose_walkthrough import main

if __name__ == "__main__":
    main()
