"""ArUco detection + IPPE_SQUARE PnP: accuracy on renders against ground truth, both IPPE
solutions, agreement with raw OpenCV and scipy, the course scenes, and bad inputs."""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRotation

from posekit.geometry import Transform
from posekit.vision.camera import OAK_RGB_CAMERA, OVERHEAD_CAMERA, T_CAMERA_FRAME_OPTICAL
from posekit.vision.detector import ArucoMarkerDetector, draw_detections
from posekit.vision.errors import CameraModelError, InvalidImageError
from posekit.vision.evaluation import look_at
from posekit.vision.render import BoxRenderer
from posekit.worlds import ARUCO_BOX

CAM = OAK_RGB_CAMERA
OBJ = np.array([[-0.1, 0.1, 0], [0.1, 0.1, 0], [0.1, -0.1, 0], [-0.1, -0.1, 0]])


@pytest.fixture(scope="module")
def renderer():
    return BoxRenderer(CAM)


def _angle(Ra, Rb):
    return math.degrees(SciRotation.from_matrix(Ra.T @ Rb).magnitude())


def _project(rvec, tvec, obj=OBJ):
    uv, _ = cv2.projectPoints(obj, np.asarray(rvec, float), np.asarray(tvec, float), CAM.K, None)
    return uv.reshape(-1, 2)


def _view(distance, angle_deg, rng):
    """Camera looking at marker 4 (face -x of a box at the origin) from `distance` at
    `angle_deg` off the face normal, horizontally or vertically, with small seeded jitter."""
    centre = np.array([-0.25, 0.0, 0.25])
    a = math.radians(angle_deg)
    if rng.random() < 0.5:
        direction = np.array([-math.cos(a), math.sin(a) * rng.choice([-1, 1]), 0.0])
    else:
        direction = np.array([-math.cos(a), 0.0, math.sin(a)])
    eye = centre + distance * direction + rng.uniform(-0.01, 0.01, 3)
    target = centre + rng.uniform(-0.03, 0.03, 3)  # marker not always at the image centre
    return look_at(eye, target)


@pytest.mark.parametrize("refine", [False, True])
def test_accuracy_grid_against_ground_truth(renderer, refine):
    """0.5-3 m x 0-60 deg on 1280x720 renders: every marker found, position error <= 2 % of
    the range (<= 1 % with subpixel refinement); orientation within 3 deg once the view is
    oblique enough for IPPE to be unambiguous (>= 30 deg)."""
    det = ArucoMarkerDetector(CAM.K, CAM.dist_coeffs, marker_size=0.2, refine_subpixel=refine)
    rng = np.random.default_rng(11 + refine)
    box = Transform.from_xyz_rpy((0.0, 0.0, 0.25), (0.0, 0.0, 0.0)).as_matrix()
    truth = next(g for g in ARUCO_BOX.ground_truth([box]) if g.marker_id == 4)
    worst_rel = worst_corner = 0.0
    for distance in (0.5, 1.0, 2.0, 3.0):
        for angle in (0.0, 30.0, 45.0, 60.0):
            T_wo = _view(distance, angle, rng)
            T_true = np.linalg.inv(T_wo) @ truth.T_world_marker
            found = [d for d in det.detect(renderer.render(T_wo, [box])) if d.marker_id == 4]
            assert len(found) == 1, (distance, angle)
            d = found[0]
            rng_m = float(np.linalg.norm(T_true[:3, 3]))
            rel = float(np.linalg.norm(d.translation - T_true[:3, 3])) / rng_m
            worst_rel = max(worst_rel, rel)
            if angle >= 30.0:
                assert _angle(d.pose.rotation_matrix, T_true[:3, :3]) < 3.0, (distance, angle)
            # detected corners match the projected true corners
            true_uv = CAM.project_world(truth.corners_world, T_wo)
            worst_corner = max(worst_corner, float(np.abs(d.corners - true_uv).max()))
    print(f"refine={refine} worst rel {worst_rel} worst corner {worst_corner}")
    assert worst_rel <= (0.01 if refine else 0.02)
    assert worst_corner <= (0.5 if refine else 2.0)


