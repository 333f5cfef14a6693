"""The main demo (``make demo``): it runs, prints the listener's lines and a table whose
estimated marker positions are within 5 cm of docs/specs/rosbot_and_worlds.md's true positions, and
saves a readable debug image. Shortened to 3 simulated seconds to keep the suite fast."""

from __future__ import annotations

import re
from pathlib import Path

import cv2
import numpy as np
import pytest

from posekit.demos.main import main

# docs/specs/rosbot_and_worlds.md: aruco_box_world's front markers in odom
TRUE = {2: (2.000, -0.5002, 0.250), 4: (2.000, 0.000, 0.250), 5: (2.000, 0.5002, 0.250)}
NUM = r"\s*(-?\d+\.\d{3})"
ROW = re.compile(rf"aruco_marker_(\d+)\s+\({NUM},{NUM},{NUM}\)\s+\({NUM},{NUM},{NUM}\)"
                 r"\s+(\d+\.\d) cm\s+(\d+)")


def test_main_demo_table_and_debug_image(tmp_path: Path, capsys: pytest.CaptureFixture[str]
                                         ) -> None:
    assert main(["--seconds", "3", "--output-dir", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    listener = [line for line in out.splitlines() if "[aruco_marker_listener]" in line]
    assert len(listener) == 9  # t = 1, 2, 3 s x three markers
    assert all(re.search(r"aruco_marker_\d in odom: x=-?\d+\.\d{3}, y=-?\d+\.\d{3}, "
                         r"z=-?\d+\.\d{3}$", line) for line in listener)
    rows = {int(m.group(1)): m for m in ROW.finditer(out)}
    assert set(rows) == set(TRUE)
    for marker_id, m in rows.items():
        estimated = np.array([float(m.group(k)) for k in (2, 3, 4)])
        printed_true = np.array([float(m.group(k)) for k in (5, 6, 7)])
        assert printed_true == pytest.approx(TRUE[marker_id], abs=6e-4)
        error = np.linalg.norm(estimated - TRUE[marker_id])
        assert error < 0.05
        assert float(m.group(8)) == pytest.approx(100 * error, abs=0.2)
        assert int(m.group(9)) == 90  # seen in every frame
    paths = re.findall(r"Debug image .*: (\S+\.png)", out)
    assert len(paths) == 1
    image = cv2.imread(paths[0])
    assert image is not None
    assert image.shape == (720, 1280, 3)
    # outlines and axes drawn in colour on the grey render
    assert (np.ptp(image.astype(int), axis=2) > 60).sum() > 500


def test_bad_arguments_exit_with_a_message() -> None:
    with pytest.raises(SystemExit) as exc:
        main(["--seconds", "-1"])
    assert exc.value.code == 2
