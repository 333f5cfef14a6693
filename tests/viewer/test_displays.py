"""Displays added from the topic list, in a real browser (Debian chromium, software WebGL), on
the P-controller scenario plus a node publishing one topic per display type.

Oracles: what the test node published (poses, counts, marker ids, image colour), numpy's
eigen decomposition of the published covariance (the ellipsoid's radii), the canvas pixels
(``canvas.toDataURL()``) of a display's colour with the display shown and hidden, and the
server's own bookkeeping (the tap stops keeping a topic nobody displays).
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterator
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

pytestmark = pytest.mark.slow  # a scenario and a browser

cv2 = pytest.importorskip("cv2")

from _support.browser import (  # noqa: E402
    add_from_topic_list,
    canvas_pixels,
    debug,
    display_entry,
    display_info,
    displays,
    drag_tool,
    set_option,
    viewer_on,
    wait_for,
)
from posekit.msgs.geometry_msgs import PoseStamped  # noqa: E402
from posekit.msgs.nav_msgs import Odometry  # noqa: E402
from posekit.msgs.registry import find_message_class  # noqa: E402
from posekit.msgs.yaml_io import default_message  # noqa: E402
from posekit.runtime.node import Node  # noqa: E402

#: Marker types the display draws, one marker each in ns "types" (id = type).
DRAWN_TYPES = {0: "ARROW", 1: "CUBE", 2: "SPHERE", 3: "CYLINDER", 4: "LINE_STRIP",
               5: "LINE_LIST", 6: "CUBE_LIST", 7: "SPHERE_LIST", 8: "POINTS",
               9: "TEXT_VIEW_FACING", 11: "TRIANGLE_LIST"}
ODOM_COVARIANCE = np.array([[0.09, 0.03, 0.0], [0.03, 0.04, 0.0], [0.0, 0.0, 0.01]])
PATH_POSES = 10
ARRAY_POSES = 5
MARKER_LIFETIME_S = 0.6
#: A view over the test node's drawings (x 0..3, y -3..2 of odom).
VIEW = "?camera=1,-6,4&target=1,-1,0"


def _pose(msg: Any, x: float, y: float, yaw: float) -> None:
    msg.position.x, msg.position.y = x, y
    msg.orientation.z, msg.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)


class DisplayTestNode(Node):
    """At 10 Hz: a PoseStamped, a PoseArray, a Path, an Odometry with a fixed covariance, a
    MarkerArray (DELETEALL, then one marker per drawn type, an added-and-deleted one, and
    ns "old" only in the first array), and every 0.5 s a Marker with a 0.6 s lifetime."""

    def __init__(self) -> None:
        super().__init__("viewer_display_test")
        self.types = {t: find_message_class(t) for t in (
            "geometry_msgs/msg/PoseArray", "nav_msgs/msg/Path",
            "visualization_msgs/msg/Marker", "visualization_msgs/msg/MarkerArray")}
        self.pose_pub = self.create_publisher(PoseStamped, "/test_pose", 5)
        self.array_pub = self.create_publisher(self.types["geometry_msgs/msg/PoseArray"],
                                               "/test_pose_array", 5)
        self.path_pub = self.create_publisher(self.types["nav_msgs/msg/Path"], "/test_path", 5)
        self.odom_pub = self.create_publisher(Odometry, "/test_odom", 5)
        self.markers_pub = self.create_publisher(
            self.types["visualization_msgs/msg/MarkerArray"], "/test_markers", 5)
        self.marker_pub = self.create_publisher(
            self.types["visualization_msgs/msg/Marker"], "/test_marker", 50)
        self.count = 0
        self.create_timer(0.1, self.tick)

    def header(self, msg: Any) -> None:
        msg.header.frame_id = "odom"
        msg.header.stamp = self.get_clock().now().to_msg()

    def marker(self, ns: str, mid: int, mtype: int, action: int = 0) -> Any:
        m = default_message("visualization_msgs/msg/Marker")
        self.header(m)
        m.ns, m.id, m.type, m.action = ns, mid, mtype, action
        m.pose.orientation.w = 1.0
        m.pose.position.x, m.pose.position.y = -1.0 + 0.5 * (mid % 6), 1.5 + 0.6 * (mid // 6)
        m.scale.x = m.scale.y = m.scale.z = 0.2
        m.color.r, m.color.g, m.color.b, m.color.a = 1.0, 0.5, 0.0, 1.0  # orange
        Point = find_message_class("geometry_msgs/msg/Point")
        if mtype in (4, 5, 6, 7, 8, 11):
            m.points = [Point(x=0.0, y=0.0, z=0.0), Point(x=0.2, y=0.0, z=0.0),
                        Point(x=0.2, y=0.2, z=0.0)]
            m.scale.x = m.scale.y = m.scale.z = 0.05 if mtype in (4, 5) else 0.1
            if mtype == 11:
                m.scale.x = m.scale.y = m.scale.z = 1.0
        if mtype == 9:
            m.text = "marker text"
        return m

    def tick(self) -> None:
        k = self.count
        pose = PoseStamped()
        self.header(pose)
        _pose(pose.pose, 1.0, -1.0, math.pi / 2)
        self.pose_pub.publish(pose)

        array = default_message("geometry_msgs/msg/PoseArray")
        self.header(array)
        Pose = find_message_class("geometry_msgs/msg/Pose")
        array.poses = []
        for i in range(ARRAY_POSES):
            p = Pose()
            _pose(p, 0.5 * i, -2.0, 0.3 * i)
            array.poses.append(p)
        self.array_pub.publish(array)

        path = default_message("nav_msgs/msg/Path")
        self.header(path)
        path.poses = []
        for i in range(PATH_POSES):
            ps = PoseStamped()
            self.header(ps)
            _pose(ps.pose, 0.3 * i, -3.0 + 0.05 * i * i, 0.0)
            path.poses.append(ps)
        self.path_pub.publish(path)

        odom = Odometry()
        self.header(odom)
        odom.child_frame_id = "test_odom_base"
        _pose(odom.pose.pose, 2.0 + 0.06 * (k % 50), -1.0, 0.0)
        cov = np.zeros((6, 6))
        cov[:3, :3] = ODOM_COVARIANCE
        odom.pose.covariance = cov.ravel()
        self.odom_pub.publish(odom)

        markers = default_message("visualization_msgs/msg/MarkerArray")
        items = [self.marker("", 0, 0, action=3)]  # DELETEALL first
        items += [self.marker("types", t, t) for t in DRAWN_TYPES]
        if k == 0:
            items.append(self.marker("old", 0, 1))
        items += [self.marker("gone", 1, 1), self.marker("gone", 1, 1, action=2)]
        markers.markers = items
        self.markers_pub.publish(markers)

        if k % 5 == 0:
            m = self.marker("life", k, 2)
            m.lifetime.sec, m.lifetime.nanosec = 0, int(MARKER_LIFETIME_S * 1e9)
            self.marker_pub.publish(m)
        self.count += 1


@pytest.fixture(scope="module")
def viewer(support: SimpleNamespace) -> Iterator[Any]:
    import posekit.robot.scenarios  # noqa: F401 - registers the robot's scenarios
    from posekit.launch import Node as LaunchNode
    from posekit.launch.scenarios import start_scenario

    run = start_scenario(
        "p_controller", realtime=True,
        extra_nodes=[LaunchNode(support.CameraTestNode, name="viewer_test_camera"),
                     LaunchNode(DisplayTestNode, name="viewer_display_test")],
    )
    with viewer_on(run) as server:
        yield server


def open_page(browser: Any, url: str, errors: list[str]) -> Any:
    page = browser.new_page(viewport={"width": 1280, "height": 800}, accept_downloads=True)
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    page.goto(url)
    wait_for(lambda: debug(page, "connected"), what="the WebSocket connection")
    return page


@pytest.fixture(scope="module")
def page(browser: Any, viewer: Any) -> Iterator[Any]:
    errors: list[str] = []
    page = open_page(browser, viewer.url + VIEW, errors)
    yield page
    assert not errors, f"page errors: {errors}"
    page.close()


def entry(page: Any, name: str, topic: str) -> dict[str, Any] | None:
    return display_entry(page, name, topic)


def info(page: Any, name: str, topic: str) -> Any:
    return display_info(page, name, topic)


def colour_mask(image: np.ndarray, bgr: tuple[int, int, int], tol: int = 40) -> np.ndarray:
    return np.abs(image.astype(int) - np.array(bgr)).max(axis=2) <= tol  # type: ignore[no-any-return]


def colour_pixels(page: Any, bgr: tuple[int, int, int], tol: int = 40) -> int:
    return int(colour_mask(canvas_pixels(page, "#scene"), bgr, tol).sum())


CYAN = (255, 255, 0)  # BGR of #00ffff


def test_add_configure_hide_and_remove_a_pose_display_from_the_topic_list(
    page: Any, viewer: Any
) -> None:
    d = add_from_topic_list(page, "/test_pose", "Pose")
    assert d["type"] == "geometry_msgs/msg/PoseStamped"
    assert d["options"]["color"] == "#ff1900"  # RViz2's default
    assert displays(page)["subscriptions"]["/test_pose"]["queue"] == 1
    got = wait_for(lambda: info(page, "Pose", "/test_pose"), what="a pose drawn")
    assert got["frame"] == "odom"
    assert got["pose"]["position"] == {"x": 1.0, "y": -1.0, "z": 0.0}
    set_option(page, d["id"], "color", "#00ffff")
    assert entry(page, "Pose", "/test_pose")["options"]["color"] == "#00ffff"  # type: ignore[index]
    wait_for(lambda: colour_pixels(page, CYAN, 10) > 150, what="the cyan arrow drawn")
    # The arrow lies where the pose puts it: from (1, -1) along +y (yaw 90 degrees).
    image = canvas_pixels(page, "#scene")
    mask = colour_mask(image, CYAN, 10)
    box = page.eval_on_selector("#scene", "c => c.getBoundingClientRect().toJSON()")
    sx, sy = image.shape[1] / box["width"], image.shape[0] / box["height"]
    for along in (0.3, 0.7, 1.1):
        p = page.evaluate(f"window.posekitViewer.project(1.0, {-1.0 + along}, 0)")
        u, v = int((p["x"] - box["x"]) * sx), int((p["y"] - box["y"]) * sy)
        assert mask[max(v - 6, 0): v + 7, max(u - 6, 0): u + 7].any(), (along, u, v)
    # Hidden with its box, shown again, then removed: no cyan, no subscription.
    page.uncheck(f"#display-list details[data-display-id='{d['id']}'] .display-enabled")
    wait_for(lambda: colour_pixels(page, CYAN, 10) < 5, what="the arrow hidden")
    page.check(f"#display-list details[data-display-id='{d['id']}'] .display-enabled")
    wait_for(lambda: colour_pixels(page, CYAN, 10) > 150, what="the arrow shown again")
    page.click(f"#display-list details[data-display-id='{d['id']}'] .display-remove")
    wait_for(lambda: colour_pixels(page, CYAN, 10) < 5, what="the arrow removed")
    assert entry(page, "Pose", "/test_pose") is None
    assert "/test_pose" not in displays(page)["subscriptions"]
    wait_for(lambda: not viewer.tap.messages_after("/test_pose", 0),
             what="the server to stop keeping /test_pose")


def test_odometry_display_keeps_poses_past_the_tolerances_and_draws_the_covariance(
    page: Any,
) -> None:
    d = add_from_topic_list(page, "/test_odom", "Odometry")
    set_option(page, d["id"], "covariance", True)
    got = wait_for(lambda: (i := info(page, "Odometry", "/test_odom")) and i["kept"] >= 3
                   and i["covariance_radii"] and i, what="kept poses and the covariance")
    # Poses 6 cm apart, position tolerance 10 cm: at most every second one is kept.
    received = displays(page)["messages"]["/test_odom"]
    assert got["kept"] <= received // 2 + 1
    expected = np.sort(np.sqrt(np.linalg.eigvalsh(ODOM_COVARIANCE)))
    assert np.allclose(np.sort(got["covariance_radii"]), expected, atol=1e-6)
    set_option(page, d["id"], "keep", 2)
    wait_for(lambda: info(page, "Odometry", "/test_odom")["kept"] <= 2, what="keep 2")
    page.click(f"#display-list details[data-display-id='{d['id']}'] .display-remove")


def test_pose_array_and_path_displays_draw_every_pose(page: Any) -> None:
    yellow, purple = (0, 255, 255), (255, 0, 128)
    before_yellow, before_purple = colour_pixels(page, yellow, 10), colour_pixels(page, purple, 10)
    a = add_from_topic_list(page, "/test_pose_array", "PoseArray")
    set_option(page, a["id"], "color", "#ffff00")
    p = add_from_topic_list(page, "/test_path", "Path")
    set_option(page, p["id"], "color", "#8000ff")
    set_option(page, p["id"], "line_width", 0.05)
    assert wait_for(lambda: info(page, "PoseArray", "/test_pose_array"))["poses"] == ARRAY_POSES
    assert wait_for(lambda: info(page, "Path", "/test_path"))["poses"] == PATH_POSES
    wait_for(lambda: colour_pixels(page, yellow, 10) > before_yellow + 30,
             what="the yellow pose arrows drawn")
    wait_for(lambda: colour_pixels(page, purple, 10) > before_purple + 100,
             what="the purple path drawn")
    set_option(page, p["id"], "pose_style", "Arrows")
    with_arrows = wait_for(lambda: colour_pixels(page, purple, 10))
    assert with_arrows > before_purple + 100
    for d in (a, p):
        page.click(f"#display-list details[data-display-id='{d['id']}'] .display-remove")
    wait_for(lambda: colour_pixels(page, purple, 10) <= before_purple + 5, what="path removed")


def orange_pixels(page: Any) -> int:
    """Shaded orange (marker colour 1.0, 0.5, 0.0): red high, green about half, no blue."""
    image = canvas_pixels(page, "#scene").astype(int)
    b, g, r = image[..., 0], image[..., 1], image[..., 2]
    return int(((r > 90) & (g > 0.3 * r) & (g < 0.75 * r) & (b < 0.25 * r)).sum())


def test_marker_array_display_draws_every_type_and_honours_delete_and_deleteall(
    page: Any,
) -> None:
    before = orange_pixels(page)
    d = add_from_topic_list(page, "/test_markers", "Marker")
    assert displays(page)["subscriptions"]["/test_markers"]["queue"] == 100

    def settled() -> Any:
        i = info(page, "Marker", "/test_markers")
        return i if i and i["count"] == len(DRAWN_TYPES) else None

    got = wait_for(settled, what="one marker per type")
    assert got["markers"] == {f"types/{t}": name for t, name in DRAWN_TYPES.items()}
    assert got["problems"] == []
    assert "gone/1" not in got["markers"]   # added then deleted in the same array
    assert "old/0" not in got["markers"]    # removed by the next array's DELETEALL
    wait_for(lambda: orange_pixels(page) > before + 300, what="the markers drawn")
    page.uncheck(f"#display-list details[data-display-id='{d['id']}'] .display-enabled")
    wait_for(lambda: orange_pixels(page) <= before + 20, what="the markers hidden")
    page.click(f"#display-list details[data-display-id='{d['id']}'] .display-remove")


def test_marker_lifetime_removes_markers(page: Any) -> None:
    d = add_from_topic_list(page, "/test_marker", "Marker")
    wait_for(lambda: displays(page)["messages"].get("/test_marker", 0) >= 4, timeout=20,
             what="four lifetime markers received")
    # One every 0.5 s living 0.6 s: never more than two at once, though four arrived.
    assert 1 <= info(page, "Marker", "/test_marker")["count"] <= 2
    assert all(k.startswith("life/") for k in info(page, "Marker", "/test_marker")["markers"])
    page.click(f"#display-list details[data-display-id='{d['id']}'] .display-remove")


def test_image_display_shows_the_published_pixels_in_its_panel(
    page: Any, support: SimpleNamespace
) -> None:
    d = add_from_topic_list(page, "/oak/rgb/color", "Image")
    panel = f"details.display-panel[data-display-id='{d['id']}'] img"
    h, w = support.CAMERA_SIZE
    wait_for(lambda: (i := info(page, "Image", "/oak/rgb/color")) and i["frames"] >= 2
             and i["width"] == w and i["height"] == h, what="two frames in the panel")
    # The panel swaps in a new frame ~15 times a second, and while the next one loads the
    # img has no natural size (chromium): read the pixels back once one is decoded.
    sample = wait_for(lambda: page.eval_on_selector(panel, """img => {
        if (!img.complete || img.naturalWidth === 0) return null;
        const c = document.createElement('canvas'); c.width = img.naturalWidth;
        c.height = img.naturalHeight; const g = c.getContext('2d'); g.drawImage(img, 0, 0);
        const d = g.getImageData(0, 0, c.width, c.height).data; const px = [];
        for (let x = 0; x < c.width; x += 7) px.push([d[4 * (5 * c.width + x)],
            d[4 * (5 * c.width + x) + 1], d[4 * (5 * c.width + x) + 2]]);
        return px; }"""), what="a decoded frame in the panel")
    # Most of the row is the camera colour (a white bar moves across it).
    median = np.median(np.array(sample), axis=0)
    assert np.allclose(median, support.CAMERA_RGB, atol=12), median
    page.click(f"#display-list details[data-display-id='{d['id']}'] .display-remove")
    assert page.query_selector(panel) is None


def test_an_image_display_subscribes_the_server_only_while_enabled(
    page: Any, viewer: Any
) -> None:
    """The simulator's depth image (rendered only for subscribers) is listed but not
    subscribed while no display shows it; an Image display subscribes it (frames reach its
    panel); unchecking the display lets go of the topic, as RViz2's displays unsubscribe when
    disabled; checking it subscribes again; removing it lets go. Oracle: the in-process bus's
    subscriber count of the topic."""
    topic = "/oak/stereo/depth"

    def subscribers() -> int:
        return int(viewer.tap.transport.count_subscribers(topic))

    wait_for(lambda: topic in viewer.tap.image_topics(), what="the depth image listed")
    assert subscribers() == 0
    d = add_from_topic_list(page, topic, "Image")
    enabled = f"#display-list details[data-display-id='{d['id']}'] .display-enabled"
    wait_for(lambda: subscribers() == 1, what="the server subscribed")
    wait_for(lambda: (i := info(page, "Image", topic)) and i["frames"] >= 1
             and (i["width"], i["height"]) == (1280, 720), timeout=30.0,
             what="a depth frame in the panel")
    page.uncheck(enabled)
    wait_for(lambda: subscribers() == 0, what="the disabled display's topic let go")
    page.check(enabled)
    wait_for(lambda: subscribers() == 1, what="the enabled display's topic subscribed again")
    page.click(f"#display-list details[data-display-id='{d['id']}'] .display-remove")
    wait_for(lambda: subscribers() == 0, what="the removed display's topic let go")


def test_tf_display_drives_the_tf_drawing(page: Any) -> None:
    page.uncheck("#show-tf")
    d = add_from_topic_list(page, "/tf", "TF")
    assert page.is_checked("#show-tf")
    set_option(page, d["id"], "marker_scale", 2)
    assert debug(page, "tfOptions.scale") == 2
    set_option(page, d["id"], "show_names", False)
    assert not page.is_checked("#show-names")
    page.click(f"#display-list details[data-display-id='{d['id']}'] .display-remove")
    assert not page.is_checked("#show-tf")
    page.check("#show-tf")
    page.check("#show-names")


def _configured(page: Any) -> list[dict[str, Any]]:
    return [{k: d[k] for k in ("display", "topic", "type", "enabled", "options")}
            for d in displays(page)["displays"]]


def test_saved_displays_restore_from_a_file_the_url_and_the_server_option(
    browser: Any, page: Any, viewer: Any, tmp_path: Path
) -> None:
    """Displays with changed options saved as the page saves a view (its viewConfig(), what
    *Save view* downloads): removed and loaded back from the file, opened from the *Link*
    URL, and served by a ViewerServer started with the file (posekit view --config), each
    ends with the same displays, options and drawing."""
    from posekit.viewer.server import ViewerServer

    pose = add_from_topic_list(page, "/test_pose", "Pose")
    set_option(page, pose["id"], "color", "#00ffff")
    set_option(page, pose["id"], "shaft_length", 0.5)
    odom = add_from_topic_list(page, "/test_odom", "Odometry")
    page.uncheck(f"#display-list details[data-display-id='{odom['id']}'] .display-enabled")
    add_from_topic_list(page, "/test_markers", "Marker")
    saved = _configured(page)
    assert len(saved) == 3
    path = tmp_path / "view.json"
    path.write_text(json.dumps(page.evaluate("window.posekitViewer.viewConfig()")))
    assert json.loads(path.read_text())["topic_displays"] == saved
    page.click("#config-link")
    url = debug(page, "viewUrl")

    def same_view(p: Any) -> None:
        wait_for(lambda: _configured(p) == saved, what="the same displays")
        assert debug(p, "configProblems") == []
        # The same drawing: the cyan half-metre pose arrow is there.
        wait_for(lambda: info(p, "Pose", "/test_pose"), what="a pose received")
        wait_for(lambda: colour_pixels(p, CYAN, 10) > 50, what="the cyan arrow")

    for d in displays(page)["displays"]:
        page.click(f"#display-list details[data-display-id='{d['id']}'] .display-remove")
    assert displays(page)["displays"] == []
    page.set_input_files("#config-load", str(path))
    same_view(page)

    errors: list[str] = []
    other = open_page(browser, url, errors)
    try:
        same_view(other)
    finally:
        other.close()
    server = ViewerServer(viewer.tap, port=0, config=path)
    server.start()
    try:
        other = open_page(browser, server.url + VIEW, errors)
        same_view(other)
        other.close()
    finally:
        server.stop()
    assert not errors, errors
    for d in displays(page)["displays"]:
        page.click(f"#display-list details[data-display-id='{d['id']}'] .display-remove")
    assert displays(page)["displays"] == []


def test_pose_estimate_tool_publishes_an_initial_pose_the_ekf_adopts(
    page: Any, viewer: Any
) -> None:
    """Press and drag with the 2D Pose Estimate tool: a PoseWithCovarianceStamped arrives on
    /initialpose (an independent subscription) at the pressed point, heading along the drag,
    with RViz2's covariance; the scenario's EKF (set_pose remapped to /initialpose) resets
    to it: odometry/filtered jumps there while the simulator's ground truth does not."""
    from posekit.msgs.geometry_msgs import PoseWithCovarianceStamped
    from posekit.runtime.qos import QoSProfile
    from posekit.runtime.transport import EndpointInfo

    transport, logger = viewer.tap.transport, viewer.tap.logger
    poses: list[Any] = []
    filtered: list[Any] = []
    truth: list[Any] = []
    subs = [transport.subscribe(EndpointInfo(topic, cls, QoSProfile(depth=50), name, "/",
                                             logger), sink)
            for topic, cls, name, sink in [
                ("/initialpose", PoseWithCovarianceStamped, "test_pose_listener", poses.append),
                ("/odometry/filtered", Odometry, "test_filtered_listener", filtered.append),
                ("/ground_truth/odom", Odometry, "test_truth_listener", truth.append)]]
    try:
        wait_for(lambda: truth and filtered, what="odometry")
        # A point in view, away from the robot's way from the origin to its goal (5, 5).
        px, py = 0.5, -2.5
        start = page.evaluate(f"window.posekitViewer.project({px}, {py})")
        end = page.evaluate(f"window.posekitViewer.project({px}, {py - 0.5})")
        assert 0 < start["x"] < 800, start  # on the 3D view
        assert 0 < start["y"] < 800, start
        drag_tool(page, "#pose-tool", start, end)
        sent = wait_for(lambda: debug(page, "initialPoseSent"), what="initial_pose_sent")
        assert debug(page, "poseTool") is False  # one pose per activation
        assert (sent["x"], sent["y"]) == pytest.approx((px, py), abs=0.05)
        assert sent["yaw"] == pytest.approx(-math.pi / 2, abs=0.1)
        msg = wait_for(lambda: poses and poses[-1], what="a pose on /initialpose")
        assert msg.header.frame_id == "odom"
        assert (msg.pose.pose.position.x, msg.pose.pose.position.y) == pytest.approx(
            (sent["x"], sent["y"]))
        cov = np.asarray(msg.pose.covariance).reshape(6, 6)
        expected = np.zeros((6, 6))
        expected[0, 0] = expected[1, 1] = 0.25
        expected[5, 5] = (math.pi / 12) ** 2
        assert np.array_equal(cov, expected)
        received = len(filtered)

        def adopted() -> bool:
            p = filtered[-1].pose.pose.position
            return len(filtered) > received and math.dist((p.x, p.y), (px, py)) < 0.3

        wait_for(adopted, what="odometry/filtered at the estimated pose")
        t = truth[-1].pose.pose.position
        assert math.dist((t.x, t.y), (px, py)) > 1.5  # the robot itself did not jump
    finally:
        for sub in subs:
            sub.destroy()
