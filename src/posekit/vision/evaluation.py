"""Accuracy of render -> detect -> PnP against the renderer's ground truth.

Used by the tests, ``benchmarks/vision.py`` and ``docs/vision.md``. The scene is one
``aruco_box`` at ``(0, 0, 0.25)``; the camera looks at the centre of its -x face (marker id 4)
from ``distance`` metres, rotated ``angle`` about the world z axis through the marker centre
(angle 0 = head-on), so the camera stays at the marker's height above the ground.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from posekit.geometry import Rotation, Transform
from posekit.vision.camera import OAK_RGB_CAMERA, PinholeCamera
from posekit.worlds import ARUCO_BOX, ArucoBoxModel

__all__ = ["AccuracyCell", "accuracy_grid", "look_at", "marker_view_pose"]

F64Array = npt.NDArray[np.float64]


def look_at(eye: npt.ArrayLike, target: npt.ArrayLike,
            up: npt.ArrayLike = (0.0, 0.0, 1.0)) -> F64Array:
    """``T_world_optical`` of a camera at ``eye`` looking at ``target`` with image-up near ``up``.

    Optical axes: z towards the target, x = z × up (image right), y = z × x (image down).
    """
    e = np.asarray(eye, dtype=np.float64)
    z = np.asarray(target, dtype=np.float64) - e
    z /= np.linalg.norm(z)
    x = np.cross(z, np.asarray(up, dtype=np.float64))
    if np.linalg.norm(x) < 1e-9:
        raise ValueError("look_at: viewing direction is parallel to 'up'")
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    return Transform(Rotation.from_matrix(np.column_stack([x, y, z])), e).as_matrix()


def marker_view_pose(distance: float, angle: float) -> tuple[F64Array, F64Array]:
    """(``T_world_box``, ``T_world_optical``) of the evaluation scene, angle in radians."""
    T_world_box = Transform.from_xyz_rpy((0.0, 0.0, 0.25), (0.0, 0.0, 0.0)).as_matrix()
    centre = np.array([-0.25, 0.0, 0.25])
    eye = centre + distance * np.array([-math.cos(angle), math.sin(angle), 0.0])
    return T_world_box, look_at(eye, centre)


@dataclass(frozen=True, slots=True)
class AccuracyCell:
    """Errors over the trials of one (distance, angle) cell.

    Attributes:
        distance: camera to marker centre, metres.
        angle_deg: viewing angle from the face normal, degrees.
        trials: number of rendered frames.
        detection_rate: fraction of frames in which marker 4 was detected.
        max_position_error: worst translation error, metres.
        mean_position_error: mean translation error, metres.
        max_rotation_error_deg: worst orientation error of the chosen IPPE solution, degrees.
        max_rotation_error_best_of_two_deg: worst error of the better of the two solutions.
        mean_ambiguity_ratio: mean of the detections' ambiguity ratios.
    """

    distance: float
    angle_deg: float
    trials: int
    detection_rate: float
    max_position_error: float
    mean_position_error: float
    max_rotation_error_deg: float
    max_rotation_error_best_of_two_deg: float
    mean_ambiguity_ratio: float


def accuracy_grid(
    distances: Sequence[float],
    angles_deg: Sequence[float],
    *,
    camera: PinholeCamera = OAK_RGB_CAMERA,
    model: ArucoBoxModel = ARUCO_BOX,
    trials: int = 1,
    jitter: float = 0.0,
    noise_sigma: float = 0.0,
    seed: int = 0,
    refine_subpixel: bool = False,
) -> list[AccuracyCell]:
    """Render, detect and compare marker 4's pose with the truth for each grid cell.

    ``jitter`` (metres) moves the camera randomly around the nominal position in each trial
    (seeded), so sub-pixel placement varies between trials.
    """
    from posekit.vision.detector import ArucoMarkerDetector
    from posekit.vision.render import BoxRenderer

    renderer = BoxRenderer(camera, model, noise_sigma=noise_sigma, seed=seed)
    detector = ArucoMarkerDetector(camera.K, camera.dist_coeffs, marker_size=model.marker_size,
                                   dictionary=model.dictionary, refine_subpixel=refine_subpixel)
    face = model.face_by_id(4)
    rng = np.random.default_rng(seed)
    cells: list[AccuracyCell] = []
    for distance in distances:
        for angle_deg in angles_deg:
            pos_err: list[float] = []
            rot_err: list[float] = []
            rot_best: list[float] = []
            ratios: list[float] = []
            for _ in range(trials):
                T_world_box, T_wo = marker_view_pose(distance, math.radians(angle_deg))
                if jitter > 0.0:
                    T_wo = T_wo.copy()
                    T_wo[:3, 3] += rng.uniform(-jitter, jitter, 3)
                T_true = np.linalg.inv(T_wo) @ T_world_box @ model.T_box_marker(face)
                image = renderer.render(T_wo, [T_world_box])
                found = [d for d in detector.detect(image) if d.marker_id == 4]
                if not found:
                    continue
                det = found[0]
                pos_err.append(float(np.linalg.norm(det.translation - T_true[:3, 3])))
                R_true_inv = Rotation.from_matrix(T_true[:3, :3]).inv()
                e0 = float((R_true_inv * Rotation.from_quat(det.pose.quaternion_xyzw)).magnitude())
                rot_err.append(math.degrees(e0))
                e1 = e0
                if det.alternative is not None:
                    R_alt = Rotation.from_quat(det.alternative.quaternion_xyzw)
                    e1 = min(e0, float((R_true_inv * R_alt).magnitude()))
                rot_best.append(math.degrees(e1))
                ratios.append(det.ambiguity_ratio)
            n = len(pos_err)
            cells.append(
                AccuracyCell(
                    distance=float(distance),
                    angle_deg=float(angle_deg),
                    trials=trials,
                    detection_rate=n / trials,
                    max_position_error=max(pos_err) if n else math.nan,
                    mean_position_error=float(np.mean(pos_err)) if n else math.nan,
                    max_rotation_error_deg=max(rot_err) if n else math.nan,
                    max_rotation_error_best_of_two_deg=max(rot_best) if n else math.nan,
                    mean_ambiguity_ratio=float(np.nanmean(ratios)) if n else math.nan,
                )
            )
    return cells
