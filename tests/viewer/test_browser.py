"""The viewer page in a real browser (Debian chromium, software WebGL) on the P-controller
scenario running in this process, with a small camera node for the image panels.

Pixels are read from the canvas itself (``canvas.toDataURL()``), never from a page
screenshot. Everything shares one scenario and one browser to stay well under a minute.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

pytestmark = pytest.mark.slow  # real processes, sessions or a browser

cv2 = pytest.importorskip("cv2")

from _support.browser import canvas_pixels, debug, drag_tool, drawn_fraction, wait_for  # noqa: E402
from posekit.viewer.taps import RTF_WINDOW_S  # noqa: E402

ROBOT_FRAMES = {"odom", "base_link", "body_link", "imu_link", "fl_wheel_link", "rr_wheel_link",
                "oak_rgb_camera_optical_frame"}


@pytest.fixture(scope="module")
def viewer(scenario_viewer: Any) -> Any:
    return scenario_viewer


@pytest.fixture(scope="module")
def page(browser: Any, viewer: Any) -> Iterator[Any]:
    page = browser.new_page(viewport={"width": 1280, "height": 800})
    errors: list[str] = []
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    page.goto(viewer.url)
    wait_for(lambda: debug(page, "connected"), what="the WebSocket connection")
    yield page
    assert not errors, f"page errors: {errors}"
    page.close()


def test_frame_list_contains_the_robot_frames(page: Any) -> None:
    def options() -> set[str]:
        values = page.eval_on_selector_all("#fixed-frame option", "os => os.map(o => o.value)")
        return set(values) if set(values) >= ROBOT_FRAMES else set()

    assert wait_for(options, what="robot frames in the fixed-frame list") >= ROBOT_FRAMES
    tree = page.eval_on_selector_all("#tf-tree tbody tr", "rs => rs.map(r => r.dataset.frame)")
    assert set(tree) >= ROBOT_FRAMES
    assert debug(page, "renderer") == "webgl"
    assert debug(page, "fixedFrame") == "odom"
    assert debug(page, "fixedFrameError") is None


def test_3d_canvas_draws_and_toggles_change_it(page: Any) -> None:
    wait_for(lambda: debug(page, "renders") > 5, what="renders")
    with_all = canvas_pixels(page, "#scene")
    assert drawn_fraction(with_all) > 0.01, "the 3D canvas is (nearly) empty"
    page.uncheck("#show-grid")
    page.uncheck("#show-tf")
    time.sleep(0.3)
    without = canvas_pixels(page, "#scene")
    page.check("#show-grid")
    page.check("#show-tf")
    assert with_all.shape == without.shape
    assert drawn_fraction(without) < drawn_fraction(with_all) - 0.002, (
        "hiding the grid and TF did not remove drawn pixels"
    )


def test_fixed_frame_selector(page: Any) -> None:
    page.select_option("#fixed-frame", "base_link")
    wait_for(lambda: debug(page, "fixedFrame") == "base_link", what="fixed frame base_link")
    rows = {f[0]: f for f in debug(page, "tf.frames")}
    # In its own frame base_link is the identity; odom is somewhere else once the robot moved.
    assert rows["base_link"][2:9] == [0, 0, 0, 0, 0, 0, 1]
    assert rows["odom"][11] is True
    assert debug(page, "fixedFrameError") is None
    assert page.eval_on_selector("#fixed-frame", "s => s.value") == "base_link"
    page.select_option("#fixed-frame", "odom")
    wait_for(lambda: debug(page, "fixedFrame") == "odom", what="fixed frame back to odom")
    rows = {f[0]: f for f in debug(page, "tf.frames")}
    assert rows["odom"][2:9] == [0, 0, 0, 0, 0, 0, 1]


def test_fixed_frame_poses_match_tf2(viewer: Any, page: Any) -> None:
    # The server's rows for fixed frame base_link: base_link is the identity and odom is the
    # inverse of T_odom_base computed here with plain 2D trigonometry.
    error, rows = viewer.tap.frames_in("base_link")
    assert error is None
    pose = {r[0]: r for r in rows}
    assert pose["base_link"][2:9] == [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]
    t = viewer.tap.buffer.lookup_transform_core("odom", "base_link", 0)
    x, y = t.transform.translation.x, t.transform.translation.y
    q = t.transform.rotation
    yaw = math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y**2 + q.z**2))
    inv_x = -math.cos(yaw) * x - math.sin(yaw) * y
    inv_y = math.sin(yaw) * x - math.cos(yaw) * y
    _, rows_again = viewer.tap.frames_in("base_link")
    odom = {r[0]: r for r in rows_again}["odom"]
    assert odom[11] is True
    # The robot may have moved between the two reads (20 Hz updates, <= 0.5 m/s).
    assert abs(odom[2] - inv_x) < 0.05
    assert abs(odom[3] - inv_y) < 0.05


def test_missing_fixed_frame_shows_a_clear_message(browser: Any, viewer: Any) -> None:
    page = browser.new_page(viewport={"width": 900, "height": 600})
    try:
        page.goto(viewer.url + "?fixed_frame=map")
        banner = page.wait_for_selector("#fixed-frame-status:not([hidden])", timeout=10_000)
        assert banner is not None
        assert "Fixed Frame [map] does not exist" in banner.inner_text()
    finally:
        page.close()


def test_image_panels_update_with_the_published_pixels(
    page: Any, support: SimpleNamespace
) -> None:
    first = wait_for(lambda: (debug(page, "imageUpdates") or {}).get("/oak/rgb/color", 0),
                     what="a camera image")
    wait_for(lambda: debug(page, "imageUpdates").get("/oak/rgb/color", 0) >= first + 3,
             what="more camera images")
    wait_for(lambda: debug(page, "imageUpdates").get("/aruco_detection_image", 0) >= 1,
             what="an aruco_detection_image")
    # Read the displayed image back through a 2D canvas: size and colour (rgb8 -> RGB). The
    # page swaps in a new frame ~15 times a second; read it back once one is decoded.
    sample = wait_for(lambda: page.evaluate(
        """() => { const img = document.getElementById('camera-image');
          if (!img.complete || img.naturalWidth === 0) return null;
          const c = document.createElement('canvas'); c.width = img.naturalWidth;
          c.height = img.naturalHeight; const g = c.getContext('2d'); g.drawImage(img, 0, 0);
          const d = g.getImageData(0, 0, c.width, c.height).data;
          // the white bar moves: take the median colour of sampled pixels
          const rs = [], gs = [], bs = [];
          for (let i = 0; i < d.length; i += 4 * 97) {
            rs.push(d[i]); gs.push(d[i + 1]); bs.push(d[i + 2]);
          }
          const med = a => a.sort((x, y) => x - y)[a.length >> 1];
          return [c.width, c.height, med(rs), med(gs), med(bs)]; }"""
    ), what="a decoded camera image")
    h, w = support.CAMERA_SIZE
    assert sample[:2] == [w, h]
    assert np.allclose(sample[2:], support.CAMERA_RGB, atol=12), sample


_LOADER_RUN = """async ([jpeg, burst, streamMs]) => {
  const { newestImageLoader } = await import('/app/image_loader.js');
  // count the URLs of this test's blobs only (the page's own panels make theirs meanwhile)
  const created = [], revoked = new Set(), mine = new WeakSet();
  const make = URL.createObjectURL, revoke = URL.revokeObjectURL;
  URL.createObjectURL = (b) => { const u = make(b); if (mine.has(b)) created.push(u); return u; };
  URL.revokeObjectURL = (u) => { revoked.add(u); revoke(u); };
  try {
    const bytes = Uint8Array.from(atob(jpeg), (c) => c.charCodeAt(0));
    const img = new Image(), shown = [];
    const loader = newestImageLoader(img, (i) => shown.push([i, img.naturalWidth]));
    const until = async (done) => {  // at most 10 s
      for (let t = 0; t < 1000 && !done(); t++) await new Promise((r) => setTimeout(r, 10));
    };
    const last = () => (shown.length ? shown[shown.length - 1][0] : -1);
    const send = (i, data = bytes) => {
      const blob = new Blob([data], { type: "image/jpeg" });
      mine.add(blob);
      loader.show(blob, i);
    };
    for (let i = 0; i < burst; i++) send(i);  // a burst in one task
    await until(() => last() === burst - 1);
    const afterBurst = shown.slice();
    send(-1, "not a jpeg");  // loads at once (the loader is idle) and fails
    send(burst);
    await until(() => last() === burst);
    // then a new blob every millisecond: far faster than a 1280x720 JPEG decodes
    let sent = burst + 1;
    const t0 = performance.now();
    while (performance.now() - t0 < streamMs) {
      send(sent++);
      await new Promise((r) => setTimeout(r, 1));
    }
    await until(() => last() === sent - 1);
    const live = created.filter((u) => !revoked.has(u)).length;
    loader.dispose();
    return { afterBurst, shown, sent, created: created.length, live,
             liveAfterDispose: created.filter((u) => !revoked.has(u)).length };
  } finally {
    URL.createObjectURL = make;
    URL.revokeObjectURL = revoke;
  }
}"""


def test_image_panels_show_the_newest_frame_and_never_abort_a_load(page: Any) -> None:
    """The page's image loader (app/image_loader.js, behind the image panels and the Image
    and Camera displays) under frames arriving faster than the browser decodes them:

    - a burst of 20 in one task shows the first and the last and nothing between;
    - an undecodable blob is skipped, frees its URL, and the one after it is shown;
    - a stream at 1 kHz shows every frame whose load began (none is aborted by the next,
      which would leave a stream faster than the decoder showing nothing at all) and ends
      on the newest;
    - blob URLs: only the one on screen stays alive, and none after dispose().
    """
    noise = np.random.default_rng(0).integers(0, 255, (720, 1280, 3), dtype=np.uint8)
    ok, jpeg = cv2.imencode(".jpg", noise, [cv2.IMWRITE_JPEG_QUALITY, 90])
    assert ok
    import base64

    r = page.evaluate(_LOADER_RUN, [base64.b64encode(jpeg.tobytes()).decode(), 20, 1000])
    assert r["afterBurst"] == [[0, 1280], [19, 1280]]
    shown = [i for i, _ in r["shown"]]
    assert shown[2] == 20
    assert -1 not in shown
    assert shown[-1] == r["sent"] - 1  # ends on the newest
    assert shown == sorted(set(shown))
    assert all(width == 1280 for _, width in r["shown"])
    # every URL made was for a load that completed, except the undecodable one
    assert r["created"] == len(shown) + 1
    assert r["live"] == 1
    assert r["liveAfterDispose"] == 0


def test_odometry_trail_grows(page: Any) -> None:
    first = wait_for(lambda: (debug(page, "trails") or {}).get("/odometry/filtered", 0),
                     what="an odometry trail")
    wait_for(lambda: debug(page, "trails").get("/odometry/filtered", 0) > first,
             what="the odometry/filtered trail to grow")
    trails = debug(page, "trails")
    assert trails.get("/odometry/wheels", 0) >= 1
    assert trails.get("/ground_truth/odom", 0) >= 1


def test_stale_frame_is_greyed_in_the_tree(page: Any, support: SimpleNamespace) -> None:
    stale = support.STALE_FRAME
    row = page.wait_for_selector(f"#tf-tree tr.stale[data-frame='{stale}']",
                                 timeout=10_000)
    assert row is not None
    assert page.eval_on_selector("#tf-tree tr[data-frame='base_link']",
                                 "r => r.classList.contains('stale')") is False


def _label_rects(page: Any) -> dict[str, dict[str, float]]:
    return dict(page.evaluate("""() => Object.fromEntries(
        [...document.querySelectorAll('#tf-labels .tf-label:not([hidden])')].map(e => {
          const r = e.getBoundingClientRect();
          return [e.dataset.frame, {x: r.x, y: r.y, w: r.width, h: r.height}];
        }))"""))


def test_frame_names_do_not_overlap_though_the_frames_do(page: Any) -> None:
    """Around the robot many frame origins project within a label's height of each other
    (three.js's projection of the frames' poses); the names shown never overlap (the
    labels' own rectangles in the page) and every robot frame keeps its name."""
    def all_named() -> dict[str, dict[str, float]]:
        rects = _label_rects(page)
        return rects if set(rects) >= ROBOT_FRAMES else {}

    rects = wait_for(all_named, what="a name for every robot frame")
    assert debug(page, "labels().hidden") == 0
    names = list(rects)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            ra, rb = rects[a], rects[b]
            apart = (ra["x"] + ra["w"] <= rb["x"] or rb["x"] + rb["w"] <= ra["x"]
                     or ra["y"] + ra["h"] <= rb["y"] or rb["y"] + rb["h"] <= ra["y"])
            assert apart, f"labels {a} and {b} overlap: {ra} {rb}"
    rows = {f[0]: f for f in debug(page, "tf.frames") if f[11]}
    anchors = [page.evaluate(f"window.posekitViewer.project({r[2]}, {r[3]}, {r[4]})")
               for name, r in rows.items() if name in ROBOT_FRAMES]
    height = max(r["h"] for r in rects.values())
    crowded = sum(
        1 for i, a in enumerate(anchors) for b in anchors[i + 1:]
        if abs(a["y"] - b["y"]) < height and abs(a["x"] - b["x"]) < 60
    )
    assert crowded > 0, "the robot's frames do not crowd: this test would prove nothing"


def test_tf_display_per_frame_axes_names_and_marker_scale(page: Any,
                                                          support: SimpleNamespace) -> None:
    """RViz2's TF display: a frame's 'show' box hides its axes and name, its 'name' box only
    the name; the marker scale grows the axes (more drawn pixels); stale names are grey."""
    wait_for(lambda: "imu_link" in debug(page, "labels().frames"), what="imu_link drawn")
    page.uncheck("#tf-tree input[data-kind='show'][data-frame='imu_link']")
    page.uncheck("#tf-tree input[data-kind='name'][data-frame='body_link']")
    time.sleep(0.3)
    state = debug(page, "labels()")
    assert "imu_link" not in state["frames"]
    assert "imu_link" not in state["shown"]
    assert "body_link" in state["frames"]
    assert "body_link" not in state["shown"]
    assert debug(page, "tfOptions") == {"hidden": ["imu_link"], "noName": ["body_link"],
                                        "scale": 1}
    # The boxes survive the tree's periodic rebuild.
    time.sleep(0.7)
    assert page.is_checked("#tf-tree input[data-kind='show'][data-frame='imu_link']") is False
    page.click("#tf-show-all")
    wait_for(lambda: {"imu_link", "body_link"} <= set(debug(page, "labels().shown")),
             what="names back after 'show all'")

    page.uncheck("#show-grid")
    page.click("#pause")  # a still scene: only the marker scale changes between the pictures
    time.sleep(0.3)
    small = drawn_fraction(canvas_pixels(page, "#scene"))
    page.fill("#marker-scale", "4")
    time.sleep(0.3)
    large = drawn_fraction(canvas_pixels(page, "#scene"))
    page.fill("#marker-scale", "1")
    page.click("#pause")
    page.check("#show-grid")
    assert large > small + 0.002, (small, large)

    stale = support.STALE_FRAME
    label = page.wait_for_selector(f"#tf-labels .tf-label.stale[data-frame='{stale}']",
                                   state="attached", timeout=10000)
    assert label is not None


def test_clock_shows_sim_time_wall_time_and_the_real_time_factor(page: Any) -> None:
    """The toolbar's clock: the run's sim time (the executor's), the wall time, and an RTF
    equal to the sim/wall progress the page itself saw over the server's RTF window (the
    readings the page got are the server's samples; the run is paced to the wall clock, so
    the RTF is at most about 1, and lower when the machine is busy)."""
    first = wait_for(lambda: debug(page, "clock"), what="the clock state")
    assert first["source"] == "executor"
    assert first["rate_clock"] == "sim"
    assert abs(first["wall"] - time.time()) < 5.0
    assert page.is_visible("#clock")
    readings = [first]

    def record() -> bool:
        reading = debug(page, "clock")
        if reading["wall"] != readings[-1]["wall"]:
            readings.append(reading)
        return bool(reading["wall"] >= first["wall"] + RTF_WINDOW_S + 1.5)

    wait_for(record, what=f"{RTF_WINDOW_S + 1.5} s of clock readings")
    last = readings[-1]
    # The window starts at a sample between RTF_WINDOW_S and one graph period older than the
    # newest: the progress measured from each reading of that age brackets the RTF.
    progress = [(last["sim"] - r["sim"]) / (last["wall"] - r["wall"]) for r in readings
                if RTF_WINDOW_S - 0.25 <= last["wall"] - r["wall"] <= RTF_WINDOW_S + 1.25]
    assert progress, [r["wall"] - last["wall"] for r in readings]
    assert last["rtf"] is not None
    assert min(progress) - 0.05 <= last["rtf"] <= max(progress) + 0.05, (last["rtf"], progress)
    assert 0.05 < last["rtf"] < 1.3
    text = page.inner_text("#clock")
    assert text.startswith("sim ")
    assert " s · wall " in text
    assert "RTF" in text
    sim_shown = float(text.split()[1])
    assert sim_shown == pytest.approx(debug(page, "clock.sim"), abs=1.0)
    assert page.inner_text("#topics-hz") == "Hz (sim)"


def test_pause_stops_updates(page: Any) -> None:
    page.click("#pause")
    time.sleep(0.3)
    count = debug(page, "tfMessages")
    time.sleep(0.6)
    assert debug(page, "tfMessages") == count
    page.click("#pause")
    wait_for(lambda: debug(page, "tfMessages") > count, what="updates after resuming")


def _magenta_pixels(image: np.ndarray) -> int:
    """Pixels of the goal arrow's colour (#ff40ff; BGR 255, 64, 255), shading included."""
    b, g, r = (image[..., i].astype(int) for i in range(3))
    return int(((r > 150) & (b > 150) & (g < 0.6 * r) & (g < 0.6 * b)).sum())


def test_goal_tool_publishes_a_goal_the_p_controller_drives_to(page: Any, viewer: Any) -> None:
    """Press on the ground and drag with the 2D Goal Pose tool: a PoseStamped arrives on
    goal_pose (an independent subscription on the run's bus) at the pressed point, heading
    along the drag; the goal is drawn; and the simulated robot's true pose (the simulator's
    ground truth) closes in on it, so the P controller acts on it."""
    from posekit.msgs.geometry_msgs import PoseStamped
    from posekit.msgs.nav_msgs import Odometry
    from posekit.runtime.qos import QoSProfile
    from posekit.runtime.transport import EndpointInfo

    transport = viewer.tap.transport
    goals: list[Any] = []
    truth: list[Any] = []
    logger = viewer.tap.logger
    subs = [
        transport.subscribe(EndpointInfo("/goal_pose", PoseStamped, QoSProfile(depth=10),
                                         "test_goal_listener", "/", logger), goals.append),
        transport.subscribe(EndpointInfo("/ground_truth/odom", Odometry, QoSProfile(depth=10),
                                         "test_truth_listener", "/", logger), truth.append),
    ]
    try:
        wait_for(lambda: truth, what="ground truth odometry")
        pose = truth[-1].pose.pose
        q = pose.orientation
        heading = math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y ** 2 + q.z ** 2))
        # One metre behind the robot: where its current goal does not take it.
        gx = pose.position.x - math.cos(heading)
        gy = pose.position.y - math.sin(heading)
        start = page.evaluate(f"window.posekitViewer.project({gx}, {gy})")
        end = page.evaluate(f"window.posekitViewer.project({gx + 0.5}, {gy})")
        assert 0 < start["x"] < 1280, start  # on screen
        assert 0 < start["y"] < 800, start
        drag_tool(page, "#goal-tool", start, end)
        sent = wait_for(lambda: debug(page, "goalSent"), what="the goal_sent answer")
        assert debug(page, "goalTool") is False  # one goal per activation, as in RViz2
        assert (sent["x"], sent["y"]) == pytest.approx((gx, gy), abs=0.05)
        assert sent["yaw"] == pytest.approx(0.0, abs=0.1)
        wait_for(lambda: goals, what="a PoseStamped on goal_pose")
        msg = goals[-1]
        assert msg.header.frame_id == "odom"
        assert (msg.pose.position.x, msg.pose.position.y) == pytest.approx((sent["x"], sent["y"]))
        o = msg.pose.orientation
        assert 2 * math.atan2(o.z, o.w) == pytest.approx(sent["yaw"], abs=1e-9)

        drawn = wait_for(lambda: debug(page, "goal"), what="the goal drawn from goal_pose")
        assert drawn["frame"] == "odom"
        assert drawn["pose"][:2] == pytest.approx([sent["x"], sent["y"]])
        time.sleep(0.2)  # next render: the goal arrow is in the scene
        shown = _magenta_pixels(canvas_pixels(page, "#scene"))
        page.uncheck("#show-goal")
        time.sleep(0.3)
        hidden = _magenta_pixels(canvas_pixels(page, "#scene"))
        page.check("#show-goal")
        assert shown > hidden + 30, (shown, hidden)

        def distance() -> float:
            p = truth[-1].pose.pose.position
            return math.hypot(p.x - sent["x"], p.y - sent["y"])

        before = distance()
        wait_for(lambda: distance() < before - 0.4, timeout=30.0,
                 what="the robot closing in on the clicked goal")
    finally:
        for sub in subs:
            sub.destroy()


