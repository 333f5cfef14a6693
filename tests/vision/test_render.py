"""Box renderer against an independent per-pixel ray caster (projection, culling, clipping,
occlusion), sub-pixel edge placement, textures, noise and input checks."""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest

from posekit.geometry import Transform
from posekit.vision.camera import OAK_RGB_CAMERA, OVERHEAD_CAMERA, T_CAMERA_FRAME_OPTICAL
from posekit.vision.errors import CameraModelError
from posekit.vision.evaluation import look_at
from posekit.vision.render import BoxRenderer, marker_texture
from posekit.worlds import ARUCO_BOX

SUN = np.array([-0.5, 0.1, -0.9])
TO_SUN = -SUN / np.linalg.norm(SUN)
GROUND, SKY = 105.0, 190.0
BOX_WORLD = [Transform.from_xyz_rpy((2.25, 0.0, 0.25), (0.0, 0.0, 0.0)).as_matrix(),
             Transform.from_xyz_rpy((2.25, -0.5, 0.25), (0.0, 0.0, -1.57)).as_matrix(),
             Transform.from_xyz_rpy((2.25, 0.5, 0.25), (0.0, 0.0, 1.57)).as_matrix()]


def _rpy(roll, pitch, yaw):
    return Transform.from_xyz_rpy((0, 0, 0), (roll, pitch, yaw)).as_matrix()[:3, :3]


def _pose(R, t):
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, t
    return T


def raycast(camera, T_wo, boxes, us, vs, walls=()):
    """Expected grey level and a surface/region code per pixel, by intersecting pixel rays.

    Written independently of the renderer: nearest front-facing hit among all box faces and
    the ground; a face's white level is 255 * min(0.5 + 0.45 * max(0, n . to_sun), 1) and
    its marker's black border 6 % of that; the marker's data cells are "don't care" (nan).
    """
    d_opt = np.stack([(us - camera.cx) / camera.fx, (vs - camera.cy) / camera.fy,
                      np.ones_like(us)], axis=-1)
    d = d_opt @ T_wo[:3, :3].T  # world directions; optical depth of a hit = t
    o = T_wo[:3, 3]
    best_t = np.full(us.shape, np.inf)
    value = np.where(d[..., 2] < 0, GROUND, SKY) if o[2] > 0 else np.full(us.shape, SKY)
    code = np.where(d[..., 2] < 0, -1, -2).astype(np.int64)
    if o[2] > 0:
        with np.errstate(divide="ignore"):
            best_t = np.where(d[..., 2] < 0, -o[2] / d[..., 2], np.inf)
    L, S = ARUCO_BOX.marker_size, ARUCO_BOX.size
    cell = L / 7.0
    for b, T_wb in enumerate(boxes):
        for f, face in enumerate(ARUCO_BOX.faces):
            T = T_wb @ ARUCO_BOX.T_box_marker(face)
            c, xa, ya, n = T[:3, 3], T[:3, 0], T[:3, 1], T[:3, 2]
            denom = d @ n
            with np.errstate(divide="ignore", invalid="ignore"):
                t = ((c - o) @ n) / denom
            p = o + t[..., None] * d
            x, y = (p - c) @ xa, (p - c) @ ya
            hit = (denom < 0) & (t >= camera.near) & (np.abs(x) <= S / 2) & (np.abs(y) <= S / 2)
            hit &= t < best_t
            white = 255.0 * min(0.5 + 0.45 * max(0.0, float(n @ TO_SUN)), 1.0)
            m = np.maximum(np.abs(x), np.abs(y))
            region = np.where(m > L / 2, 0, np.where(m > L / 2 - cell, 1, 2))
            val = np.where(region == 0, white, np.where(region == 1, 0.06 * white, np.nan))
            best_t = np.where(hit, t, best_t)
            value = np.where(hit, val, value)
            code = np.where(hit, 100 * (b * 6 + f) + region, code)
    for s, (a, b, height) in enumerate(walls):  # vertical faces, both sides, albedo 0.9
        a3, e = np.array([a[0], a[1], 0.0]), np.array([b[0] - a[0], b[1] - a[1], 0.0])
        n = np.cross(e, [0.0, 0.0, 1.0])
        n /= np.linalg.norm(n)
        if n @ (o - a3) < 0:
            n = -n
        denom = d @ n
        with np.errstate(divide="ignore", invalid="ignore"):
            t = ((a3 - o) @ n) / denom
        p = o + t[..., None] * d
        along = (p - a3) @ e / (e @ e)
        hit = (t > 0) & (along >= 0) & (along <= 1) & (p[..., 2] >= 0) & (p[..., 2] <= height)
        hit &= t < best_t
        grey = round(255.0 * 0.9 * min(0.5 + 0.45 * max(0.0, float(n @ TO_SUN)), 1.0))
        best_t = np.where(hit, t, best_t)
        value = np.where(hit, grey, value)
        code = np.where(hit, 100_000 + s, code)
    return value, code


