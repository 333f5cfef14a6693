"""The sensor displays (LaserScan, PointCloud2, RobotModel, Imu, Axes) in a real browser
(Debian chromium, software WebGL) on the simulated ROSbot facing a wall.

Oracles: the world's geometry (a wall 2 m ahead of the robot: where the scan and the depth
cloud must land, projected to the canvas by the page's own camera), the canvas pixels of a
display's colour with the display shown and hidden, the URDF parsed here with xml.etree
(the links with visuals the robot model must draw), and what the simulator publishes (the
IMU's frame).
"""

from __future__ import annotations

import json
import threading
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

pytestmark = pytest.mark.slow  # a scenario and a browser

from _support.browser import (  # noqa: E402
    add_from_topic_list,
    canvas_pixels,
    debug,
    display_info,
    set_display_shown,
    set_option,
    wait_for,
)

#: The wall: x = WALL_X in odom, |y| <= 3, 1 m high; the robot at the origin facing it.
WALL_X = 2.0
VIEW = "?camera=-2.5,-3.5,3&target=1.5,0,0.3"
MAGENTA = (255, 0, 255)  # BGR of #ff00ff
ORANGE = (0, 128, 255)  # BGR of #ff8000


@pytest.fixture(scope="module")
def viewer(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Any]:
    import posekit.robot.scenarios  # noqa: F401 - registers the robot's scenarios
    from posekit.cli.view_cmd import attach_to_run
    from posekit.launch.scenarios import start_scenario

    world = tmp_path_factory.mktemp("world") / "wall.json"
    world.write_text(json.dumps({"name": "wall", "walls": [
        {"name": "w", "height": 1.0, "loops": [[[WALL_X, -3.0], [WALL_X, 3.0],
                                                 [WALL_X + 0.1, 0.0]]]}]}))
    run = start_scenario("empty_world", {"world": str(world), "depth_rate": 5.0},
                         realtime=True)
    server = attach_to_run(run, port=0)
    spinner = threading.Thread(target=run.executor.spin, daemon=True)
    spinner.start()
    try:
        yield server
    finally:
        server.stop()
        run.shutdown()
        spinner.join(timeout=5.0)


@pytest.fixture(scope="module")
def page(browser: Any, viewer: Any) -> Iterator[Any]:
    errors: list[str] = []
    page = browser.new_page(viewport={"width": 1280, "height": 800})
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    page.goto(viewer.url + VIEW)
    wait_for(lambda: debug(page, "connected"), what="the WebSocket connection")
    yield page
    assert not errors, f"page errors: {errors}"
    page.close()


def _mask(page: Any, bgr: tuple[int, int, int], tol: int = 30) -> np.ndarray:
    image = canvas_pixels(page, "#scene")
    return np.abs(image.astype(int) - np.array(bgr)).max(axis=2) <= tol  # type: ignore[no-any-return]


def _pixel(page: Any, x: float, y: float, z: float, shape: tuple[int, ...]) -> tuple[int, int]:
    box = page.eval_on_selector("#scene", "c => c.getBoundingClientRect().toJSON()")
    p = page.evaluate(f"window.posekitViewer.project({x}, {y}, {z})")
    sx, sy = shape[1] / box["width"], shape[0] / box["height"]
    return int((p["x"] - box["x"]) * sx), int((p["y"] - box["y"]) * sy)


def _near(mask: np.ndarray, u: int, v: int, r: int = 8) -> bool:
    return bool(mask[max(v - r, 0): v + r + 1, max(u - r, 0): u + r + 1].any())


def test_laser_scan_points_land_on_the_wall(page: Any) -> None:
    d = add_from_topic_list(page, "/scan", "LaserScan", timeout=20)
    assert d["type"] == "sensor_msgs/msg/LaserScan"
    assert d["options"]["color_transformer"] == "Intensity"
    set_option(page, d["id"], "color_transformer", "FlatColor")
    set_option(page, d["id"], "color", "#ff00ff")
    set_option(page, d["id"], "size", 0.06)
    got = wait_for(lambda: display_info(page, "LaserScan", "/scan"),
                   timeout=20, what="a scan drawn")
    assert got["frame"] == "laser"
    wait_for(lambda: _mask(page, MAGENTA).sum() > 200, timeout=20, what="magenta scan points")
    mask = _mask(page, MAGENTA)
    laser_z = 0.1313
    for y in (-1.0, 0.0, 1.0):  # the beams' hits on the wall, where the page projects them
        u, v = _pixel(page, WALL_X, y, laser_z, mask.shape)
        assert _near(mask, u, v), (y, u, v)
    # Nothing magenta where the scan cannot be: 1 m in front of the wall.
    u, v = _pixel(page, WALL_X - 1.0, 0.0, laser_z, mask.shape)
    assert not _near(mask, u, v, 3)
    set_display_shown(page, d["id"], False)
    wait_for(lambda: _mask(page, MAGENTA).sum() < 20, what="the scan hidden")
    set_display_shown(page, d["id"], True)
    # Decay time 1 s: the scans of the last second of stamps (10 Hz) are kept, then one.
    set_option(page, d["id"], "decay_time", 1.0)
    kept = wait_for(lambda: display_info(page, "LaserScan", "/scan")["scans"] >= 8
                    and display_info(page, "LaserScan", "/scan"), timeout=30,
                    what="decayed scans")
    assert kept["scans"] <= 11
    set_option(page, d["id"], "decay_time", 0)
    wait_for(lambda: display_info(page, "LaserScan", "/scan")["scans"] == 1,
             what="one scan again")