def test_a_saved_view_restores_the_same_view_from_a_file_and_from_the_url(
    browser: Any, viewer: Any, tmp_path: Any
) -> None:
    """Orbit with the mouse, change displays and TF options, save the view to a file; a new
    page that loads the file, and one opened with the Link URL, end with the same state and
    (only static displays on) the same pixels as the page the view was saved from."""
    import json

    def open_page(url: str) -> Any:
        p = browser.new_page(viewport={"width": 1100, "height": 700})
        p.goto(url)
        wait_for(lambda: debug(p, "connected"), what="the WebSocket connection")
        wait_for(lambda: debug(p, "renders") > 2, what="renders")
        return p

    def still(p: Any) -> np.ndarray:
        p.wait_for_timeout(400)  # the next capped-rate render has drawn the new view
        return canvas_pixels(p, "#scene")

    def settled(p: Any) -> Any:
        """The configuration without the panels, camera rounded to 1 µm (three.js's orbit
        update recomputes the position in floating point)."""
        cfg = p.evaluate("window.posekitViewer.viewConfig()")
        cfg["view"] = {k: [round(v, 6) for v in vec] for k, vec in cfg["view"].items()}
        return {k: v for k, v in cfg.items() if k != "panels"}

    first = open_page(viewer.url)
    second = third = None
    try:
        box = first.locator("#scene").bounding_box()
        cx, cy = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        first.mouse.move(cx, cy)
        first.mouse.down()
        first.mouse.move(cx + 140, cy + 30, steps=8)  # orbit (three.js OrbitControls)
        first.mouse.up()
        for toggle in ("#show-tf", "#show-names", "#show-robot", "#show-odom-filtered",
                       "#show-odom-wheels", "#show-truth", "#show-goal"):
            first.uncheck(toggle)
        first.fill("#marker-scale", "2.5")
        first.uncheck("#tf-tree input[data-kind='show'][data-frame='imu_link']")
        saved_state = settled(first)
        assert saved_state["tf"]["hidden"] == ["imu_link"]
        assert saved_state["view"]["camera"] != pytest.approx([-1.5, -2.5, 4.0])  # orbited
        assert saved_state["tf"]["marker_scale"] == 2.5
        with first.expect_download() as download:
            first.click("#config-save")
        path = tmp_path / "view.json"
        download.value.save_as(path)
        saved = json.loads(path.read_text())
        assert saved["posekit_view"] == 1
        saved_view = {k: [round(v, 6) for v in vec] for k, vec in saved["view"].items()}
        assert {**{k: v for k, v in saved.items() if k != "panels"},
                "view": saved_view} == saved_state
        first.click("#config-link")
        link = debug(first, "viewUrl")
        assert "view=" in link
        pixels = still(first)

        second = open_page(viewer.url)
        assert settled(second) != saved_state
        second.set_input_files("#config-load", str(path))
        wait_for(lambda: debug(second, "configLoaded"), what="the file loaded")
        assert debug(second, "configProblems") == []
        assert settled(second) == saved_state
        assert np.abs(still(second).astype(int) - pixels.astype(int)).max() <= 2

        third = open_page(link)
        assert settled(third) == saved_state
        assert np.abs(still(third).astype(int) - pixels.astype(int)).max() <= 2

        # A file that is not a view configuration is named and changes nothing.
        bad = tmp_path / "bad.json"
        bad.write_text(json.dumps({"hello": 1}))
        third.set_input_files("#config-load", str(bad))
        wait_for(lambda: debug(third, "configError"), what="the refusal")
        assert "not a posekit view configuration" in debug(third, "configError")
        assert settled(third) == saved_state
    finally:
        for p in (first, second, third):
            if p is not None:
                p.close()


