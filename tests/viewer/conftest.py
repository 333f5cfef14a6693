"""Shared pieces of the viewer tests: a small camera node, and chromium for browser tests."""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterator
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.image import numpy_to_image
from posekit.msgs.sensor_msgs import Image
from posekit.runtime.node import Node
from posekit.tf2_ros import TransformBroadcaster

CHROMIUM = "/usr/bin/chromium"
CHROMIUM_FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--use-gl=angle",
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
#: The camera node's colour (R, G, B): a test can find it in the decoded JPEG.
CAMERA_RGB = (210, 40, 30)
CAMERA_SIZE = (240, 320)  # height, width
STALE_FRAME = "viewer_test_stale_frame"


class CameraTestNode(Node):
    """Publishes an rgb8 camera image (CAMERA_RGB with a moving white bar) on
    ``/oak/rgb/color`` and a mono8 ``aruco_detection_image`` at 10 Hz of its clock, and one
    dynamic transform ``base_link -> STALE_FRAME`` at start only (so it goes stale)."""

    def __init__(self) -> None:
        super().__init__("viewer_test_camera")
        self.pub = self.create_publisher(Image, "/oak/rgb/color", 5)
        self.pub_aruco = self.create_publisher(Image, "aruco_detection_image", 5)
        self.tf = TransformBroadcaster(self)
        self.count = 0
        self.create_timer(0.1, self.tick)

    def tick(self) -> None:
        h, w = CAMERA_SIZE
        rgb = np.empty((h, w, 3), np.uint8)
        rgb[:] = CAMERA_RGB
        x = (self.count * 8) % w
        rgb[:, x : x + 6] = 255
        stamp = self.get_clock().now().to_msg()
        msg = numpy_to_image(rgb, "rgb8")
        msg.header.stamp = stamp
        msg.header.frame_id = "oak_rgb_camera_optical_frame"
        self.pub.publish(msg)
        mono = np.full((h, w), 90, np.uint8)
        mono[:, x : x + 6] = 250
        aruco = numpy_to_image(mono, "mono8")
        aruco.header.stamp = stamp
        self.pub_aruco.publish(aruco)
        if self.count == 0:
            t = TransformStamped()
            t.header.stamp = stamp
            t.header.frame_id = "base_link"
            t.child_frame_id = STALE_FRAME
            t.transform.translation.z = 0.5
            self.tf.sendTransform(t)
        self.count += 1


@pytest.fixture(scope="session")
def chromium() -> str:
    """Path of Debian's chromium; skip (with the reason) only when it is not installed."""
    pytest.importorskip("playwright.sync_api", reason="PyPI 'playwright' is not installed")
    if not (os.path.exists(CHROMIUM) or shutil.which("chromium")):
        pytest.skip(
            "chromium is not installed (apt-get install chromium; see "
            "scripts/install_browser_deps.sh)"
        )
    return CHROMIUM if os.path.exists(CHROMIUM) else str(shutil.which("chromium"))


@pytest.fixture(scope="module")
def browser(chromium: str, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Any]:
    """A headless chromium (software GL) with HOME in a temporary directory."""
    from playwright.sync_api import sync_playwright

    from posekit.viewer.server import THREE_ROOT

    assert (THREE_ROOT / "build" / "three.module.js").is_file(), (
        f"{THREE_ROOT} is missing: the vendored three.js belongs to the repository "
        "(scripts/vendor_three.sh re-creates it)"
    )
    home = tmp_path_factory.mktemp("chromium-home")
    with sync_playwright() as p:
        browser = p.chromium.launch(
            executable_path=chromium,
            args=CHROMIUM_FLAGS,
            env={**os.environ, "HOME": str(home)},
        )
        try:
            yield browser
        finally:
            browser.close()


@pytest.fixture(scope="session")
def support() -> SimpleNamespace:
    """The helpers above for test modules (conftest is not importable under importlib mode)."""
    return SimpleNamespace(
        CameraTestNode=CameraTestNode,
        CAMERA_RGB=CAMERA_RGB,
        CAMERA_SIZE=CAMERA_SIZE,
        STALE_FRAME=STALE_FRAME,
    )


@pytest.fixture(scope="module")
def scenario_viewer() -> Iterator[Any]:
    """The P-controller scenario paced to the wall clock plus :class:`CameraTestNode`, with a
    viewer attached in process on a free port (``server.url``, ``server.tap``)."""
    import posekit.robot.scenarios  # noqa: F401 - registers the robot's scenarios
    from _support.browser import viewer_on
    from posekit.launch import Node as LaunchNode
    from posekit.launch.scenarios import start_scenario

    run = start_scenario(
        "p_controller",
        realtime=True,
        extra_nodes=[LaunchNode(CameraTestNode, name="viewer_test_camera")],
    )
    with viewer_on(run) as server:
        yield server