def test_depth_cloud_points_land_on_the_wall(page: Any) -> None:
    d = add_from_topic_list(page, "/oak/stereo/depth/points", "PointCloud2")
    set_option(page, d["id"], "color_transformer", "FlatColor")
    set_option(page, d["id"], "color", "#ff8000")
    set_option(page, d["id"], "size", 0.04)
    got = wait_for(lambda: display_info(page, "PointCloud2", "/oak/stereo/depth/points"),
                   timeout=30, what="a cloud drawn")
    assert got["frame"] == "oak_rgb_camera_optical_frame"
    assert got["total"] == 1280 * 720
    assert 10_000 < got["points"] <= 100_000
    wait_for(lambda: _mask(page, ORANGE).sum() > 500, timeout=30, what="orange cloud points")
    mask = _mask(page, ORANGE)
    for y, z in ((0.0, 0.5), (0.4, 0.2), (-0.4, 0.6)):  # in the camera's view of the wall
        u, v = _pixel(page, WALL_X, y, z, mask.shape)
        assert _near(mask, u, v), (y, z, u, v)
    u, v = _pixel(page, WALL_X, 0.0, 1.6, mask.shape)  # above the wall: nothing
    assert not _near(mask, u, v, 3)
    # Removed: the page unsubscribes and the cloud leaves the canvas.
    page.click(f"#display-list details[data-display-id='{d['id']}'] .display-remove")
    wait_for(lambda: "/oak/stereo/depth/points" not in page.evaluate(
        "window.posekitViewer.displays()")["subscriptions"], what="the cloud unsubscribed")
    wait_for(lambda: _mask(page, ORANGE).sum() < 20, what="the cloud gone")


def test_robot_model_draws_the_urdf_links(page: Any, viewer: Any) -> None:
    from posekit.robot.description import robot_description_urdf

    root = ET.fromstring(robot_description_urdf())
    with_visuals = {link.get("name") for link in root.iter("link") if link.find("visual")
                    is not None}
    d = add_from_topic_list(page, "/robot_description", "RobotModel")
    set_option(page, d["id"], "default_color", "#00ff00")
    got = wait_for(lambda: (display_info(page, "RobotModel", "/robot_description") or {})
                   .get("links"), timeout=20, what="the robot model")
    assert set(got) == with_visuals
    green = (0, 255, 0)
    wait_for(lambda: _mask(page, green, 90).sum() > 100, what="the green robot")
    mask = _mask(page, green, 90)
    u, v = _pixel(page, 0.0, 0.0, 0.08, mask.shape)  # the body box around base_link
    assert _near(mask, u, v, 12)
    set_option(page, d["id"], "hidden_links", "body_link")
    def body_hidden() -> Any:
        got = display_info(page, "RobotModel", "/robot_description")
        return got if "body_link" not in got["links"] else None

    info = wait_for(body_hidden, what="body_link hidden")
    assert set(info["links"]) == with_visuals - {"body_link"}


def test_imu_and_axes(page: Any) -> None:
    d = add_from_topic_list(page, "/imu/data", "Imu")
    got = wait_for(lambda: display_info(page, "Imu", "/imu/data"),
                   timeout=20, what="the IMU drawn")
    assert got["frame"] == "imu_link"
    assert abs(sum(c * c for c in got["orientation"]) - 1.0) < 1e-6
    assert got["axes"] is True
    a = add_from_topic_list(page, "/tf", "Axes")
    set_option(page, a["id"], "reference_frame", "odom")
    set_option(page, a["id"], "length", 1.5)
    set_option(page, a["id"], "radius", 0.05)
    red = (0, 0, 255)
    wait_for(lambda: (display_info(page, "Axes", "/tf") or {}).get("placed"),
             what="the axes placed")
    mask = _mask(page, red, 60)
    u, v = _pixel(page, 1.0, 0.0, 0.0, mask.shape)  # on the x axis of odom
    assert _near(mask, u, v)
    set_display_shown(page, a["id"], False)
    set_display_shown(page, d["id"], False)
    wait_for(lambda: not _near(_mask(page, red, 60), u, v, 2), what="the axes hidden")

