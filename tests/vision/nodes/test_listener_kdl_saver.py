"""aruco_marker_listener (discovery, log format, warnings), kdl_chain_demo (log format, the
composition against scipy and against tf2's own lookup) and image_saver (PNG contents)."""

from __future__ import annotations

import re

import cv2
import numpy as np
import pytest
from scipy.spatial.transform import Rotation as R

from posekit.msgs.image import numpy_to_image
from posekit.msgs.sensor_msgs import Image
from posekit.msgs.std_msgs import Header
from posekit.runtime.node import Node
from posekit.tf2_ros import StaticTransformBroadcaster, TransformBroadcaster
from posekit.time import Time, stamp_from_ns
from posekit.vision.nodes import ArucoMarkerListener, ImageSaver, KdlChainDemo
from posekit.vision.nodes._common import transform_msg

SIM = {"use_sim_time": True}
T_ODOM_CAM = ((0.5, -0.2, 0.3), R.from_euler("xyz", [-np.pi / 2, 0.1, -np.pi / 2]))
MARKERS = {3: ((0.2, 0.1, 1.5), R.from_rotvec([0.1, -0.2, 0.3])),
           7: ((-0.3, 0.0, 2.0), R.from_rotvec([-0.4, 0.05, 0.2]))}


class TfSource(Node):
    """odom -> cam on /tf_static; cam -> aruco_marker_<id> on /tf every 0.1 s; an
    unconnected aruco_marker_9."""

    def __init__(self, ctx) -> None:
        super().__init__("tf_source", context=ctx, parameter_overrides=SIM)
        self.static = StaticTransformBroadcaster(self)
        self.dynamic = TransformBroadcaster(self)
        xyz, rot = T_ODOM_CAM
        self.static.sendTransform(
            transform_msg("odom", "cam", stamp_from_ns(0), xyz, rot.as_quat()))
        self.create_timer(0.1, self.tick)

    def tick(self) -> None:
        stamp = self.get_clock().now().to_msg()
        msgs = [transform_msg("cam", f"aruco_marker_{i}", stamp, xyz, rot.as_quat())
                for i, (xyz, rot) in MARKERS.items()]
        msgs.append(transform_msg("elsewhere", "aruco_marker_9", stamp, (0, 0, 1), (0, 0, 0, 1)))
        self.dynamic.sendTransform(msgs)


def expected_in_odom(marker_id: int) -> np.ndarray:
    xyz, rot = T_ODOM_CAM
    return rot.apply(MARKERS[marker_id][0]) + xyz


def test_listener_logs_each_marker_in_odom_and_warns_on_failures(ctx, executor, logs) -> None:
    listener = ArucoMarkerListener(context=ctx,
                                   parameter_overrides={**SIM, "lookup_timeout": 0.0})
    executor.add_node(TfSource(ctx))
    executor.add_node(listener)
    executor.run_until(2.0)
    lines = [r for r in logs if r.name == "aruco_marker_listener"]
    infos = [r.message for r in lines if r.severity.name == "INFO"]
    warns = [r.message for r in lines if r.severity.name == "WARN"]
    assert len(infos) == 4  # t = 1, 2 s; markers 3 and 7 (sorted)
    pattern = re.compile(r"aruco_marker_(\d+) in odom: x=(-?\d+\.\d{3}), y=(-?\d+\.\d{3}), "
                         r"z=(-?\d+\.\d{3})")
    seen = []
    for line in infos:
        m = pattern.fullmatch(line)
        assert m, line
        marker_id = int(m.group(1))
        seen.append(marker_id)
        got = np.array([float(m.group(k)) for k in (2, 3, 4)])
        assert got == pytest.approx(expected_in_odom(marker_id), abs=6e-4)
    assert seen == [3, 7, 3, 7]
    assert len(warns) == 2
    assert all(w.startswith("aruco_marker_9 -> odom: ") for w in warns)
    assert listener.positions["aruco_marker_7"] == pytest.approx(expected_in_odom(7), abs=1e-9)
    assert executor.callback_exceptions == 0


