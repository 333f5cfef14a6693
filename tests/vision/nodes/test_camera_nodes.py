"""oak_camera and overhead_camera: topics, sizes, stamps, intrinsics and frames against the
docs/specs/rosbot_and_worlds.md numbers; the robot camera's pose from ground truth (checked against
a fine Euler integration); lazy rendering; the overhead camera's static frames."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as R

from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.sensor_msgs import CameraInfo, Image
from posekit.msgs.tf2_msgs import TFMessage
from posekit.runtime.node import Node
from posekit.tf2_ros import StaticListenerQoS
from posekit.time import stamp_from_ns
from posekit.vision.detector import ArucoMarkerDetector
from posekit.vision.nodes import OakCameraNode, OverheadCameraNode

SIM = {"use_sim_time": True}


class Sink(Node):
    def __init__(self, ctx, image_topic: str, info_topic: str) -> None:
        super().__init__("sink", context=ctx, parameter_overrides=SIM)
        self.images: list[Image] = []
        self.infos: list[CameraInfo] = []
        self.tf_static: list[TFMessage] = []
        self.truth_pub = self.create_publisher(Odometry, "/ground_truth/odom", 10)
        self.image_topic = image_topic
        self.create_subscription(CameraInfo, info_topic, self.infos.append, 10)
        self.create_subscription(TFMessage, "/tf_static", self.tf_static.append,
                                 StaticListenerQoS())

    def watch_images(self) -> None:
        self.create_subscription(Image, self.image_topic, self.images.append, 10)


def test_oak_camera_topics_size_stamps_and_intrinsics(ctx, executor) -> None:
    cam = OakCameraNode(context=ctx, parameter_overrides=SIM)
    sink = Sink(ctx, "/oak/rgb/color", "/oak/stereo/camera_info")
    sink.watch_images()
    executor.add_node(cam)
    executor.add_node(sink)
    executor.run_until(0.2)
    assert len(sink.images) == 6  # 30 Hz: t = 1/30 ... 6/30
    for k, (img, info) in enumerate(zip(sink.images, sink.infos, strict=True), start=1):
        ns = k * 33_333_333  # timers fire on the integer-ns grid of round(1e9 / 30)
        assert img.header.stamp == stamp_from_ns(ns) == info.header.stamp
        assert img.header.frame_id == info.header.frame_id == "oak_rgb_camera_optical_frame"
        assert (img.width, img.height, img.encoding, img.step) == (1280, 720, "rgb8", 3840)
    K = np.asarray(sink.infos[0].k).reshape(3, 3)
    # docs/specs/rosbot_and_worlds.md:
    # K = [[1108.513, 0, 640], [0, 1108.513, 360], [0, 0, 1]], D = 0
    assert pytest.approx(np.array([[1108.513, 0, 640], [0, 1108.513, 360], [0, 0, 1]]),
                              abs=1e-3) == K
    assert not np.any(sink.infos[0].d)


def test_oak_optical_frame_from_the_robot_description(ctx) -> None:
    cam = OakCameraNode(context=ctx)
    T = cam.T_base_optical
    # docs/specs/rosbot_and_worlds.md: base_link -> oak_rgb_camera_frame = (-0.0241, 0, 0.1875);
    # optical R = Rz(-pi/2) Rx(-pi/2)
    assert T[:3, 3] == pytest.approx([-0.0241, 0.0, 0.1875], abs=1e-12)
    assert T[:3, :3] == pytest.approx(R.from_euler("ZX", [-np.pi / 2, -np.pi / 2]).as_matrix(),
                                      abs=1e-12)


def euler_integrate(x, y, yaw, v, w, dt, n=20000):
    h = dt / n
    for _ in range(n):
        x += v * h * math.cos(yaw + 0.5 * w * h)
        y += v * h * math.sin(yaw + 0.5 * w * h)
        yaw += w * h
    return x, y, yaw


@pytest.mark.parametrize(("v", "w"), [(0.5, 0.0), (0.3, 0.8), (0.0, -1.2)])
def test_oak_pose_follows_ground_truth_between_samples(ctx, executor, v, w) -> None:
    cam = OakCameraNode(context=ctx, parameter_overrides=SIM)
    sink = Sink(ctx, "/oak/rgb/color", "/oak/stereo/camera_info")
    executor.add_node(cam)
    executor.add_node(sink)
    msg = Odometry()
    msg.header.stamp = stamp_from_ns(0)
    msg.pose.pose.position.x, msg.pose.pose.position.y = 1.0, -0.5
    yaw0 = 0.4
    msg.pose.pose.orientation.z, msg.pose.pose.orientation.w = math.sin(yaw0 / 2), math.cos(
        yaw0 / 2)
    msg.twist.twist.linear.x, msg.twist.twist.angular.z = v, w
    sink.truth_pub.publish(msg)
    executor.run_until(0.01)
    dt = 0.045
    T = cam.T_world_base_at(round(dt * 1e9))
    x, y, yaw = euler_integrate(1.0, -0.5, yaw0, v, w, dt)
    assert T[:3, 3] == pytest.approx([x, y, 0.0], abs=1e-9)
    assert math.atan2(T[1, 0], T[0, 0]) == pytest.approx(yaw, abs=1e-9)
    # the optical frame rides on top: T_odom_optical = T_odom_base @ T_base_optical
    assert cam.T_world_optical_at(round(dt * 1e9)) == pytest.approx(T @ cam.T_base_optical)


def test_lazy_camera_renders_only_for_subscribers(ctx, executor) -> None:
    cam = OakCameraNode(context=ctx, parameter_overrides=SIM)
    sink = Sink(ctx, "/oak/rgb/color", "/oak/stereo/camera_info")
    executor.add_node(cam)
    executor.add_node(sink)
    executor.run_until(0.1)
    assert cam.frames_published == 0
    assert len(sink.infos) == 3  # CameraInfo keeps flowing
    sink.watch_images()
    executor.run_until(0.2)
    assert cam.frames_published == 3


def test_oak_image_shows_the_front_markers_from_the_spawn_pose(ctx, executor) -> None:
    cam = OakCameraNode(context=ctx, parameter_overrides=SIM)
    sink = Sink(ctx, "/oak/rgb/color", "/oak/stereo/camera_info")
    sink.watch_images()
    executor.add_node(cam)
    executor.add_node(sink)
    executor.run_until(0.04)
    img = sink.images[0]
    pixels = np.asarray(img.data).reshape(720, 1280, 3)
    dets = ArucoMarkerDetector(np.asarray(sink.infos[0].k).reshape(3, 3),
                               marker_size=0.2).detect(pixels)
    assert sorted(d.marker_id for d in dets) == [2, 4, 5]
    # docs/specs/rosbot_and_worlds.md: optical frame at (-0.0241, 0, 0.1875); marker 4 at (2, 0,
    # 0.25) in odom
    d4 = next(d for d in dets if d.marker_id == 4)
    expected = R.from_euler("ZX", [-np.pi / 2, -np.pi / 2]).inv().apply(
        np.array([2.0, 0.0, 0.25]) - [-0.0241, 0.0, 0.1875])
    assert np.linalg.norm(d4.translation - expected) < 0.03


def test_overhead_camera_frames_image_and_intrinsics(ctx, executor) -> None:
    cam = OverheadCameraNode(context=ctx, parameter_overrides=SIM)
    sink = Sink(ctx, "/overhead_camera/image_raw", "/overhead_camera/camera_info")
    sink.watch_images()
    executor.add_node(cam)
    executor.add_node(sink)
    executor.run_until(0.04)
    (img,) = sink.images
    assert (img.width, img.height) == (640, 480)
    assert img.header.frame_id == "overhead_camera_optical_frame"
    K = np.asarray(sink.infos[0].k).reshape(3, 3)
    assert K[0, 0] == pytest.approx(554.383, abs=1e-3)
    assert (K[0, 2], K[1, 2]) == (320.0, 240.0)
    statics = {t.child_frame_id: t for t in sink.tf_static[-1].transforms}
    assert set(statics) == {"overhead_camera", "overhead_camera_optical_frame"}
    top = statics["overhead_camera"]
    assert top.header.frame_id == "odom"
    p = top.transform.translation
    assert (p.x, p.y, p.z) == (2.0, 2.0, 2.0)
    q = top.transform.rotation
    assert R.from_quat([q.x, q.y, q.z, q.w]).as_matrix() == pytest.approx(
        R.from_euler("xyz", [0, 1.5708, 0]).as_matrix(), abs=1e-12)
    # The optical z axis looks straight down, from (2, 2, 2).
    T = cam.T_world_optical
    assert T[:3, 3] == pytest.approx([2.0, 2.0, 2.0])
    assert T[:3, 2] == pytest.approx([0.0, 0.0, -1.0], abs=1e-4)
    pixels = np.asarray(img.data).reshape(480, 640, 3)
    (det,) = ArucoMarkerDetector(K, marker_size=0.2).detect(pixels)
    assert det.marker_id == 3  # the top face (docs/specs/rosbot_and_worlds.md)


def test_unknown_camera_name_is_a_clear_error(ctx) -> None:
    with pytest.raises(ValueError, match="no camera 'nope'"):
        OverheadCameraNode(context=ctx, parameter_overrides={"camera_name": "nope"})


@pytest.mark.parametrize(("world", "camera_cls", "image_topic", "body_frame", "root"), [
    ("aruco_box_world", OakCameraNode, "/oak/rgb/color", "oak_rgb_camera_frame", "base_link"),
    ("aruco_box_camera_world", OverheadCameraNode, "/overhead_camera/image_raw",
     "overhead_camera", "odom"),
])
def test_images_carry_an_optical_frame_of_the_tf_tree(ctx, executor, world, camera_cls,
                                                      image_topic, body_frame, root) -> None:
    # REP 103: camera drivers stamp images with the optical frame (z forward, x right, y down),
    # a child of the body frame (x forward, y left, z up) rotated by rpy (-pi/2, 0, -pi/2).
    from posekit.robot.nodes import WorldSimulation
    from posekit.tf2_ros import Buffer, TransformListener
    from posekit.time import Time

    sim = WorldSimulation(context=ctx, parameter_overrides={**SIM, "world": world})
    cam = camera_cls(context=ctx, parameter_overrides={**SIM, "world": world})
    sink = Sink(ctx, image_topic, image_topic.rsplit("/", 1)[0] + "/camera_info")
    sink.watch_images()
    buffer = Buffer()
    TransformListener(buffer, sink)
    for node in (sim, cam, sink):
        executor.add_node(node)
    executor.run_until(0.2)
    frame = sink.images[-1].header.frame_id
    assert frame.endswith("_optical_frame")
    t = buffer.lookup_transform(body_frame, frame, Time())
    q = t.transform.rotation
    expected = R.from_euler("xyz", [-np.pi / 2, 0.0, -np.pi / 2])
    assert (R.from_quat([q.x, q.y, q.z, q.w]) * expected.inv()).magnitude() < 1e-4
    assert buffer.can_transform(root, frame, Time())


@pytest.mark.parametrize("yaw", [0.0, math.pi / 2, math.pi, -math.pi / 2])
def test_oak_camera_sees_husarion_world_walls(ctx, yaw) -> None:
    """In husarion_world the camera draws the walls: at the image centre, the optical axis
    meets a wall at the distance the LiDAR's ray caster gives (within the far clip), and the
    pixel is that wall face's flat shade (0.9 x the documented face light, normal turned to
    the camera). The ring wall encloses the spawn, so every heading meets a wall."""
    from posekit.worlds.obstacles import BoxObstacles, WallSegments, cast_rays

    cam = OakCameraNode(context=ctx, parameter_overrides={"world": "husarion_world"})
    sx, sy, syaw = cam.world.spawn
    cam._truth = (0, sx, sy, syaw + yaw, 0.0, 0.0)  # the robot turned in place at its spawn
    img = cam.render_at(0)
    T = cam.last_T_world_optical
    walls = WallSegments.from_world(cam.world)
    axis = T[:3, 2]
    r = cast_rays(T[:3, 3], axis[None, :], BoxObstacles.from_world(cam.world), walls=walls)[0]
    centre = img[cam.camera.height // 2, cam.camera.width // 2, 0]
    assert 1.0 < r < cam.camera.far
    # The face hit: the segment whose line is at distance r along the axis.
    hit = T[:3, 3] + r * axis
    e = walls.ends - walls.starts
    rel = hit[:2] - walls.starts
    dist = np.abs(e[:, 0] * rel[:, 1] - e[:, 1] * rel[:, 0]) / np.linalg.norm(e, axis=1)
    s = int(np.argmin(dist))
    n = np.array([e[s, 1], -e[s, 0], 0.0]) / np.linalg.norm(e[s])
    if n @ (T[:3, 3] - hit) < 0:
        n = -n
    sun = np.array([-0.5, 0.1, -0.9])
    light = 0.5 + 0.45 * max(0.0, float(n @ (-sun / np.linalg.norm(sun))))
    assert abs(int(centre) - round(255 * 0.9 * min(light, 1.0))) <= 1