def test_2d_fallback_draws(browser: Any, viewer: Any) -> None:
    page = browser.new_page(viewport={"width": 900, "height": 600})
    try:
        page.goto(viewer.url + "?renderer=2d")
        wait_for(lambda: debug(page, "renderer") == "2d", what="the 2D renderer")
        wait_for(lambda: debug(page, "tfMessages") > 3 and debug(page, "renders") > 3,
                 what="2D renders")
        time.sleep(0.2)
        image = canvas_pixels(page, "#scene2d")
        assert drawn_fraction(image) > 0.01
        assert "2D" in page.inner_text("#renderer-note")
    finally:
        page.close()


def test_missing_three_js_falls_back_to_2d_naming_the_fix_and_recovers_on_reload(
    browser: Any, viewer: Any, tmp_path: Any, monkeypatch: pytest.MonkeyPatch
) -> None:
    import posekit.viewer.server as server

    vendored = server.THREE_ROOT
    monkeypatch.setattr(server, "THREE_ROOT", tmp_path)  # an installation without three.js
    page = browser.new_page(viewport={"width": 900, "height": 600})
    try:
        page.goto(viewer.url)
        wait_for(lambda: debug(page, "renderer") == "2d", what="the 2D fallback")
        note = page.inner_text("#renderer-note")
        assert "three.js is missing" in note
        assert "pip install --force-reinstall 'posekit[viewer]'" in note
        assert "scene3d" not in note
        monkeypatch.setattr(server, "THREE_ROOT", vendored)  # repaired: no server restart
        page.reload()
        wait_for(lambda: debug(page, "renderer") == "webgl", what="the 3D view after reload")
        assert page.is_hidden("#renderer-note")
    finally:
        page.close()


