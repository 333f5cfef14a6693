"""Every named scenario, registered on import.

Importing this registers the robot's, the vision demos' and the lecture's two-terminal scenarios
in :mod:`posekit.launch.scenarios` (look them up and run them there); :func:`include_scenario`
puts one into a launch file.
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from typing import Any

from posekit.launch import Node
from posekit.launch.scenarios import get_scenario

__all__ = ["SCENARIO_EXTRAS", "include_scenario"]

#: Scenarios that need an optional extra (registered only when it is installed), so that a
#: missing one is named before anything runs.
SCENARIO_EXTRAS: dict[str, str] = dict.fromkeys(
    ("aruco_box_camera_world", "aruco_box_world", "static_aruco_detector", "kdl_chain_demo",
     "dynamic_detector", "dynamic_detector_listener"),
    "vision",
)


def include_scenario(name: str, params: Mapping[str, Any] | None = None,
                     seed: int = 0) -> list[Node]:
    """The launch entries of scenario ``name``, for your own launch file.

    Put them next to your nodes (``IncludeLaunchDescription``'s role)::

        LaunchDescription([*include_scenario("aruco_box_world"), Node(MyDetector)])

    ``params`` as ``posekit launch NAME name:=value`` takes them.
    """
    return get_scenario(name).factory(dict(params or {}), int(seed)).nodes


# Each module registers its scenarios when imported; vision is optional (needs OpenCV).
for _module in ("posekit.vision.scenarios", "posekit.demos.lecture"):
    try:
        importlib.import_module(_module)
    except ModuleNotFoundError as _exc:
        if _exc.name not in (_module, "cv2"):
            raise