def test_both_ippe_solutions_on_exact_projection():
    # a marker tilted 20 deg at 1.5 m: exact corners, so the best solution is the truth
    R_true = SciRotation.from_euler("xyz", [math.pi + 0.35, 0.1, 0.2]).as_matrix()
    t_true = np.array([0.1, -0.05, 1.5])
    rvec_true = cv2.Rodrigues(R_true)[0]
    corners = _project(rvec_true, t_true)
    det = ArucoMarkerDetector(CAM.K, marker_size=0.2)
    best, alt = det.estimate_pose(corners, 0.2)
    assert alt is not None
    np.testing.assert_allclose(best.translation, t_true, atol=1e-5)
    assert _angle(best.rotation_matrix, R_true) < 1e-3
    assert best.reprojection_error < 1e-3
    assert alt.reprojection_error > best.reprojection_error
    assert _angle(alt.rotation_matrix, R_true) > 5.0  # the mirrored pose is really different
    # each candidate's reported error is OpenCV's RMS over the 8 corner coordinates
    for cand in (best, alt):
        rms = np.sqrt(np.mean((_project(cand.rvec, cand.translation) - corners) ** 2))
        assert cand.reprojection_error == pytest.approx(rms, rel=1e-3, abs=1e-4)
        # quaternion agrees with scipy's from_rotvec (xyzw), up to sign; canonical w >= 0
        ref = SciRotation.from_rotvec(cand.rvec).as_quat()
        assert min(np.abs(cand.quaternion_xyzw - ref).max(),
                   np.abs(cand.quaternion_xyzw + ref).max()) < 1e-12
        assert cand.quaternion_xyzw[3] >= 0.0
        np.testing.assert_allclose(cand.T_camera_marker[:3, 3], cand.translation)


def test_ambiguity_ratio_separates_head_on_from_oblique(renderer):
    det = ArucoMarkerDetector(CAM.K, marker_size=0.2)
    box = [Transform.from_xyz_rpy((0.0, 0.0, 0.25), (0.0, 0.0, 0.0)).as_matrix()]
    far_head_on = look_at((-3.25, 0.01, 0.26), (-0.25, 0.0, 0.25))
    close_oblique = look_at((-0.25 - 0.8 * math.cos(1.0), 0.8 * math.sin(1.0), 0.25),
                            (-0.25, 0.0, 0.25))
    r_far = det.detect(renderer.render(far_head_on, box))[0].ambiguity_ratio
    r_close = det.detect(renderer.render(close_oblique, box))[0].ambiguity_ratio
    assert 0.0 <= r_close < 0.1
    assert r_far > 3 * r_close
    assert r_far <= 1.0


def test_best_pose_equals_raw_opencv_solvepnp(renderer):
    T_wo = look_at((-1.4, 0.6, 0.7), (-0.25, 0.0, 0.25))
    T_world_box = Transform.from_xyz_rpy((0.0, 0.0, 0.25), (0.0, 0.0, 0.0)).as_matrix()
    img = renderer.render(T_wo, [T_world_box])
    det = ArucoMarkerDetector(CAM.K, CAM.dist_coeffs, marker_size=0.2)
    ours = det.detect(img)
    raw = cv2.aruco.ArucoDetector(cv2.aruco.getPredefinedDictionary(cv2.aruco.DICT_5X5_250))
    corners, ids, _ = raw.detectMarkers(img)
    assert sorted(d.marker_id for d in ours) == sorted(ids.ravel().tolist())
    for c, i in zip(corners, ids.ravel(), strict=True):
        ok, rvec, tvec = cv2.solvePnP(OBJ.astype(np.float32), c.reshape(4, 2), CAM.K,
                                      CAM.dist_coeffs, flags=cv2.SOLVEPNP_IPPE_SQUARE)
        assert ok
        d = next(d for d in ours if d.marker_id == i)
        np.testing.assert_allclose(d.corners, c.reshape(4, 2))
        np.testing.assert_allclose(d.rvec, rvec.ravel(), atol=1e-9)
        np.testing.assert_allclose(d.translation, tvec.ravel(), atol=1e-9)


