"""The simulated OAK-D depth camera and the z-buffer under it.

Oracles: closed-form depths (a wall plane at a known distance and the ground plane, pixel by
pixel; the front face of a box of known size and place, and where its edges fall in the
image); an independent ray caster (the LiDAR's slab/segment caster, range along each pixel's
ray turned into depth with the ray's z component) on randomly posed boxes and husarion_world's
walls; REP 117 for out-of-range pixels; the noise's sample statistics against the stereo
formula; the PointCloud2 bytes read back by a reader written here (rosbags deserializes the
CDR, a numpy dtype built from the fields it decoded) and by the real ROS 2 rclpy's
deserialization in the reference venv.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from posekit.geometry import Rotation, Transform
from posekit.msgs.cdr import to_cdr
from posekit.msgs.std_msgs import Header
from posekit.robot.depth import (
    DEFAULT_DEPTH,
    DepthCamera,
    DepthParams,
    depth_cloud,
    depth_image_msg,
    depth_points,
)
from posekit.robot.description import FIXED_JOINTS, T_base_frame
from posekit.worlds import World, load_world
from posekit.worlds.obstacles import BoxObstacles, WallSegments, cast_rays

NOISELESS = DepthParams(disparity_stddev=0.0)
OPTICAL = "oak_rgb_camera_optical_frame"
T_BASE_OPT = T_base_frame(OPTICAL)
CAM_X, CAM_Z = T_BASE_OPT.translation[0], T_BASE_OPT.translation[2]  # -0.0241, 0.1875


def _T_world_optical(x: float = 0.0, y: float = 0.0, yaw: float = 0.0) -> np.ndarray:
    return (Transform(Rotation.from_rpy(0.0, 0.0, yaw), (x, y, 0.0)) * T_BASE_OPT).as_matrix()


def _wall_world(x: float = 3.0) -> World:
    return World.from_dict({"name": "wall", "walls": [
        {"name": "w", "height": 5.0, "loops": [[[x, -40.0], [x, 40.0], [x + 0.2, 0.0]]]}]})


def test_the_defaults_are_the_course_description() -> None:
    p = DEFAULT_DEPTH
    assert (p.width, p.height, p.rate_hz) == (1280, 720, 30.0)
    assert math.degrees(p.hfov) == pytest.approx(60.0)
    assert (p.min_depth, p.max_depth) == (1.0, 12.0)
    assert p.fx == pytest.approx(1108.513, abs=1e-3)  # the colour camera's K
    assert (p.cx, p.cy) == (640.0, 360.0)
    assert p.frame_id == OPTICAL
    assert p.frame_id in {child for _, child, _, _ in FIXED_JOINTS}
    # The stereo formula: sigma = z^2 * 0.1 px / (881 px * 0.075 m).
    assert p.noise_sigma(4.0) == pytest.approx(16 * 0.1 / (640 / math.tan(math.radians(36))
                                                           * 0.075))


def test_a_wall_and_the_ground_pixel_by_pixel() -> None:
    """Level camera in front of a wall 3 m ahead: depth(v) = min(3.0241, h fy / (v - cy)) for
    every pixel (the ground below the horizon, h the camera height), exactly in float32."""
    cam = DepthCamera(_wall_world(3.0), NOISELESS)
    p = cam.params
    z = cam.true_depth(_T_world_optical())
    wall = 3.0 - CAM_X
    v = np.arange(p.height, dtype=np.float64)
    with np.errstate(divide="ignore"):
        ground = np.where(v > p.cy, CAM_Z * p.fy / (v - p.cy), np.inf)
    expected = np.minimum(wall, ground)[:, None] * np.ones((1, p.width))
    np.testing.assert_allclose(z, expected, rtol=2e-6)


def test_box_front_face_depth_and_silhouette() -> None:
    """aruco_box_world's box_1 alone (0.5 m cube at x = 2.25): its front face at x = 2.0 fills
    the pixels the closed-form projection of its edges bounds, at depth 2.0241."""
    box_1 = load_world("aruco_box_world").boxes[0]
    cam = DepthCamera(World(name="one", boxes=(box_1,)), NOISELESS, ground=False)
    p = cam.params
    z = cam.true_depth(_T_world_optical())
    d = 2.0 - CAM_X
    u_half = p.fx * 0.25 / d
    v_top = p.cy - p.fy * (0.5 - CAM_Z) / d
    v_bottom = p.cy + p.fy * CAM_Z / d
    inner = z[math.ceil(v_top) + 1 : math.floor(v_bottom) - 1,
              math.ceil(p.cx - u_half) + 1 : math.floor(p.cx + u_half) - 1]
    assert inner.size > 10_000
    np.testing.assert_allclose(inner, d, rtol=2e-6)
    row = int(p.cy)
    # Two pixels beyond each edge: nothing (no ground in this test).
    assert np.isinf(z[row, math.floor(p.cx - u_half) - 2])
    assert np.isinf(z[row, math.ceil(p.cx + u_half) + 2])
    assert np.isinf(z[math.floor(v_top) - 2, int(p.cx)])
    assert np.isinf(z[math.ceil(v_bottom) + 2, int(p.cx)])


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_depth_equals_an_independent_ray_caster(seed: int) -> None:
    """Random boxes (any yaw, some tilted) plus husarion_world's walls: at 4000 random
    pixels, depth = range along the pixel's unit ray (slab / segment caster) * ray z."""
    rng = np.random.default_rng(seed)
    boxes = []
    for i in range(12):
        pose = [float(rng.uniform(1.5, 6.0)), float(rng.uniform(-3.0, 3.0)),
                float(rng.uniform(0.0, 1.0)), float(rng.uniform(-0.5, 0.5)),
                float(rng.uniform(-0.5, 0.5)), float(rng.uniform(-math.pi, math.pi))]
        boxes.append({"name": f"b{i}", "model": "aruco_box", "pose": pose})
    husarion = load_world("husarion_world")
    world = World.from_dict({"name": "mix", "boxes": boxes,
                             "walls": [w.to_dict() for w in husarion.walls]})
    x, y, yaw = float(rng.uniform(-1, 1)), float(rng.uniform(-2.5, -1.5)), float(rng.uniform(-3, 3))
    T = _T_world_optical(x, y, yaw)
    cam = DepthCamera(world, NOISELESS, ground=False)
    p = cam.params
    z = cam.true_depth(T)
    cols = rng.integers(0, p.width, 4000)
    rows = rng.integers(0, p.height, 4000)
    rays = np.column_stack([(cols - p.cx) / p.fx, (rows - p.cy) / p.fy, np.ones(4000)])
    rays /= np.linalg.norm(rays, axis=1, keepdims=True)
    ranges = cast_rays(T[:3, 3], rays @ T[:3, :3].T, BoxObstacles.from_world(world),
                       walls=WallSegments.from_world(world))
    expected = ranges * rays[:, 2]
    got = z[rows, cols].astype(np.float64)
    finite = np.isfinite(expected) & (expected < 2.0 * p.max_depth)
    assert finite.sum() > 1000
    # Pixels on a silhouette may go either way (pixel-centre coverage vs the exact ray); they
    # are few. Everywhere else the two agree to float32 precision.
    close = np.isclose(got[finite], expected[finite], rtol=1e-5, atol=1e-5)
    assert close.mean() > 0.995, np.column_stack([got[finite][~close], expected[finite][~close]])
    assert np.all(np.isinf(got[~np.isfinite(ranges)]))