def test_kdl_chain_demo_composes_the_two_hops(ctx, executor, logs) -> None:
    src = Node("src", context=ctx, parameter_overrides=SIM)
    static = StaticTransformBroadcaster(src)
    T_odom_cam = ((2.0, 2.0, 2.0), R.from_euler("xyz", [0, 1.5708, 0]))
    T_cam_opt = ((0.0, 0.0, 0.0), R.from_euler("xyz", [-1.5708, 0, -1.5708]))
    T_opt_box = ((0.01, -0.02, 1.49), R.from_rotvec([0.02, -0.01, 3.1]))
    static.sendTransform([
        transform_msg("odom", "overhead_camera", stamp_from_ns(0), T_odom_cam[0],
                      T_odom_cam[1].as_quat()),
        transform_msg("overhead_camera", "overhead_camera_optical_frame", stamp_from_ns(0),
                      T_cam_opt[0], T_cam_opt[1].as_quat()),
        transform_msg("overhead_camera_optical_frame", "static_aruco_box", stamp_from_ns(0),
                      T_opt_box[0], T_opt_box[1].as_quat()),
    ])
    demo = KdlChainDemo(context=ctx, parameter_overrides=SIM)
    executor.add_node(src)
    executor.add_node(demo)
    executor.run_until(1.0)
    # independent composition with scipy
    rot_odom_opt = T_odom_cam[1] * T_cam_opt[1]
    p_odom_opt = T_odom_cam[1].apply(T_cam_opt[0]) + T_odom_cam[0]
    p = rot_odom_opt.apply(T_opt_box[0]) + p_odom_opt
    q = (rot_odom_opt * T_opt_box[1]).as_quat()
    assert demo.last_frame is not None
    got_p = np.array(list(demo.last_frame.p))
    assert got_p == pytest.approx(p, abs=1e-12)
    got_q = np.array(demo.last_frame.M.GetQuaternion())
    assert min(np.abs(got_q - q).max(), np.abs(got_q + q).max()) < 1e-12
    # equal to tf2's own chaining to 1e-9
    direct = demo.buffer.lookup_transform("odom", "static_aruco_box", Time())
    d = direct.transform
    assert got_p == pytest.approx([d.translation.x, d.translation.y, d.translation.z], abs=1e-9)
    qd = np.array([d.rotation.x, d.rotation.y, d.rotation.z, d.rotation.w])
    assert min(np.abs(got_q - qd).max(), np.abs(got_q + qd).max()) < 1e-9
    (line,) = [r.message for r in logs if r.name == "kdl_chain_demo" and "composed" in r.message]
    o = demo.last_pose.orientation
    assert line == (f"KDL-composed static_aruco_box in odom: pos=({p[0]:.3f}, {p[1]:.3f}, "
                    f"{p[2]:.3f}) quat=({o.x:.3f}, {o.y:.3f}, {o.z:.3f}, {o.w:.3f})")


def test_kdl_chain_demo_warns_while_a_hop_is_missing(ctx, executor, logs) -> None:
    demo = KdlChainDemo(context=ctx, parameter_overrides={**SIM, "lookup_timeout": 0.0})
    executor.add_node(demo)
    executor.run_until(3.0)
    warns = [r.message for r in logs if r.name == "kdl_chain_demo"
             and r.severity.name == "WARN"]
    assert warns
    assert warns[0].startswith("TF lookup failed: ")
    assert demo.compositions == 0


class ImagePub(Node):
    def __init__(self, ctx) -> None:
        super().__init__("pub", context=ctx, parameter_overrides=SIM)
        self.pub = self.create_publisher(Image, "aruco_detection_image", 10)

    def send(self, pixels: np.ndarray, encoding: str, t: float) -> None:
        self.pub.publish(
            numpy_to_image(pixels, encoding, Header(stamp=stamp_from_ns(round(t * 1e9)))))


def test_image_saver_writes_true_colour_pngs_at_its_period(ctx, executor, tmp_path, logs) -> None:
    saver = ImageSaver(context=ctx, parameter_overrides={
        **SIM, "output_dir": str(tmp_path), "period": 1.0})
    pub = ImagePub(ctx)
    executor.add_node(saver)
    executor.add_node(pub)
    rgb = np.zeros((6, 8, 3), np.uint8)
    rgb[..., 0] = 255  # pure red in RGB order
    bgr = np.zeros((6, 8, 3), np.uint8)
    bgr[..., 1] = 200  # green
    pub.send(rgb, "rgb8", 0.1)
    pub.send(bgr, "bgr8", 0.5)  # within the period: not written (kept as the last one)
    pub.send(np.zeros((2, 2), np.uint16), "16UC1", 1.2)
    executor.run_until(0.01)
    assert [p.name for p in saver.saved] == ["aruco_detection_image_0_100000000.png",
                                             "aruco_detection_image_1_200000000.png"]
    red = cv2.imread(str(saver.saved[0]))
    assert red.shape == (6, 8, 3)
    assert (red[0, 0] == [0, 0, 255]).all()  # OpenCV reads BGR: red is the last channel
    pub.send(bgr, "bgr8", 1.3)
    pub.send(np.zeros((0, 0, 3), np.uint8), "rgb8", 2.5)  # empty: logged, skipped
    executor.run_until(0.02)
    assert any("empty image" in r.message for r in logs if r.name == "image_saver")
    saver.destroy_node()  # writes the last image received
    last = cv2.imread(str(tmp_path / "aruco_detection_image_last.png"))
    assert last is None  # the last image was the empty one: nothing to write
    assert saver.last_path == saver.saved[-1]