def test_exact_fronto_parallel_square_is_not_identity():
    # Integer corners of a perfectly square head-on marker: OpenCV's IPPE degenerates to the
    # identity rotation (marker facing away, tens of px of error); we must return the real pose.
    corners = [[602.0, 398.0], [602.0, 310.0], [690.0, 310.0], [690.0, 398.0]]
    best, _ = ArucoMarkerDetector(CAM.K).estimate_pose(corners, 0.2)
    assert best.reprojection_error < 0.05
    z_axis = best.rotation_matrix[:, 2]
    assert z_axis[2] < -0.99  # marker normal points back at the camera
    # the corners in this order mean the marker's x axis points up in the image
    np.testing.assert_allclose(best.rotation_matrix[:, 0], [0.0, -1.0, 0.0], atol=0.02)
    assert best.translation[2] == pytest.approx(CAM.fx * 0.2 / 88.0, rel=1e-3)


def test_per_id_marker_sizes_scale_translation(renderer):
    T_wo = look_at((-1.0, -1.0, 1.0), (0.0, 0.0, 0.25))
    T_world_box = Transform.from_xyz_rpy((0.0, 0.0, 0.25), (0.0, 0.0, 0.0)).as_matrix()
    img = renderer.render(T_wo, [T_world_box])
    base = {d.marker_id: d for d in ArucoMarkerDetector(CAM.K, marker_size=0.2).detect(img)}
    sized = ArucoMarkerDetector(CAM.K, marker_size=0.2, marker_sizes={4: 0.1})
    assert sized.size_of(4) == 0.1
    assert sized.size_of(2) == 0.2
    got = {d.marker_id: d for d in sized.detect(img)}
    assert 4 in got
    assert len(got) == 3  # ids 4, 2 and 3 (faces -x, -y, +z)
    np.testing.assert_allclose(got[4].translation, 0.5 * base[4].translation, rtol=1e-6)
    assert got[4].marker_size == 0.1
    for i in set(got) - {4}:
        np.testing.assert_allclose(got[i].translation, base[i].translation)


def test_robot_sees_markers_2_4_5_in_aruco_box_world():
    boxes = [Transform.from_xyz_rpy((2.25, 0.0, 0.25), (0.0, 0.0, 0.0)).as_matrix(),
             Transform.from_xyz_rpy((2.25, -0.5, 0.25), (0.0, 0.0, -1.57)).as_matrix(),
             Transform.from_xyz_rpy((2.25, 0.5, 0.25), (0.0, 0.0, 1.57)).as_matrix()]
    T_world_optical = np.eye(4)
    T_world_optical[:3, 3] = (-0.0241, 0.0, 0.1875)  # base_link at the origin
                                                     # (docs/specs/rosbot_and_worlds.md)
    T_world_optical = T_world_optical @ T_CAMERA_FRAME_OPTICAL
    img = BoxRenderer(CAM, noise_sigma=2.0, seed=1).render(T_world_optical, boxes)
    dets = ArucoMarkerDetector(CAM.K, marker_size=0.2).detect(img)
    spec = {4: (2.0, 0.0, 0.25), 2: (2.0, -0.5002, 0.25), 5: (2.0, 0.5002, 0.25)}
    assert sorted(d.marker_id for d in dets) == [2, 4, 5]
    for d in dets:
        p_world = T_world_optical @ np.append(d.translation, 1.0)
        assert np.linalg.norm(p_world[:3] - spec[d.marker_id]) < 0.05


def test_overhead_camera_sees_static_box_within_3cm():
    T_world_camera = Transform.from_xyz_rpy((2.0, 2.0, 2.0), (0.0, 1.5708, 0.0)).as_matrix()
    T_world_optical = T_world_camera @ T_CAMERA_FRAME_OPTICAL
    T_world_box = Transform.from_xyz_rpy((2.0, 2.0, 0.25), (0.0, 0.0, 0.0)).as_matrix()
    img = BoxRenderer(OVERHEAD_CAMERA).render(T_world_optical, [T_world_box])
    info = OVERHEAD_CAMERA.camera_info(frame_id="overhead_camera_optical_frame")
    dets = ArucoMarkerDetector.from_camera_info(info, marker_size=0.2).detect(img)
    assert [d.marker_id for d in dets] == [3]
    T_world_marker = T_world_optical @ dets[0].T_camera_marker
    assert np.linalg.norm(T_world_marker[:3, 3] - [2.0, 2.0, 0.5]) < 0.03
    # orientation quat (0, 0, 1, 0): marker z up, x along world -x
    np.testing.assert_allclose(T_world_marker[:3, 2], [0, 0, 1], atol=0.05)
    np.testing.assert_allclose(T_world_marker[:3, 0], [-1, 0, 0], atol=0.05)