def test_out_of_range_pixels_are_signed_infinities() -> None:
    """REP 117 as gz-sensors applies it: nothing seen or >= 12 m -> +inf; <= 1 m -> -inf
    (the ground just in front of the robot); a wall at 13 m is +inf."""
    cam = DepthCamera(_wall_world(13.0), NOISELESS)
    z = cam.frame(_T_world_optical(), 0)
    p = cam.params
    assert np.all(z[: int(p.cy)] == np.inf)  # above the horizon: the wall at 13 m
    ground = CAM_Z * p.fy / (np.arange(p.height) - p.cy + 1e-9)
    near_rows = np.flatnonzero((ground > 0) & (ground <= 1.0 - 1e-3))
    far_rows = np.flatnonzero(ground >= 12.0 + 1e-2)
    assert near_rows.size > 50
    assert np.all(z[near_rows] == -np.inf)
    assert np.all(z[far_rows] == np.inf)
    mid = np.flatnonzero((ground > 1.01) & (ground < 11.9))
    assert np.all(np.isfinite(z[mid]))


def test_noise_is_seeded_per_frame_and_follows_the_stereo_formula() -> None:
    """Same seed and frame index -> the same frame, whatever was drawn before; the inverse
    depth error is Gaussian-like with sigma_d / (f B) (1/m) and zero mean; a constant term
    adds noise_stddev in depth."""
    world = _wall_world(5.0)
    T = _T_world_optical()
    a = DepthCamera(world, seed=3)
    b = DepthCamera(world, seed=3)
    f7 = a.frame(T, 7)
    a.frame(T, 8)
    np.testing.assert_array_equal(f7, b.frame(T, 7))  # independent of frames drawn before
    assert not np.array_equal(f7, a.frame(T, 9))
    assert not np.array_equal(f7, DepthCamera(world, seed=4).frame(T, 7))
    rows = slice(0, int(DEFAULT_DEPTH.cy) - 1)  # the wall only
    truth = DepthCamera(world, NOISELESS).true_depth(T)[rows].astype(np.float64)
    p = DEFAULT_DEPTH
    k = p.disparity_stddev / (p.stereo_focal_px * p.baseline)
    err = (1.0 / f7[rows] - 1.0 / truth).ravel()
    assert abs(err.mean()) < 5 * k / math.sqrt(err.size)
    assert err.std() == pytest.approx(k, rel=0.02)
    # Depth sigma ~ z^2 k to first order.
    assert (f7[rows] - truth).std() == pytest.approx(p.noise_sigma(5.0 - CAM_X), rel=0.03)
    const = DepthCamera(world, DepthParams(disparity_stddev=0.0, noise_stddev=0.2), seed=1)
    derr = (const.frame(T, 0)[rows] - truth).ravel()
    assert derr.std() == pytest.approx(0.2, rel=0.02)


