"""The world's static objects (boxes with ArUco markers, fixed cameras) as the page draws them.

Worlds are not published on a topic: the page gets them once, in the ``hello`` message.
Poses are 4x4 row-major matrices ``T_frame_object`` in ``frame`` (the world frame, which
posekit's worlds make equal to ``odom``). Marker images are PNG data URLs generated with
OpenCV's ``cv2.aruco.generateImageMarker`` (the same dictionary as the world's model).
"""

from __future__ import annotations

import base64
from functools import lru_cache
from typing import Any

import numpy as np

from posekit.worlds import ARUCO_BOX, World, load_world, marker_poses

__all__ = ["WORLD_FRAME", "marker_png_data_url", "world_payload"]

#: Frame of the world's poses (the robot spawns in odom; see robot/nodes/world_simulation).
WORLD_FRAME = "odom"


def _rows(m: Any) -> list[float]:
    return [round(float(v), 6) for v in np.asarray(m, dtype=np.float64).reshape(16)]


@lru_cache(maxsize=64)
def marker_png_data_url(dictionary: str, marker_id: int, pixels: int = 120) -> str:
    """A PNG data URL of ArUco marker ``marker_id`` of ``dictionary`` (black border included)."""
    import cv2

    aruco = cv2.aruco
    dict_id = getattr(aruco, dictionary, None)
    if dict_id is None:
        raise ValueError(f"unknown ArUco dictionary {dictionary!r}")
    image = aruco.generateImageMarker(aruco.getPredefinedDictionary(dict_id), marker_id, pixels)
    ok, png = cv2.imencode(".png", image)
    if not ok:
        raise ValueError(f"cannot encode marker {marker_id} as PNG")
    return "data:image/png;base64," + base64.b64encode(png.tobytes()).decode("ascii")


def world_payload(world: World | str | None) -> dict[str, Any] | None:
    """The ``world`` entry of the hello message, or None without a world."""
    if world is None:
        return None
    if isinstance(world, str):
        world = load_world(world)
    sizes = {ARUCO_BOX.name: ARUCO_BOX.size}
    boxes = [
        {
            "name": b.name,
            "size": sizes.get(b.model, ARUCO_BOX.size),
            "T": _rows(b.T_world_box),
        }
        for b in world.boxes
    ]
    markers = []
    for m in marker_poses(world):
        try:
            image = marker_png_data_url(m.dictionary, m.marker_id)
        except (ImportError, ValueError):
            image = ""
        markers.append(
            {"box": m.box, "id": m.marker_id, "size": m.size, "T": _rows(m.T_world_marker),
             "image": image}
        )
    cameras = [{"name": c.name, "T": _rows(c.T_world_camera)} for c in world.cameras]
    return {
        "name": world.name,
        "frame": WORLD_FRAME,
        "boxes": boxes,
        "markers": markers,
        "cameras": cameras,
    }