def check_against_raycast(renderer, T_wo, boxes, step=3, tol=1.5, min_checked=1000, walls=()):
    img = renderer.render(T_wo, boxes)
    assert img.shape == (renderer.camera.height, renderer.camera.width, 3)
    assert img.dtype == np.uint8
    assert np.array_equal(img[..., 0], img[..., 1])
    assert np.array_equal(img[..., 0], img[..., 2])
    cam = renderer.camera
    vs, us = np.mgrid[2 : cam.height - 2 : step, 2 : cam.width - 2 : step].astype(np.float64)
    value, code = raycast(cam, T_wo, boxes, us, vs, walls)
    stable = np.ones(us.shape, dtype=bool)
    for du, dv in ((1.5, 0), (-1.5, 0), (0, 1.5), (0, -1.5), (1.5, 1.5), (1.5, -1.5),
                   (-1.5, 1.5), (-1.5, -1.5)):
        _, c2 = raycast(cam, T_wo, boxes, us + du, vs + dv, walls)
        stable &= c2 == code
    check = stable & ~np.isnan(value)
    got = img[vs.astype(int), us.astype(int), 0].astype(np.float64)
    err = np.abs(got - value)[check]
    assert check.sum() >= min_checked
    assert err.max() <= tol, f"{(err > tol).sum()} of {err.size} pixels differ, max {err.max()}"
    return img, code