@pytest.mark.parametrize(
    "image",
    [
        np.zeros((0, 0), np.uint8),
        np.zeros((0, 640, 3), np.uint8),
        np.zeros((480, 640), np.float32),
        np.zeros((480, 640, 2), np.uint8),
        np.zeros((2, 480, 640, 3), np.uint8),
        [[0, 1], [2, 3]],
        None,
    ],
)
def test_bad_images_raise_named_error(image):
    det = ArucoMarkerDetector(CAM.K)
    with pytest.raises(InvalidImageError):
        det.detect(image)


def test_no_markers_gives_empty_result_for_every_layout():
    det = ArucoMarkerDetector(CAM.K)
    for img in (np.full((480, 640), 200, np.uint8), np.zeros((480, 640, 1), np.uint8),
                np.zeros((480, 640, 3), np.uint8), np.zeros((480, 640, 4), np.uint8)):
        assert det.detect(img) == []


def test_bad_construction_raises():
    with pytest.raises(CameraModelError, match="9 elements"):
        ArucoMarkerDetector(np.eye(2))
    with pytest.raises(CameraModelError, match="intrinsic"):
        ArucoMarkerDetector(np.diag([-1.0, 1.0, 1.0]))
    with pytest.raises(CameraModelError, match="dist_coeffs"):
        ArucoMarkerDetector(CAM.K, [0.1, 0.2, 0.3])
    with pytest.raises(ValueError, match="dictionary"):
        ArucoMarkerDetector(CAM.K, dictionary="DICT_NOPE")
    with pytest.raises(ValueError, match="positive"):
        ArucoMarkerDetector(CAM.K, marker_size=0.0)
    with pytest.raises(ValueError, match="id 3"):
        ArucoMarkerDetector(CAM.K, marker_sizes={3: -0.1})


def test_subpixel_option_sets_opencv_refinement():
    det = ArucoMarkerDetector(CAM.K, refine_subpixel=True)
    assert det._detector.getDetectorParameters().cornerRefinementMethod == (
        cv2.aruco.CORNER_REFINE_SUBPIX
    )
    default = ArucoMarkerDetector(CAM.K)
    assert default._detector.getDetectorParameters().cornerRefinementMethod == (
        cv2.aruco.CORNER_REFINE_NONE
    )


def test_debug_image_draws_outlines_and_axes(renderer):
    T_wo = look_at((-1.2, 0.5, 0.6), (-0.25, 0.0, 0.25))
    T_world_box = Transform.from_xyz_rpy((0.0, 0.0, 0.25), (0.0, 0.0, 0.0)).as_matrix()
    img = renderer.render(T_wo, [T_world_box])
    before = img.copy()
    det = ArucoMarkerDetector(CAM.K, marker_size=0.2)
    dets = det.detect(img)
    out = draw_detections(img, dets, CAM.K, CAM.dist_coeffs)
    assert np.array_equal(img, before)  # input untouched
    assert out.shape == img.shape
    assert out.dtype == np.uint8
    colour = (out.max(axis=2).astype(int) - out.min(axis=2)) > 100
    assert colour.sum() > 200  # coloured outlines / axes on a grey scene
    # the x axis (red in BGR) starts at the projected marker centre
    centre = _project(dets[0].rvec, dets[0].translation, np.zeros((1, 3)))[0]
    u, v = round(centre[0]), round(centre[1])
    patch = out[v - 3 : v + 4, u - 3 : u + 4]
    assert (patch[..., 2].astype(int) - patch[..., 1] > 100).any() or (
        patch[..., 0].astype(int) - patch[..., 1] > 100).any()
    grey = draw_detections(img[..., 0], [], CAM.K)
    assert grey.shape == img.shape