def test_dynamic_detector_scenario_shows_camera_detections_and_marker_frames(
    browser: Any,
) -> None:
    import threading

    from posekit.cli.view_cmd import attach_to_run
    from posekit.launch.scenarios import start_scenario

    pytest.importorskip("posekit.vision.scenarios")  # registers the ArUco scenarios
    run = start_scenario("dynamic_detector", realtime=True)
    server = attach_to_run(run, port=0)
    spinner = threading.Thread(target=run.executor.spin, daemon=True)
    spinner.start()
    page = browser.new_page(viewport={"width": 1280, "height": 800})
    try:
        page.goto(server.url + "?camera=0.5,-1.2,1.0&target=2,0.3,0.25")
        wait_for(lambda: debug(page, "world") == "aruco_box_world", what="the world")
        updates = wait_for(
            lambda: (debug(page, "imageUpdates") or {}).get("/aruco_detection_image", 0) >= 2
            and debug(page, "imageUpdates"),
            timeout=20.0, what="aruco_detection_image frames",
        )
        assert updates.get("/oak/rgb/color", 0) >= 1
        markers = wait_for(
            lambda: {f for f in debug(page, "frames") if f.startswith("aruco_marker_")},
            timeout=10.0, what="aruco_marker frames",
        )
        assert markers <= {f"aruco_marker_{i}" for i in (2, 4, 5)}
        # (0 while the next frame loads: read it between two)
        width = wait_for(lambda: page.eval_on_selector("#aruco-image", "img => img.naturalWidth"),
                         what="a decoded aruco_detection_image")
        assert width == 1280
        _camera_frustum_and_detections(page, server)
    finally:
        page.close()
        server.stop()
        run.shutdown()
        spinner.join(timeout=5.0)