def test_robot_view_of_aruco_box_world():
    T_wo = _pose(np.eye(3), [-0.0241, 0.0, 0.1875]) @ T_CAMERA_FRAME_OPTICAL
    _, code = check_against_raycast(BoxRenderer(OAK_RGB_CAMERA), T_wo, BOX_WORLD)
    # the front faces of all three boxes (ids 4, 2, 5 on faces -x, -y, +y) are in view
    seen_faces = {int(c) // 100 for c in np.unique(code) if c >= 0}
    assert {0 * 6 + 2, 1 * 6 + 1, 2 * 6 + 5} <= seen_faces


@pytest.mark.parametrize(
    "eye",
    [(0.8, -1.6, 1.6), (1.2, 1.9, 0.9), (3.8, 0.9, 1.2), (2.4, 0.1, 1.6)],
)
def test_oblique_views_with_occlusion(eye):
    T_wo = look_at(eye, (2.25, 0.0, 0.25))
    _, code = check_against_raycast(BoxRenderer(OAK_RGB_CAMERA), T_wo, BOX_WORLD, step=4)
    assert (code >= 0).sum() > 1000  # boxes fill part of the view


def test_rolled_camera_and_overhead_camera():
    T_wo = look_at((0.9, 0.4, 0.6), (2.25, 0.0, 0.25))
    T_wo[:3, :3] = T_wo[:3, :3] @ _rpy(0.0, 0.0, 0.7)  # roll about the optical axis
    check_against_raycast(BoxRenderer(OAK_RGB_CAMERA), T_wo, BOX_WORLD, step=4)
    T_over = _pose(_rpy(0.0, 1.5708, 0.0), [2.0, 2.0, 2.0]) @ T_CAMERA_FRAME_OPTICAL
    T_world_box = Transform.from_xyz_rpy((2.0, 2.0, 0.25), (0.0, 0.0, 0.0)).as_matrix()
    _, code = check_against_raycast(BoxRenderer(OVERHEAD_CAMERA), T_over, [T_world_box], step=2)
    assert {int(c) // 100 for c in np.unique(code) if c >= 0} == {0}  # only the top face


def test_face_crossing_the_near_plane_is_clipped_not_dropped():
    # Camera 0.12 m in front of face -x of a box at the origin, looking along +y and turned
    # 35 degrees towards the face: half of the face plane is behind the camera.
    box = [Transform.from_xyz_rpy((0.0, 0.0, 0.25), (0.0, 0.0, 0.0)).as_matrix()]
    fwd = np.array([math.sin(math.radians(35)), math.cos(math.radians(35)), 0.0])
    eye = np.array([-0.37, 0.0, 0.3])
    T_wo = look_at(eye, eye + fwd)
    _, code = check_against_raycast(BoxRenderer(OAK_RGB_CAMERA), T_wo, box, step=3,
                                    min_checked=5000)
    assert (code // 100 == 2).sum() > 1000  # face -x (index 2) covers a large part


def test_back_faces_and_boxes_behind_camera_are_culled():
    r = BoxRenderer(OAK_RGB_CAMERA)
    T_wo = look_at((0.0, 0.0, 0.25), (1.0, 0.0, 0.25))
    empty = r.render(T_wo, [])
    # camera inside a box: every face is a back face -> only the background
    T_world_box = Transform.from_xyz_rpy((0.0, 0.0, 0.25), (0.0, 0.0, 0.0)).as_matrix()
    assert np.array_equal(r.render(T_wo, [T_world_box]), empty)
    # a box behind the camera
    T_world_box = Transform.from_xyz_rpy((-1.5, 0.0, 0.25), (0.0, 0.0, 0.0)).as_matrix()
    assert np.array_equal(r.render(T_wo, [T_world_box]), empty)
    # and only front faces are reported visible: head-on -> one marker
    T_world_box = Transform.from_xyz_rpy((2.25, 0.0, 0.25), (0.0, 0.0, 0.0)).as_matrix()
    vis = r.visible_markers(T_wo, [T_world_box])
    assert [v.marker_id for v in vis] == [4]
    assert vis[0].in_image
    assert vis[0].viewing_angle == pytest.approx(0.0, abs=1e-9)


def test_painter_order_does_not_depend_on_input_order():
    r = BoxRenderer(OAK_RGB_CAMERA)
    T_wo = look_at((0.5, -1.2, 0.9), (2.25, 0.0, 0.25))
    a = r.render(T_wo, BOX_WORLD)
    b = r.render(T_wo, BOX_WORLD[::-1])
    assert np.array_equal(a, b)


def test_silhouette_edges_land_on_projected_positions():
    # Head-on face at 1.3 m on a sky-only background; 50 % crossings along a row through
    # the face must sit where the closed-form projection puts the face edges.
    r = BoxRenderer(OAK_RGB_CAMERA, ground_level=None)
    cam = OAK_RGB_CAMERA
    T_world_box = Transform.from_xyz_rpy((0.0, 0.0, 0.25), (0.0, 0.0, 0.0)).as_matrix()
    for dx in (0.0, 0.0123, 0.031):
        T_wo = look_at((-1.55 + 0.0, dx, 0.25 + dx), (0.0, dx, 0.25 + dx))
        img = r.render(T_wo, [T_world_box])[..., 0].astype(np.float64)
        depth = 1.3
        u_left = cam.cx + cam.fx * (-0.25 - dx) / depth  # face spans y in [-0.25, 0.25]
        u_right = cam.cx + cam.fx * (0.25 - dx) / depth
        # world +y is image left when looking along +x, so swap
        u_left, u_right = cam.cx - (u_right - cam.cx), cam.cx - (u_left - cam.cx)
        row = round(cam.cy + cam.fy * 0.15 / depth)  # in the quiet zone above the marker
        prof = img[row]
        face_level = prof[int(cam.cx)]
        mid = (face_level + 190.0) / 2
        for u_edge in (u_left, u_right):
            i = math.floor(u_edge)
            a, b = prof[i - 1 : i + 3][:-1], prof[i - 1 : i + 3][1:]
            k = int(np.nonzero((a - mid) * (b - mid) <= 0)[0][0]) + i - 1
            crossing = k + (mid - prof[k]) / (prof[k + 1] - prof[k])
            assert crossing == pytest.approx(u_edge, abs=0.2)


def test_marker_texture_decodes_and_is_centred():
    aruco = cv2.aruco
    det = aruco.ArucoDetector(aruco.getPredefinedDictionary(aruco.DICT_5X5_250))
    for marker_id in (1, 2, 3, 4, 5, 6):
        pyramid = marker_texture(marker_id)
        level0 = pyramid[0][..., 0]
        assert level0.shape == (1120, 1120)  # 17.5 cells of 64 texels: 0.5 m face
        assert np.all(pyramid[0][..., 1] == 255)
        _, ids, _ = det.detectMarkers(level0)
        assert ids is not None
        assert ids.ravel().tolist() == [marker_id]
        dark = np.argwhere(level0 < 128)
        # the black square spans 0.2 / 0.5 of the face, centred
        assert dark.min() == 336
        assert dark.max() == 1120 - 336 - 1
        assert [p.shape[0] for p in pyramid] == [1120, 560, 280, 140, 70, 35, 17]


def test_noise_is_seeded_and_has_requested_sigma():
    T_wo = look_at((0.0, 0.0, 0.25), (1.0, 0.0, 0.25))
    clean = BoxRenderer(OAK_RGB_CAMERA).render(T_wo, []).astype(np.float64)
    a = BoxRenderer(OAK_RGB_CAMERA, noise_sigma=4.0, seed=7).render(T_wo, [])
    b = BoxRenderer(OAK_RGB_CAMERA, noise_sigma=4.0, seed=7).render(T_wo, [])
    c = BoxRenderer(OAK_RGB_CAMERA, noise_sigma=4.0, seed=8).render(T_wo, [])
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)
    resid = (a.astype(np.float64) - clean)[:300, :, 0]  # sky: far from 0 and 255
    assert resid.std() == pytest.approx(4.0, rel=0.05)
    assert abs(resid.mean()) < 0.1


def test_supersampling_agrees_with_mipmapped_render():
    T_wo = look_at((0.8, -1.6, 1.6), (2.25, 0.0, 0.25))
    base = BoxRenderer(OAK_RGB_CAMERA).render(T_wo, BOX_WORLD).astype(np.float64)
    ss = BoxRenderer(OAK_RGB_CAMERA, supersample=3)
    check_against_raycast(ss, T_wo, BOX_WORLD, step=4)
    diff = np.abs(ss.render(T_wo, BOX_WORLD).astype(np.float64) - base)
    assert diff.mean() < 1.0  # differences only along edges


@pytest.mark.parametrize(
    ("T", "match"),
    [
        (np.eye(3), "4x4"),
        (np.full((4, 4), np.nan), "non-finite"),
        (np.diag([1.0, 1.0, -1.0, 1.0]), "rotation"),
        (np.diag([2.0, 1.0, 1.0, 1.0]), "rotation"),
    ],
)
def test_bad_poses_raise(T, match):
    r = BoxRenderer(OVERHEAD_CAMERA)
    with pytest.raises(CameraModelError, match=match):
        r.render(T, [])
    with pytest.raises(CameraModelError, match=match):
        r.render(np.eye(4), [T])


def test_bad_renderer_options_raise():
    with pytest.raises(CameraModelError, match="supersample"):
        BoxRenderer(OVERHEAD_CAMERA, supersample=0)
    with pytest.raises(CameraModelError, match="noise_sigma"):
        BoxRenderer(OVERHEAD_CAMERA, noise_sigma=-1.0)


def test_walls_are_drawn_and_hide_the_boxes_behind_them():
    """A wall between the camera and box_1 (x = 1.5, |y| <= 0.3, 0.4 m high), a tall wall
    beyond the boxes (x = 4) and a box in front of a wall: every pixel matches the ray
    caster above (walls as vertical faces seen from both sides, flat-shaded at albedo 0.9);
    box_1's marker is hidden where the low wall covers it and visible above it."""
    from posekit.worlds.obstacles import WallSegments

    walls = [((1.5, -0.3), (1.5, 0.3), 0.4), ((4.0, -5.0), (4.0, 5.0), 2.0),
             ((3.0, 1.5), (3.0, 3.0), 1.0)]
    segs = WallSegments(np.array([w[0] for w in walls], dtype=float),
                        np.array([w[1] for w in walls], dtype=float),
                        np.array([w[2] for w in walls], dtype=float))
    boxes = [*BOX_WORLD, Transform.from_xyz_rpy((2.5, 2.0, 0.25), (0.0, 0.0, 0.3)).as_matrix()]
    T_wo = look_at([-0.3, 0.6, 0.35], [2.0, 0.5, 0.3])
    renderer = BoxRenderer(OAK_RGB_CAMERA, walls=segs)
    _, code = check_against_raycast(renderer, T_wo, boxes, step=3, walls=walls)
    for wall in range(3):
        assert np.any(code == 100_000 + wall)
    box_1 = (code >= 0) & (code < 600)  # codes 100 * face + region of box 0
    assert box_1.sum() > 100  # box_1 shows above the low wall
    # The same view without walls shows box_1 where the low wall now is.
    _, no_walls = check_against_raycast(BoxRenderer(OAK_RGB_CAMERA), T_wo, boxes, step=3)
    hidden = (code == 100_000) & (no_walls >= 0) & (no_walls < 600)
    assert hidden.sum() > 100