def test_points_lie_on_the_wall_in_the_world_through_the_optical_frame() -> None:
    """Points of the noiseless cloud mapped to the world with T_world_optical: the wall's
    points have x = 3, the ground's z = 0, and the cloud is organised in the optical frame
    (y down: the ground rows have y > 0)."""
    cam = DepthCamera(_wall_world(3.0), NOISELESS)
    T = _T_world_optical()
    z = cam.frame(T, 0)
    pts = depth_points(z, cam.params)
    assert pts.shape == (720, 1280, 3)
    finite = np.isfinite(pts[:, :, 2])
    assert np.array_equal(finite, np.isfinite(z))
    assert np.all(np.isnan(pts[~finite]))
    world = pts[finite].astype(np.float64) @ T[:3, :3].T + T[:3, 3]
    on_wall = np.abs(world[:, 0] - 3.0) < 1e-4
    on_ground = np.abs(world[:, 2]) < 1e-4
    assert np.all(on_wall | on_ground)
    assert on_wall.sum() > 400_000
    assert on_ground.sum() > 10_000
    assert np.all(pts[finite][on_ground & ~on_wall][:, 1] > 0.0)


def _cloud_msg():
    cam = DepthCamera(_wall_world(3.0), NOISELESS)
    z = cam.frame(_T_world_optical(), 0)
    header = Header(frame_id=OPTICAL)
    header.stamp.sec, header.stamp.nanosec = 12, 345
    return z, depth_cloud(z, cam.params, header)


