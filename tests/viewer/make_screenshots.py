"""Write the viewer screenshots of docs/viewer.md into docs/images/ (not a test).

    .venv/bin/python tests/viewer/make_screenshots.py [OUTDIR [NAME ...]]

1. ``viewer_p_controller.png``: the P-controller scenario (goal (5, 5, pi/2)) after about
   14 s of simulated time, paced to the wall clock.
2. ``viewer_aruco.png``: the ``dynamic_detector`` scenario (the ROSbot approaching the
   ArUco boxes, the OAK camera's frustum and image, the detector's debug image and the
   ``aruco_marker_<id>`` frames) after about 5 s.
3. ``viewer_cameras.png``: the same scenario seen from behind the robot: the OAK camera's
   frustum with its image on the far plane (the Camera display added for
   ``/oak/stereo/camera_info``) and the detected markers highlighted.

NAMEs (``p_controller``, ``aruco``, ``cameras``) pick some of them; default: all.

Needs chromium (scripts/install_browser_deps.sh) and the viewer's PyPI packages.
"""

from __future__ import annotations

import os
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

import posekit.robot.scenarios  # noqa: F401 - registers the robot's scenarios
from posekit.cli.view_cmd import attach_to_run
from posekit.launch.scenarios import start_scenario

FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--use-gl=angle", "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader", "--disable-background-networking",
    "--disable-component-update", "--disable-sync", "--no-first-run",
]


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
    wanted = set(argv[1:]) or {"p_controller", "aruco", "cameras"}
    out.mkdir(parents=True, exist_ok=True)
    if "p_controller" in wanted:
        run = start_scenario("p_controller", realtime=True)
        shoot(run, out / "viewer_p_controller.png", 14.0,
              "?camera=-0.5,-2.5,4.2&target=2.6,2.4,0")
    import posekit.vision.scenarios  # noqa: F401 - registers the ArUco scenarios

    if "aruco" in wanted:
        run = start_scenario("dynamic_detector", realtime=True)
        shoot(run, out / "viewer_aruco.png", 5.0, "?camera=-0.9,-1.5,1.3&target=1.5,0.1,0.15")
    if "cameras" in wanted:
        run = start_scenario("dynamic_detector", realtime=True)
        shoot(run, out / "viewer_cameras.png", 8.0, "?camera=0.5,-1.2,1.0&target=2,0.3,0.25")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
