"""The course's ``aruco_box`` model: a 0.5 m cube with one DICT_5X5_250 marker per face.

Frames
------
* **Box frame** (``T_world_box``): origin at the cube's centre, axes of the SDF model.
* **Marker frame** (``T_box_marker``): OpenCV's ArUco / ``SOLVEPNP_IPPE_SQUARE`` convention.
  Origin at the marker's centre (= the face's centre), x from the top-left to the top-right
  corner (image right), y from the bottom-left to the top-left corner (image up), z = x × y
  out of the face. Corner order of a detection: TL (-L/2, +L/2), TR (+L/2, +L/2),
  BR (+L/2, -L/2), BL (-L/2, -L/2) in marker coordinates.

The face-to-marker table was derived from the model's UV coordinates
(``docs/specs/rosbot_and_worlds.md``): no face is mirrored, every marker's z points outward.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from posekit.geometry import Rotation, Transform
from posekit.robot.worlds import ARUCO_BOX as _WORLD_BOX
from posekit.vision.errors import CameraModelError

__all__ = [
    "ARUCO_BOX",
    "ArucoBoxModel",
    "BoxFace",
    "MarkerGroundTruth",
    "box_pose_matrix",
    "marker_corners_local",
]

F64Array = npt.NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class BoxFace:
    """One face of the box: its outward normal and the marker printed on it (box frame)."""

    normal: tuple[float, float, float]
    marker_id: int
    x_axis: tuple[float, float, float]
    y_axis: tuple[float, float, float]


@dataclass(frozen=True, slots=True)
class MarkerGroundTruth:
    """True pose of one marker: ``T_world_marker`` (4x4), world corners (4x3, TL TR BR BL)."""

    box_index: int
    marker_id: int
    face_normal_world: F64Array
    T_world_marker: F64Array
    corners_world: F64Array


def marker_corners_local(side: float) -> F64Array:
    """Corners (4x3) of a square of side ``side`` m, own frame: TL, TR, BR, BL (IPPE_SQUARE)."""
    h = side / 2.0
    return np.array([[-h, h, 0.0], [h, h, 0.0], [h, -h, 0.0], [-h, -h, 0.0]])


def _faces_of_world_model() -> tuple[BoxFace, ...]:
    """docs/specs/rosbot_and_worlds.md's face table, kept once in
    :data:`posekit.robot.worlds.ARUCO_BOX`."""
    def as_float(v: Sequence[float]) -> tuple[float, float, float]:
        return (float(v[0]), float(v[1]), float(v[2]))

    return tuple(
        BoxFace(as_float(normal), marker_id, as_float(x_axis), as_float(y_axis))
        for marker_id, (normal, x_axis, y_axis) in _WORLD_BOX.faces.items()
    )


def box_pose_matrix(x: float, y: float, z: float, roll: float = 0.0, pitch: float = 0.0,
                    yaw: float = 0.0) -> F64Array:
    """``T_world_box`` from an SDF ``<pose>`` (metres; rpy radians, fixed-axis x-y-z)."""
    return Transform(Rotation.from_rpy(roll, pitch, yaw), (x, y, z)).as_matrix()


@dataclass(frozen=True)
class ArucoBoxModel:
    """A cube with a square ArUco marker centred on each face.

    Attributes:
        size: cube side, metres.
        marker_size: marker side including its one-cell black border, metres.
        dictionary: OpenCV predefined dictionary name.
        faces: the six faces (normal, marker id, marker axes) in the box frame.
    """

    size: float = _WORLD_BOX.size
    marker_size: float = _WORLD_BOX.marker_size
    dictionary: str = _WORLD_BOX.dictionary
    faces: tuple[BoxFace, ...] = field(default_factory=lambda: _faces_of_world_model())

    def __post_init__(self) -> None:
        if not 0.0 < self.marker_size <= self.size:
            raise CameraModelError(
                f"need 0 < marker_size <= size, got {self.marker_size} and {self.size}"
            )
        for face in self.faces:
            x, y, n = (np.asarray(a) for a in (face.x_axis, face.y_axis, face.normal))
            if not np.allclose(np.cross(x, y), n):
                raise CameraModelError(f"face of marker {face.marker_id}: x × y != normal")

    def T_box_marker(self, face: BoxFace) -> F64Array:
        """Pose of ``face``'s marker frame in the box frame (4x4)."""
        R = np.column_stack([face.x_axis, face.y_axis, face.normal])
        t_box_marker = np.asarray(face.normal) * (self.size / 2.0)
        return Transform(Rotation.from_matrix(R), t_box_marker).as_matrix()

    def face_by_id(self, marker_id: int) -> BoxFace:
        """The face carrying ``marker_id`` (KeyError if the box has none)."""
        for face in self.faces:
            if face.marker_id == marker_id:
                return face
        raise KeyError(f"aruco_box has no marker with id {marker_id}")

    def ground_truth(self, boxes_T_world_box: Sequence[npt.ArrayLike]) -> list[MarkerGroundTruth]:
        """Every marker of every box in the world: poses and corner positions (metres)."""
        out: list[MarkerGroundTruth] = []
        local = marker_corners_local(self.marker_size)
        for i, T in enumerate(boxes_T_world_box):
            T_world_box = np.asarray(T, dtype=np.float64)
            for face in self.faces:
                T_world_marker = T_world_box @ self.T_box_marker(face)
                corners = local @ T_world_marker[:3, :3].T + T_world_marker[:3, 3]
                out.append(
                    MarkerGroundTruth(
                        box_index=i,
                        marker_id=face.marker_id,
                        face_normal_world=T_world_marker[:3, 2].copy(),
                        T_world_marker=T_world_marker,
                        corners_world=corners,
                    )
                )
        return out


#: The course's ``aruco_box`` (husarion_gz_worlds/models/aruco_box).
ARUCO_BOX = ArucoBoxModel()
