"""Simulated cameras, the ArUco box renderer, and ArUco detection with PnP.

``camera`` needs numpy only; ``render`` and ``detector`` import OpenCV
(``pip install posekit[vision]``) and are loaded on first attribute access. The ArUco box
model (``ARUCO_BOX``, ``ArucoBoxModel``, ``BoxFace``, ``MarkerGroundTruth``,
``marker_corners_local``) lives in :mod:`posekit.worlds`; it is re-exported here because the
vision examples import it from ``posekit.vision``.
"""

from __future__ import annotations

import importlib
from typing import Any

from posekit.vision.camera import (
    OAK_RGB_CAMERA,
    OVERHEAD_CAMERA,
    R_CAMERA_FRAME_OPTICAL,
    T_CAMERA_FRAME_OPTICAL,
    PinholeCamera,
)
from posekit.vision.errors import CameraModelError, InvalidImageError, VisionError
from posekit.worlds import (
    ARUCO_BOX,
    ArucoBoxModel,
    BoxFace,
    MarkerGroundTruth,
    marker_corners_local,
)

_LAZY = {
    "BoxRenderer": "posekit.vision.render",
    "VisibleMarker": "posekit.vision.render",
    "render_boxes": "posekit.vision.render",
    "ArucoMarkerDetector": "posekit.vision.detector",
    "MarkerDetection": "posekit.vision.detector",
    "PoseCandidate": "posekit.vision.detector",
    "draw_detections": "posekit.vision.detector",
}

__all__ = [
    "ARUCO_BOX",
    "OAK_RGB_CAMERA",
    "OVERHEAD_CAMERA",
    "R_CAMERA_FRAME_OPTICAL",
    "T_CAMERA_FRAME_OPTICAL",
    "ArucoBoxModel",
    "ArucoMarkerDetector",
    "BoxFace",
    "BoxRenderer",
    "CameraModelError",
    "InvalidImageError",
    "MarkerDetection",
    "MarkerGroundTruth",
    "PinholeCamera",
    "PoseCandidate",
    "VisibleMarker",
    "VisionError",
    "draw_detections",
    "marker_corners_local",
    "render_boxes",
]


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'posekit.vision' has no attribute {name!r}")
    return getattr(importlib.import_module(module), name)
