"""static_aruco_detector and dynamic_detector as nodes: the TF they publish (against the
marker poses of docs/specs/rosbot_and_worlds.md, composed with scipy), the one-shot behaviour, the
course parameters and posekit's additions, and bad inputs logged and survived."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as R

from posekit.geometry import Transform
from posekit.msgs.image import numpy_to_image
from posekit.msgs.sensor_msgs import CameraInfo, Image
from posekit.msgs.std_msgs import Header
from posekit.msgs.tf2_msgs import TFMessage
from posekit.runtime.node import Node
from posekit.runtime.qos import QoSProfile
from posekit.tf2_ros import StaticListenerQoS
from posekit.time import stamp_from_ns
from posekit.vision.camera import OAK_RGB_CAMERA, OVERHEAD_CAMERA
from posekit.vision.detector import ArucoMarkerDetector
from posekit.vision.nodes import DynamicDetector, StaticArucoDetector
from posekit.vision.render import BoxRenderer

SIM = {"use_sim_time": True}

# docs/specs/rosbot_and_worlds.md: aruco_box_world boxes, and the three front markers' centres in
# odom.
BOX_WORLD = [Transform.from_xyz_rpy((2.25, 0.0, 0.25), (0.0, 0.0, 0.0)).as_matrix(),
             Transform.from_xyz_rpy((2.25, -0.5, 0.25), (0.0, 0.0, -1.57)).as_matrix(),
             Transform.from_xyz_rpy((2.25, 0.5, 0.25), (0.0, 0.0, 1.57)).as_matrix()]
FRONT_MARKERS = {4: (2.000, 0.000, 0.250), 2: (2.000, -0.5002, 0.250),
                 5: (2.000, 0.5002, 0.250)}


def T_from(xyz, rotation: R) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = rotation.as_matrix()
    T[:3, 3] = xyz
    return T


# docs/specs/rosbot_and_worlds.md: base_link -> oak_rgb_camera_frame = (-0.0241, 0, 0.1875),
# optical R = Rz(-pi/2) Rx(-pi/2).
T_ODOM_OAK_OPTICAL = T_from((-0.0241, 0.0, 0.1875),
                            R.from_euler("ZX", [-np.pi / 2, -np.pi / 2]))
# docs/specs/rosbot_and_worlds.md: odom -> overhead_camera (2, 2, 2, rpy 0 1.5708 0) -> optical
# (rpy -1.5708 0 -1.5708).
T_ODOM_OVERHEAD_OPTICAL = (T_from((2.0, 2.0, 2.0), R.from_euler("xyz", [0, 1.5708, 0]))
                           @ T_from((0, 0, 0), R.from_euler("xyz", [-1.5708, 0, -1.5708])))


def tf_matrix(t) -> np.ndarray:
    q = t.transform.rotation
    p = t.transform.translation
    return T_from((p.x, p.y, p.z), R.from_quat([q.x, q.y, q.z, q.w]))


class Feeder(Node):
    """Publishes camera images / CameraInfo on demand and records /tf and /tf_static."""

    def __init__(self, ctx, image_topic: str, info_topic: str) -> None:
        super().__init__("feeder", context=ctx, parameter_overrides=SIM)
        self.image_pub = self.create_publisher(Image, image_topic, 10)
        self.info_pub = self.create_publisher(CameraInfo, info_topic, 10)
        self.tf: list[TFMessage] = []
        self.tf_static: list[TFMessage] = []
        self.debug: list[Image] = []
        self.create_subscription(TFMessage, "/tf", self.tf.append, QoSProfile(depth=100))
        self.create_subscription(TFMessage, "/tf_static", self.tf_static.append,
                                 StaticListenerQoS())

    def image(self, pixels: np.ndarray, t: float, frame: str, encoding: str = "rgb8") -> None:
        header = Header(stamp=stamp_from_ns(round(t * 1e9)), frame_id=frame)
        self.image_pub.publish(numpy_to_image(pixels, encoding, header))


def oak_frame() -> np.ndarray:
    return BoxRenderer(OAK_RGB_CAMERA).render(T_ODOM_OAK_OPTICAL, BOX_WORLD)


@pytest.fixture
def oak_pixels() -> np.ndarray:
    return oak_frame()


def dynamic_setup(ctx, executor, **params):
    det = DynamicDetector(context=ctx, parameter_overrides={
        **SIM, "marker_size": 0.2, **params})
    feeder = Feeder(ctx, "/oak/rgb/color", "/oak/stereo/camera_info")
    executor.add_node(det)
    executor.add_node(feeder)
    return det, feeder


def test_dynamic_detector_publishes_every_marker_stamped_with_the_image(
        ctx, executor, oak_pixels) -> None:
    det, feeder = dynamic_setup(ctx, executor)
    feeder.info_pub.publish(OAK_RGB_CAMERA.camera_info(frame_id="oak_rgb_camera_optical_frame"))
    executor.run_until(0.1)
    feeder.image(oak_pixels, 0.05, "oak_rgb_camera_optical_frame")  # an image from the past
    executor.run_until(0.2)
    assert len(feeder.tf) == 1
    transforms = {t.child_frame_id: t for t in feeder.tf[0].transforms}
    assert set(transforms) == {f"aruco_marker_{i}" for i in FRONT_MARKERS}
    for marker_id, truth in FRONT_MARKERS.items():
        t = transforms[f"aruco_marker_{marker_id}"]
        assert t.header.frame_id == "oak_rgb_camera_optical_frame"
        assert (t.header.stamp.sec, t.header.stamp.nanosec) == (0, 50_000_000)
        T_odom_marker = T_ODOM_OAK_OPTICAL @ tf_matrix(t)
        assert np.linalg.norm(T_odom_marker[:3, 3] - truth) < 0.03
        # marker z axis (out of the face) points back along -x in odom for all three
        assert T_odom_marker[:3, 2] @ np.array([-1.0, 0.0, 0.0]) > 0.99
    assert det.detection_counts == {2: 1, 4: 1, 5: 1}
    assert {d.marker_id for d in det.last_detections} == set(FRONT_MARKERS)


def test_dynamic_detector_parent_frame_defaults_to_the_image_frame(ctx, executor,
                                                                   oak_pixels) -> None:
    _det, feeder = dynamic_setup(ctx, executor, parent_frame_id="")
    feeder.info_pub.publish(OAK_RGB_CAMERA.camera_info())
    executor.run_until(0.1)
    feeder.image(oak_pixels, 0.1, "some_camera_frame")
    executor.run_until(0.2)
    assert {t.header.frame_id for t in feeder.tf[0].transforms} == {"some_camera_frame"}


def test_dynamic_detector_parent_frame_id_overrides_the_image_frame(ctx, executor,
                                                                    oak_pixels) -> None:
    _det, feeder = dynamic_setup(ctx, executor, parent_frame_id="oak_rgb_camera_optical_frame")
    feeder.info_pub.publish(OAK_RGB_CAMERA.camera_info())
    executor.run_until(0.1)
    feeder.image(oak_pixels, 0.1, "oak_rgb_camera_frame")  # a source stamping the body frame
    executor.run_until(0.2)
    assert {t.header.frame_id for t in feeder.tf[0].transforms} == {
        "oak_rgb_camera_optical_frame"}


def test_debug_image_is_bgr8_with_the_image_header_and_drawn(ctx, executor, oak_pixels) -> None:
    _det, feeder = dynamic_setup(ctx, executor)
    feeder.create_subscription(Image, "aruco_detection_image", feeder.debug.append, 10)
    feeder.info_pub.publish(OAK_RGB_CAMERA.camera_info())
    executor.run_until(0.1)
    feeder.image(oak_pixels, 0.1, "oak_rgb_camera_optical_frame")
    executor.run_until(0.2)
    (debug,) = feeder.debug
    assert debug.encoding == "bgr8"
    assert (debug.width, debug.height) == (1280, 720)
    assert debug.header.frame_id == "oak_rgb_camera_optical_frame"
    pixels = np.asarray(debug.data).reshape(720, 1280, 3)
    # The render is grey; outlines (green) and axes (red/blue) are the only coloured pixels.
    coloured = np.ptp(pixels.astype(int), axis=2) > 60
    assert coloured.sum() > 500


def test_per_id_marker_size_scales_that_marker_only(ctx, executor, oak_pixels) -> None:
    _det, feeder = dynamic_setup(ctx, executor, marker_sizes="4:0.1")
    feeder.info_pub.publish(OAK_RGB_CAMERA.camera_info())
    executor.run_until(0.1)
    feeder.image(oak_pixels, 0.1, "f")
    executor.run_until(0.2)
    half = {t.child_frame_id: tf_matrix(t) for t in feeder.tf[0].transforms}
    full = {d.marker_id: d.translation for d in
            ArucoMarkerDetector(OAK_RGB_CAMERA.K, marker_size=0.2).detect(oak_pixels)}
    # PnP of a square scaled by s gives the translation scaled by s (same pixels).
    assert half["aruco_marker_4"][:3, 3] == pytest.approx(0.5 * full[4], rel=1e-6)
    assert half["aruco_marker_2"][:3, 3] == pytest.approx(full[2], rel=1e-6)


def test_alternative_ippe_solution_is_broadcast_on_request(ctx, executor, oak_pixels) -> None:
    det, feeder = dynamic_setup(ctx, executor, publish_alternative_tf=True)
    feeder.info_pub.publish(OAK_RGB_CAMERA.camera_info())
    executor.run_until(0.1)
    feeder.image(oak_pixels, 0.1, "f")
    executor.run_until(0.2)
    frames = {t.child_frame_id: tf_matrix(t) for t in feeder.tf[0].transforms}
    assert {f"ippe_alt_marker_{i}" for i in FRONT_MARKERS} <= set(frames)
    for d in det.last_detections:
        assert d.alternative is not None
        assert 0.0 <= d.ambiguity_ratio <= 1.0
        alt = frames[f"ippe_alt_marker_{d.marker_id}"]
        assert alt[:3, 3] == pytest.approx(d.alternative.translation)


def test_bad_inputs_are_logged_and_survived(ctx, executor, logs, oak_pixels) -> None:
    det, feeder = dynamic_setup(ctx, executor)
    # 1. image before CameraInfo
    feeder.image(oak_pixels, 0.01, "f")
    executor.run_until(0.02)
    assert any("before camera_info" in r.message for r in logs if r.name == "dynamic_detector")
    # 2. a malformed CameraInfo (K all zero) is ignored; the subscription stays
    feeder.info_pub.publish(CameraInfo())
    executor.run_until(0.03)
    assert det.detector is None
    feeder.info_pub.publish(OAK_RGB_CAMERA.camera_info())
    executor.run_until(0.04)
    assert det.detector is not None
    # 3. unsupported encoding, 4. empty image, 5. data shorter than the header says
    feeder.image(np.zeros((4, 4), dtype=np.uint16), 0.05, "f", encoding="mono16")
    feeder.image_pub.publish(Image(header=Header(frame_id="f"), encoding="rgb8"))
    feeder.image_pub.publish(Image(header=Header(frame_id="f"), height=10, width=10,
                                   encoding="rgb8", step=30, data=np.zeros(7, dtype=np.uint8)))
    executor.run_until(0.06)
    reasons = [reason for _, reason in det.images_rejected]
    assert len(reasons) == 3
    assert "unsupported image encoding 'mono16'" in reasons[0]
    assert "empty image" in reasons[1]
    assert "malformed image" in reasons[2]
    # 6. no markers: nothing published, nothing raised
    feeder.image(np.full((720, 1280, 3), 128, dtype=np.uint8), 0.07, "f")
    executor.run_until(0.08)
    assert feeder.tf == []
    assert det.last_detections == []
    # ... and the node still works
    feeder.image(oak_pixels, 0.09, "f")
    executor.run_until(0.1)
    assert len(feeder.tf) == 1
    assert len(feeder.tf[0].transforms) == 3
    assert executor.callback_exceptions == 0


def test_camera_info_subscription_is_dropped_after_the_first_valid_one(ctx, executor) -> None:
    det, feeder = dynamic_setup(ctx, executor)
    assert feeder.info_pub.get_subscription_count() == 1
    feeder.info_pub.publish(OAK_RGB_CAMERA.camera_info())
    executor.run_until(0.01)
    assert feeder.info_pub.get_subscription_count() == 0
    assert det.detector is not None
    assert det.detector.camera_matrix[0, 0] == pytest.approx(1108.513, abs=1e-3)


def test_bad_parameters_fail_at_start(ctx) -> None:
    with pytest.raises(ValueError, match="marker_sizes"):
        DynamicDetector(context=ctx, parameter_overrides={"marker_sizes": "4=0.2"})
    with pytest.raises(ValueError, match="dictionary"):
        DynamicDetector(context=ctx, parameter_overrides={"dictionary_id": "DICT_NOPE"},
                        node_name="d2")
    with pytest.raises(ValueError, match="marker_size"):
        StaticArucoDetector(context=ctx, parameter_overrides={"marker_size": 0.0})


def test_course_defaults(ctx) -> None:
    dyn = DynamicDetector(context=ctx)
    assert dyn.get_name() == "dynamic_detector"
    assert {k: dyn.get_parameter(k).value for k in (
        "camera_image_topic", "camera_info_topic", "marker_size", "dictionary_id",
        "publish_tf", "parent_frame_id", "refine_subpixel")} == {
        "camera_image_topic": "/oak/rgb/color", "camera_info_topic": "/oak/stereo/camera_info",
        "marker_size": 0.194, "dictionary_id": "DICT_5X5_250", "publish_tf": True,
        "parent_frame_id": "", "refine_subpixel": False}
    st = StaticArucoDetector(context=ctx)
    assert {k: st.get_parameter(k).value for k in (
        "camera_image_topic", "camera_info_topic", "marker_size", "child_frame_id")} == {
        "camera_image_topic": "/overhead_camera/image_raw",
        "camera_info_topic": "/overhead_camera/camera_info", "marker_size": 0.1,
        "child_frame_id": "static_aruco_box"}


def test_static_detector_publishes_once_then_unsubscribes(ctx, executor, logs) -> None:
    det = StaticArucoDetector(context=ctx, parameter_overrides={
        **SIM, "marker_size": 0.2})
    feeder = Feeder(ctx, "/overhead_camera/image_raw", "/overhead_camera/camera_info")
    executor.add_node(det)
    executor.add_node(feeder)
    T_odom_box = Transform.from_xyz_rpy((2.0, 2.0, 0.25), (0.0, 0.0, 0.0)).as_matrix()
    pixels = BoxRenderer(OVERHEAD_CAMERA).render(T_ODOM_OVERHEAD_OPTICAL, [T_odom_box])
    optical = "overhead_camera_optical_frame"
    feeder.image(pixels, 0.0, optical)  # before CameraInfo: skipped
    executor.run_until(0.05)
    assert not det.tf_published
    feeder.info_pub.publish(OVERHEAD_CAMERA.camera_info(frame_id=optical))
    feeder.image(np.full((480, 640, 3), 200, np.uint8), 0.1, optical)  # no marker
    executor.run_until(0.15)
    assert not det.tf_published
    assert feeder.tf_static == []
    feeder.image(pixels, 0.2, optical)  # stamped 0.2, delivered at sim time 0.15
    executor.run_until(0.25)
    assert det.tf_published
    assert feeder.image_pub.get_subscription_count() == 0
    assert feeder.info_pub.get_subscription_count() == 0
    for k in range(3):  # later images reach nobody
        feeder.image(pixels, 0.3 + 0.1 * k, optical)
    executor.run_until(1.0)
    (msg,) = feeder.tf_static
    (t,) = msg.transforms
    assert (t.header.frame_id, t.child_frame_id) == ("overhead_camera_optical_frame",
                                                     "static_aruco_box")
    # stamped with the node clock's now (the course), not with the image stamp
    assert (t.header.stamp.sec, t.header.stamp.nanosec) == (0, 150_000_000)
    T_odom_box = T_ODOM_OVERHEAD_OPTICAL @ tf_matrix(t)
    assert np.linalg.norm(T_odom_box[:3, 3] - (2.0, 2.0, 0.5)) < 0.03
    assert det.detection is not None
    assert det.detection.marker_id == 3
    assert any("halting further detection" in r.message for r in logs)
