"""Every named scenario: importing this registers the robot's and the vision demos' scenarios."""

from __future__ import annotations

import importlib

from posekit.robot.scenarios import get_scenario, run_scenario, scenario_names

__all__ = ["get_scenario", "run_scenario", "scenario_names"]

# Each module registers its scenarios when imported; vision is optional (needs OpenCV).
for _module in ("posekit.vision.scenarios", "posekit.demos.lecture"):
    try:
        importlib.import_module(_module)
    except ModuleNotFoundError as _exc:
        if _exc.name not in (_module, "cv2"):
            raise
