"""Pinhole camera model: intrinsics of docs/specs/rosbot_and_worlds.md, projection against closed
form and OpenCV, messages."""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest
from scipy.spatial.transform import Rotation as SciRotation

from posekit.msgs.builtin_interfaces import Time
from posekit.vision.camera import (
    OAK_RGB_CAMERA,
    OVERHEAD_CAMERA,
    R_CAMERA_FRAME_OPTICAL,
    T_CAMERA_FRAME_OPTICAL,
    PinholeCamera,
)
from posekit.vision.errors import CameraModelError


def test_oak_intrinsics_match_spec():
    # docs/specs/rosbot_and_worlds.md: 1280x720, HFOV 60 deg, K = [[1108.513, 0, 640], [0,
    # 1108.513, 360], [0, 0, 1]]
    cam = OAK_RGB_CAMERA
    assert (cam.width, cam.height) == (1280, 720)
    np.testing.assert_allclose(cam.K, [[1108.513, 0, 640], [0, 1108.513, 360], [0, 0, 1]],
                               atol=1e-3)
    assert math.isclose(cam.hfov, math.radians(60.0), rel_tol=1e-12)


def test_overhead_intrinsics_match_spec():
    cam = OVERHEAD_CAMERA
    assert (cam.width, cam.height) == (640, 480)
    np.testing.assert_allclose(cam.K, [[554.383, 0, 320], [0, 554.383, 240], [0, 0, 1]],
                               atol=1e-2)
    assert cam.near == 0.1


def test_project_closed_form():
    cam = OAK_RGB_CAMERA
    f = 640.0 / math.tan(math.radians(30.0))
    uv = cam.project([[0.1, -0.05, 2.0], [0.0, 0.0, 1.0]])
    np.testing.assert_allclose(uv, [[640 + f * 0.05, 360 - f * 0.025], [640, 360]], atol=1e-9)


def test_project_behind_camera_is_nan():
    uv = OAK_RGB_CAMERA.project([[0.0, 0.0, -1.0], [0.0, 0.0, 0.0]])
    assert np.all(np.isnan(uv))


def test_project_world_matches_opencv():
    rng = np.random.default_rng(3)
    cam = OAK_RGB_CAMERA
    rotvec = rng.normal(size=3)
    R_world_optical = SciRotation.from_rotvec(rotvec).as_matrix()
    t_world_optical = rng.normal(size=3)
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R_world_optical, t_world_optical
    # points in front of the camera, expressed in the world
    p_opt = np.column_stack([rng.uniform(-1, 1, 50), rng.uniform(-1, 1, 50),
                             rng.uniform(0.5, 5, 50)])
    p_world = p_opt @ R_world_optical.T + t_world_optical
    R_ow = R_world_optical.T
    ref, _ = cv2.projectPoints(p_world, cv2.Rodrigues(R_ow)[0], -R_ow @ t_world_optical, cam.K,
                               None)
    np.testing.assert_allclose(cam.project_world(p_world, T), ref.reshape(-1, 2), atol=1e-7)


def test_optical_rotation_is_urdf_rpy():
    # URDF joint rpy (-pi/2, 0, -pi/2) = extrinsic x-y-z Euler angles
    ref = SciRotation.from_euler("xyz", [-math.pi / 2, 0.0, -math.pi / 2]).as_matrix()
    np.testing.assert_allclose(R_CAMERA_FRAME_OPTICAL, ref, atol=1e-12)
    # optical z (forward) is body x, optical x (right) is body -y, optical y (down) is body -z
    np.testing.assert_allclose(R_CAMERA_FRAME_OPTICAL @ [0, 0, 1], [1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(R_CAMERA_FRAME_OPTICAL @ [1, 0, 0], [0, -1, 0], atol=1e-12)
    np.testing.assert_allclose(R_CAMERA_FRAME_OPTICAL @ [0, 1, 0], [0, 0, -1], atol=1e-12)
    np.testing.assert_allclose(T_CAMERA_FRAME_OPTICAL[:3, 3], 0.0)
    with pytest.raises(ValueError, match="read-only"):
        R_CAMERA_FRAME_OPTICAL[0, 0] = 2.0


def test_camera_info_fields_and_round_trip():
    stamp = Time(sec=12, nanosec=5)
    msg = OAK_RGB_CAMERA.camera_info(frame_id="oak_rgb_camera_frame", stamp=stamp)
    assert msg.__msgtype__ == "sensor_msgs/msg/CameraInfo"
    assert (msg.width, msg.height) == (1280, 720)
    assert msg.distortion_model == "plumb_bob"
    assert msg.header.frame_id == "oak_rgb_camera_frame"
    assert msg.header.stamp == stamp
    np.testing.assert_array_equal(msg.d, np.zeros(5))
    np.testing.assert_allclose(msg.k.reshape(3, 3), OAK_RGB_CAMERA.K)
    np.testing.assert_allclose(msg.r.reshape(3, 3), np.eye(3))
    P = msg.p.reshape(3, 4)
    np.testing.assert_allclose(P[:, :3], OAK_RGB_CAMERA.K)
    np.testing.assert_allclose(P[:, 3], 0.0)
    back = PinholeCamera.from_camera_info(msg)
    assert back.K.tolist() == OAK_RGB_CAMERA.K.tolist()
    assert (back.width, back.height) == (1280, 720)


def test_scaled_camera_maps_pixel_centres():
    cam = OVERHEAD_CAMERA
    p = np.array([[0.3, -0.2, 1.7], [-0.1, 0.25, 3.0]])
    for s in (2, 3):
        np.testing.assert_allclose(cam.scaled(s).project(p), s * cam.project(p) + (s - 1) / 2,
                                   atol=1e-9)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"width": 0, "height": 10, "fx": 1.0, "fy": 1.0, "cx": 0.0, "cy": 0.0}, "positive"),
        ({"width": 10, "height": 10, "fx": math.nan, "fy": 1.0, "cx": 0.0, "cy": 0.0}, "finite"),
        ({"width": 10, "height": 10, "fx": -1.0, "fy": 1.0, "cx": 0.0, "cy": 0.0}, "focal"),
        ({"width": 10.0, "height": 10, "fx": 1.0, "fy": 1.0, "cx": 0.0, "cy": 0.0}, "int"),
        ({"width": 10, "height": 10, "fx": 1.0, "fy": 1.0, "cx": 0.0, "cy": 0.0, "near": 0.0},
         "near"),
    ],
)
def test_bad_parameters_raise(kwargs, match):
    with pytest.raises(CameraModelError, match=match):
        PinholeCamera(**kwargs)


def test_bad_fov_and_scale_raise():
    with pytest.raises(CameraModelError, match="FOV"):
        PinholeCamera.from_hfov(640, 480, 180.0, degrees=True)
    with pytest.raises(CameraModelError, match="scale"):
        OAK_RGB_CAMERA.scaled(0)
    with pytest.raises(CameraModelError, match="shape"):
        OAK_RGB_CAMERA.project([1.0, 2.0])


def test_camera_and_box_model_import_without_opencv():
    import subprocess
    import sys

    code = ("import sys, posekit.vision as v; v.PinholeCamera; v.ARUCO_BOX; "
            "assert 'cv2' not in sys.modules, 'cv2 imported eagerly'; "
            "v.BoxRenderer; assert 'cv2' in sys.modules")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            timeout=60)
    assert result.returncode == 0, result.stderr
