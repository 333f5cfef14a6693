"""The course's ``aruco_box`` model: a 0.5 m cube with one DICT_5X5_250 marker per face.

One model serves the world loader (box sizes, marker poses), the simulated cameras and the
detector evaluation (:mod:`posekit.vision` re-exports it).

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

from posekit.worlds.errors import WorldError

__all__ = [
    "ARUCO_BOX",
    "ArucoBoxModel",
    "BoxFace",
    "MarkerGroundTruth",
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


#: The aruco_box face table (docs/specs/rosbot_and_worlds.md): per marker id, the face's
#: outward normal and the marker's x and y axes, in the box frame.
ARUCO_BOX_FACES: tuple[BoxFace, ...] = tuple(
    BoxFace(normal, marker_id, x_axis, y_axis)
    for marker_id, normal, x_axis, y_axis in (
        (3, (0.0, 0.0, 1.0), (-1.0, 0.0, 0.0), (0.0, -1.0, 0.0)),
        (2, (0.0, -1.0, 0.0), (0.0, 0.0, 1.0), (-1.0, 0.0, 0.0)),
        (4, (-1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (0.0, 1.0, 0.0)),
        (1, (0.0, 0.0, -1.0), (1.0, 0.0, 0.0), (0.0, -1.0, 0.0)),
        (6, (1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (0.0, -1.0, 0.0)),
        (5, (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (1.0, 0.0, 0.0)),
    )
)


@dataclass(frozen=True)
class ArucoBoxModel:
    """A cube with a square ArUco marker centred on each face.

    Attributes:
        name: the model name worlds refer to (``model: aruco_box``).
        size: cube side, metres.
        marker_size: marker side including its one-cell black border, metres.
        dictionary: OpenCV predefined dictionary name.
        faces: the six faces (normal, marker id, marker axes) in the box frame; the marker z
            axis is x × y and equals the outward normal (no mirrored face).

    Raises:
        WorldError: marker larger than the cube, or a face whose x × y is not its normal.
    """

    name: str = "aruco_box"
    size: float = 0.5
    marker_size: float = 0.2
    dictionary: str = "DICT_5X5_250"
    faces: tuple[BoxFace, ...] = field(default=ARUCO_BOX_FACES)

    def __post_init__(self) -> None:
        if not 0.0 < self.marker_size <= self.size:
            raise WorldError(
                f"need 0 < marker_size <= size, got {self.marker_size} and {self.size}"
            )
        for face in self.faces:
            x, y, n = (np.asarray(a) for a in (face.x_axis, face.y_axis, face.normal))
            if not np.allclose(np.cross(x, y), n):
                raise WorldError(f"face of marker {face.marker_id}: x × y != normal")

    @property
    def marker_ids(self) -> list[int]:
        """The marker ids of the faces, sorted."""
        return sorted(face.marker_id for face in self.faces)

    def T_box_marker(self, face: BoxFace | int) -> F64Array:
        """Pose (4x4) of the marker frame of ``face`` (a face or its marker id) in the box frame.

        Columns x, y, normal; origin at the face centre.
        """
        if not isinstance(face, BoxFace):
            face = self.face_by_id(face)
        m = np.eye(4)
        m[:3, 0] = face.x_axis
        m[:3, 1] = face.y_axis
        m[:3, 2] = face.normal
        m[:3, 3] = 0.5 * self.size * np.asarray(face.normal, dtype=np.float64)
        return m

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