def _highlight_pixels(page: Any) -> int:
    """Pixels of the detection highlight's colour #00ff66 (BGR 102, 255, 0), blends included."""
    image = canvas_pixels(page, "#scene").astype(int)
    b, g, r = image[..., 0], image[..., 1], image[..., 2]
    return int(((g > 150) & (g > r + 80) & (g > b + 60) & (b > 0.2 * g)).sum())


def _camera_frustum_and_detections(page: Any, server: Any) -> None:
    """The camera drawn in 3D: a Camera display added by itself for the camera_info topic,
    paired with the colour image, its far-plane corners where the pinhole K puts them
    (numpy: K^-1 [u, v, 1] at 1 m) and the image textured there; the detected markers
    highlighted at their TF frames, and the highlight toggled with Detections."""
    info_topic = "/oak/stereo/camera_info"

    def camera() -> Any:
        for d in page.evaluate("window.posekitViewer.displays()")["displays"]:
            if d["display"] == "Camera" and d["topic"] == info_topic and d["info"] \
                    and d["info"]["corners"] and d["info"]["image_frames"] >= 1:
                return d["info"]
        return None

    cam = wait_for(camera, timeout=20.0, what="the Camera display with an image")
    # Drawn: hiding the display (its box in the Displays panel) changes a good share of the
    # canvas (the far plane with the image faces this view).
    box = f"#display-list details[data-topic='{info_topic}'] .display-enabled"
    shown = canvas_pixels(page, "#scene")
    page.uncheck(box)
    wait_for(lambda: (np.abs(canvas_pixels(page, "#scene").astype(int) - shown.astype(int))
                      .max(axis=2) > 30).mean() > 0.02, what="the camera frustum hidden")
    page.check(box)
    assert cam["image_topic"] == "/oak/rgb/color"
    assert cam["image_size"] == [1280, 720]
    assert cam["image_shown"] is True
    # shown again, the display watches its topic anew: its next message is kept
    kept = wait_for(lambda: server.tap.messages_after(info_topic, 0), timeout=20.0,
                    what="a camera_info kept after the display was shown again")
    info = kept[-1][1]
    assert cam["frame"] == info.header.frame_id
    k = np.array(info.k, float).reshape(3, 3)
    pixels = np.array([[0, 0, 1], [info.width, 0, 1], [info.width, info.height, 1],
                       [0, info.height, 1]], float)
    expected = (np.linalg.inv(k) @ pixels.T).T
    assert np.allclose(cam["corners"], expected, atol=1e-9)

    def detections() -> Any:
        d = debug(page, "detections()")
        return d if d and set(d) <= {f"aruco_marker_{i}" for i in (2, 4, 5)} else None

    highlighted = wait_for(detections, timeout=10.0, what="highlighted detections")
    rows = {r[0]: r for r in debug(page, "tf.frames")}
    for name, h in highlighted.items():
        assert np.allclose(h["position"], rows[name][2:5], atol=0.05), (name, h, rows[name])
    wait_for(lambda: _highlight_pixels(page) > 100, what="the highlight drawn")
    page.uncheck("#show-detections")
    wait_for(lambda: _highlight_pixels(page) < 20, what="the highlight hidden")
    page.check("#show-detections")