def test_pointcloud2_layout_read_back_with_rosbags_and_a_dtype_built_here() -> None:
    from rosbags.typesys import Stores, get_typestore

    z, msg = _cloud_msg()
    store = get_typestore(Stores.ROS2_JAZZY)
    raw = store.deserialize_cdr(to_cdr(msg), "sensor_msgs/msg/PointCloud2")
    assert (raw.height, raw.width, raw.point_step, raw.row_step) == (720, 1280, 32, 32 * 1280)
    assert raw.is_dense is False
    assert raw.is_bigendian is False
    assert raw.header.frame_id == OPTICAL
    assert [(f.name, f.offset, f.datatype, f.count) for f in raw.fields] == [
        ("x", 0, 7, 1), ("y", 4, 7, 1), ("z", 8, 7, 1), ("rgb", 16, 7, 1)]
    dtype = np.dtype({"names": [f.name for f in raw.fields],
                      "formats": ["<f4"] * len(raw.fields),
                      "offsets": [f.offset for f in raw.fields], "itemsize": raw.point_step})
    pts = np.frombuffer(bytes(raw.data), dtype=dtype).reshape(raw.height, raw.width)
    np.testing.assert_array_equal(pts["z"], np.where(np.isfinite(z), z, np.nan))
    p = DEFAULT_DEPTH
    r, c = 100, 1000
    assert pts["x"][r, c] == pytest.approx((c - p.cx) / p.fx * z[r, c], rel=1e-6)
    assert pts["y"][r, c] == pytest.approx((r - p.cy) / p.fy * z[r, c], rel=1e-6)
    assert pts["rgb"][r, c].view(np.uint32) == 0x00FFFFFF


def _decoded_cloud(msg):
    """``(raw message, bytes (H, W, point_step))`` of ``msg`` deserialized by rosbags."""
    from rosbags.typesys import Stores, get_typestore

    raw = get_typestore(Stores.ROS2_JAZZY).deserialize_cdr(to_cdr(msg),
                                                            "sensor_msgs/msg/PointCloud2")
    data = np.frombuffer(bytes(raw.data), np.uint8)
    return raw, data.reshape(raw.height, raw.width, raw.point_step)


def test_pointcloud2_padding_is_zero_and_rgb_white_at_every_point() -> None:
    """Every point's bytes outside x, y, z, rgb (12-16 and 20-32) are zero and every rgb is
    0x00FFFFFF, read from the CDR rosbags decoded (the cloud is written in row blocks)."""
    _, msg = _cloud_msg()
    _, points = _decoded_cloud(msg)
    assert not points[:, :, 12:16].any()
    assert not points[:, :, 20:32].any()
    assert np.all(points[:, :, 16:20].copy().view("<u4") == 0x00FFFFFF)


@pytest.mark.parametrize("height", [1, 8, 11])
def test_pointcloud2_of_a_small_image_every_point_closed_form(height: int) -> None:
    """A 13-column image of ``height`` rows (fewer, as many and more rows than one block)
    with random depths and every kind of non-finite value: x = (c - cx)/fx z and
    y = (r - cy)/fy z at every pixel (float64 formula, float32 tolerance), NaN x, y, z where
    the depth is not finite, ``is_dense`` false; the same image made finite is dense."""
    params = DepthParams(width=13, height=height)
    rng = np.random.default_rng(height)
    z = rng.uniform(1.0, 5.0, (height, 13)).astype(np.float32)
    flat = z.reshape(-1)
    flat[rng.choice(flat.size, 3, replace=False)] = [np.inf, -np.inf, np.nan]
    raw, points = _decoded_cloud(depth_cloud(z, params, Header(frame_id=OPTICAL)))
    assert (raw.height, raw.width, raw.is_dense) == (height, 13, False)
    xyz = points[:, :, :12].copy().view("<f4").astype(np.float64)
    rows, cols = np.mgrid[0:height, 0:13]
    finite = np.isfinite(z)
    zz = z.astype(np.float64)
    np.testing.assert_allclose(xyz[:, :, 0][finite], ((cols - params.cx) / params.fx * zz)[finite],
                               rtol=1e-6, atol=1e-7)
    np.testing.assert_allclose(xyz[:, :, 1][finite], ((rows - params.cy) / params.fy * zz)[finite],
                               rtol=1e-6, atol=1e-7)
    np.testing.assert_array_equal(xyz[:, :, 2][finite], zz[finite])
    assert np.all(np.isnan(xyz[~finite]))
    raw_dense, _ = _decoded_cloud(depth_cloud(np.where(finite, z, np.float32(2.0)), params,
                                              Header(frame_id=OPTICAL)))
    assert raw_dense.is_dense is True


