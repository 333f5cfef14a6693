"""Write the viewer screenshots of docs/viewer.md into docs/images/ (not a test).

    .venv/bin/python tests/viewer/make_screenshots.py [OUTDIR]

1. ``viewer_p_controller.png``: the P-controller scenario (goal (5, 5, pi/2)) after about
   14 s of simulated time, paced to the wall clock.
2. ``viewer_aruco.png``: the ROSbot standing in ``aruco_box_world`` with a stand-in camera +
   detector node (the vision team's nodes come later): it renders the boxes from the true
   pose of ``oak_rgb_camera_optical_frame`` (posekit.vision.render), detects the markers
   (posekit.vision.detector), publishes ``/oak/rgb/color``, ``aruco_detection_image`` and
   the ``aruco_marker_<id>`` frames.

Needs chromium (scripts/install_browser_deps.sh) and the viewer's PyPI packages.
"""

from __future__ import annotations

import math
import os
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np

from posekit.cli.view_cmd import attach_to_run
from posekit.launch import Node as LaunchNode
from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.image import numpy_to_image
from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.sensor_msgs import Image
from posekit.robot.description import FIXED_JOINTS
from posekit.robot.scenarios import start_scenario
from posekit.robot.worlds import load_world, pose_matrix
from posekit.runtime.node import Node
from posekit.runtime.tf2_ros import TransformBroadcaster

FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--use-gl=angle", "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader", "--disable-background-networking",
    "--disable-component-update", "--disable-sync", "--no-first-run",
]


def T_base_optical() -> np.ndarray:
    """base_link -> oak_rgb_camera_optical_frame from the robot description's fixed joints."""
    parents = {child: (parent, xyz, rpy) for parent, child, xyz, rpy in FIXED_JOINTS}
    T = np.eye(4)
    frame = "oak_rgb_camera_optical_frame"
    while frame != "base_link":
        parent, xyz, rpy = parents[frame]
        T = pose_matrix((*xyz, *rpy)) @ T
        frame = parent
    return T


class ArucoCameraStandIn(Node):
    """Renders the world's boxes from the robot's true camera pose and runs the detector."""

    def __init__(self) -> None:
        super().__init__("aruco_camera_stand_in")
        from posekit.vision.camera import PinholeCamera
        from posekit.vision.detector import ArucoMarkerDetector
        from posekit.vision.render import BoxRenderer

        world = load_world("aruco_box_world")
        self.boxes = [b.T_world_box for b in world.boxes]
        w, h = 640, 360
        f = 0.5 * w / math.tan(math.radians(30.0))
        self.camera = PinholeCamera(width=w, height=h, fx=f, fy=f, cx=w / 2, cy=h / 2)
        self.renderer = BoxRenderer(self.camera)
        self.K = np.array([[f, 0, w / 2], [0, f, h / 2], [0, 0, 1.0]])
        self.detector = ArucoMarkerDetector(self.K, marker_size=0.2)
        self.T_base_optical = T_base_optical()
        self.T_world_base: np.ndarray | None = None
        self.pub = self.create_publisher(Image, "/oak/rgb/color", 2)
        self.pub_debug = self.create_publisher(Image, "aruco_detection_image", 2)
        self.tf = TransformBroadcaster(self)
        self.create_subscription(Odometry, "ground_truth/odom", self.on_truth, 10)
        self.create_timer(0.2, self.tick)

    def on_truth(self, msg: Odometry) -> None:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        yaw = math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y**2 + q.z**2))
        self.T_world_base = pose_matrix((p.x, p.y, p.z, 0.0, 0.0, yaw))

    def tick(self) -> None:
        if self.T_world_base is None:
            return
        from posekit.vision.detector import draw_detections

        rgb = self.renderer.render(self.T_world_base @ self.T_base_optical, self.boxes)
        stamp = self.get_clock().now().to_msg()
        image = numpy_to_image(rgb, "rgb8")
        image.header.stamp = stamp
        image.header.frame_id = "oak_rgb_camera_frame"
        self.pub.publish(image)
        detections = self.detector.detect(rgb)
        debug = draw_detections(np.ascontiguousarray(rgb[:, :, ::-1]), detections, self.K)
        debug_msg = numpy_to_image(np.ascontiguousarray(debug), "bgr8")
        debug_msg.header.stamp = stamp
        self.pub_debug.publish(debug_msg)
        transforms = []
        for d in detections:
            t = TransformStamped()
            t.header.stamp = stamp
            t.header.frame_id = "oak_rgb_camera_optical_frame"
            t.child_frame_id = f"aruco_marker_{d.marker_id}"
            x, y, z = (float(v) for v in d.translation)
            t.transform.translation.x, t.transform.translation.y = x, y
            t.transform.translation.z = z
            qx, qy, qz, qw = (float(v) for v in d.quaternion_xyzw)
            r = t.transform.rotation
            r.x, r.y, r.z, r.w = qx, qy, qz, qw
            transforms.append(t)
        if transforms:
            self.tf.sendTransform(transforms)


def shoot(run: Any, out: Path, seconds: float, query: str = "") -> None:
    from playwright.sync_api import sync_playwright

    server = attach_to_run(run, port=0)
    spinner = threading.Thread(target=run.executor.spin, daemon=True)
    spinner.start()
    try:
        with tempfile.TemporaryDirectory() as home, sync_playwright() as p:
            browser = p.chromium.launch(executable_path="/usr/bin/chromium", args=FLAGS,
                                        env={**os.environ, "HOME": home})
            page = browser.new_page(viewport={"width": 1500, "height": 900})
            page.goto(server.url + query)
            time.sleep(seconds)
            page.screenshot(path=str(out))
            browser.close()
        print(f"wrote {out}")
    finally:
        server.stop()
        run.shutdown()


def main(argv: list[str]) -> int:
    out = Path(argv[0]) if argv else Path(__file__).parents[2] / "docs" / "images"
    out.mkdir(parents=True, exist_ok=True)
    run = start_scenario("p_controller", realtime=True, record=False)
    shoot(run, out / "viewer_p_controller.png", 14.0, "?camera=-0.5,-2.5,4.2&target=2.6,2.4,0")
    run = start_scenario(
        "empty_world",
        {"world": "aruco_box_world"},
        realtime=True,
        record=False,
        extra_nodes=[LaunchNode(ArucoCameraStandIn, name="aruco_camera_stand_in")],
    )
    shoot(run, out / "viewer_aruco.png", 5.0, "?camera=-0.9,-1.5,1.3&target=1.5,0.1,0.15")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
