"""posekit.worlds: the scenes the simulation, the cameras and the viewer share.

The course's worlds as validated data and a loader for users' own world files
(:mod:`posekit.worlds.world`: :func:`load_world`, :class:`World` and its box, wall, camera and
static-transform specs, :func:`marker_poses`), and the ArUco box model their boxes use
(:mod:`posekit.worlds.aruco_box`: :data:`ARUCO_BOX`, ground truth of every marker), and
the world's solid geometry as arrays with vectorised ray casting
(:mod:`posekit.worlds.obstacles`: ``BoxObstacles``, ``WallSegments``, ``cast_rays``). Needs
numpy and :mod:`posekit.geometry` only (PyYAML for ``.yaml`` world files); the robot's
simulator, the vision cameras and the viewer build on it.
"""

from __future__ import annotations

from posekit.worlds.aruco_box import (
    ARUCO_BOX,
    ArucoBoxModel,
    BoxFace,
    MarkerGroundTruth,
    marker_corners_local,
)
from posekit.worlds.errors import WorldError
from posekit.worlds.world import (
    MAX_CAMERA_PIXELS,
    MAX_CAMERA_RATE_HZ,
    MAX_CAMERA_SIDE,
    MAX_LIST_ITEMS,
    MAX_WORLD_FILE_BYTES,
    WORLDS,
    BoxSpec,
    CameraSpec,
    MarkerPose,
    StaticTransformSpec,
    WallSpec,
    World,
    box_half_extents,
    load_world,
    marker_poses,
    world_names,
)

__all__ = [
    "ARUCO_BOX",
    "MAX_CAMERA_PIXELS",
    "MAX_CAMERA_RATE_HZ",
    "MAX_CAMERA_SIDE",
    "MAX_LIST_ITEMS",
    "MAX_WORLD_FILE_BYTES",
    "WORLDS",
    "ArucoBoxModel",
    "BoxFace",
    "BoxSpec",
    "CameraSpec",
    "MarkerGroundTruth",
    "MarkerPose",
    "StaticTransformSpec",
    "WallSpec",
    "World",
    "WorldError",
    "box_half_extents",
    "load_world",
    "marker_corners_local",
    "marker_poses",
    "world_names",
]