def test_depth_image_is_32fc1_metres() -> None:
    from rosbags.typesys import Stores, get_typestore

    z, _ = _cloud_msg()
    msg = depth_image_msg(z, Header(frame_id=OPTICAL))
    raw = get_typestore(Stores.ROS2_JAZZY).deserialize_cdr(to_cdr(msg), "sensor_msgs/msg/Image")
    assert (raw.encoding, raw.height, raw.width, raw.step, raw.is_bigendian) == (
        "32FC1", 720, 1280, 4 * 1280, 0)
    np.testing.assert_array_equal(np.frombuffer(bytes(raw.data), "<f4").reshape(720, 1280), z)


@pytest.mark.slow
def test_pointcloud2_deserialized_by_the_real_rclpy(tmp_path) -> None:
    """The real ROS 2 Jazzy rclpy deserializes the CDR bytes into its sensor_msgs
    PointCloud2; the points read there with the fields it decoded equal ours."""
    from tests._support.ros2 import run_ros2_script

    z, msg = _cloud_msg()
    (tmp_path / "cloud.cdr").write_bytes(to_cdr(msg))
    script = f"""
        import json, numpy as np
        from rclpy.serialization import deserialize_message
        from sensor_msgs.msg import PointCloud2, PointField
        msg = deserialize_message(open({str(tmp_path / 'cloud.cdr')!r}, 'rb').read(), PointCloud2)
        assert all(f.datatype == PointField.FLOAT32 and f.count == 1 for f in msg.fields)
        dtype = np.dtype({{'names': [f.name for f in msg.fields],
                          'formats': ['<f4'] * len(msg.fields),
                          'offsets': [f.offset for f in msg.fields],
                          'itemsize': msg.point_step}})
        pts = np.frombuffer(bytes(msg.data), dtype=dtype)
        xyz = np.stack([pts['x'], pts['y'], pts['z']], axis=1)
        xyz = xyz[np.isfinite(xyz).all(axis=1)]
        np.save({str(tmp_path / 'pts.npy')!r}, xyz)
        print(json.dumps({{'frame': msg.header.frame_id, 'n': int(xyz.shape[0]),
                          'h': msg.height, 'w': msg.width, 'step': msg.point_step,
                          'row': msg.row_step, 'dense': msg.is_dense,
                          'fields': [f.name for f in msg.fields]}}))
    """
    out = run_ros2_script(script, domain_id=0)
    assert out.returncode == 0, out.stderr
    info = json.loads(out.stdout.strip().splitlines()[-1])
    assert info == {"frame": OPTICAL, "n": int(np.isfinite(z).sum()), "h": 720, "w": 1280,
                    "step": 32, "row": 32 * 1280, "dense": False,
                    "fields": ["x", "y", "z", "rgb"]}
    theirs = np.load(tmp_path / "pts.npy")
    ours = depth_points(z, DEFAULT_DEPTH)[np.isfinite(z)]
    np.testing.assert_array_equal(theirs, ours)
