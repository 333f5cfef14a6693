"""The pose walkthrough runs as a module and prints the lecture's numbers (checked against
closed forms computed here, not against posekit)."""

import math
import re
import subprocess
import sys

import numpy as np
import pytest

NUM = r"[+-]\d+\.\d{3}"


@pytest.fixture(scope="module")
def text():
    out = subprocess.run(
        [sys.executable, "-m", "posekit.demos.pose_walkthrough"],
        capture_output=True,
        text=True,
        check=True,
        timeout=60,
    )
    assert out.stderr == ""
    return out.stdout


def tuples_in(line):
    return [
        np.array([float(v) for v in re.findall(NUM, group)])
        for group in re.findall(r"\(([^()]*)\)", line)
        if re.fullmatch(rf"\s*{NUM}(,\s*{NUM})*\s*", group)
    ]


def line_with(text, start):
    (line,) = [ln for ln in text.splitlines() if ln.strip().startswith(start)]
    return line


def half_angle_wxyz(axis, deg):
    h = math.radians(deg) / 2
    return np.array([math.cos(h), *(math.sin(h) * np.array(axis))])


@pytest.mark.parametrize(
    ("label", "axis", "deg"),
    [
        ("No rotation", (0, 0, 1), 0),
        ("90 deg about Z", (0, 0, 1), 90),
        ("180 deg about Z", (0, 0, 1), 180),
        ("90 deg about X", (1, 0, 0), 90),
        ("45 deg about Y", (0, 1, 0), 45),
    ],
)
def test_common_quaternion_table(text, label, axis, deg):
    (q,) = tuples_in(line_with(text, label))
    np.testing.assert_allclose(q, half_angle_wxyz(axis, deg), atol=5e-4)
    assert line_with(text, label).rstrip().endswith(f"{deg:.1f} deg")


def test_exercise_and_double_cover(text):
    s = math.sqrt(2) / 2
    (q,) = tuples_in(line_with(text, "q = (w, x, y, z)"))
    np.testing.assert_allclose(q, [s, s, 0, 0], atol=5e-4)
    _, rotated = tuples_in(line_with(text, "rotating p"))
    np.testing.assert_allclose(rotated, [0, 0, 1], atol=5e-4)  # y axis -> z axis
    assert line_with(text, "double cover").endswith("same rotation: True")


def test_world_vs_body(text):
    # Hamilton products by hand: qx = (c, s, 0, 0), qz = (c, 0, 0, s), c = s = sqrt(2)/2
    world_q, world_nose, world_top = tuples_in(text.splitlines()[text.splitlines().index(
        line_with(text, "world frame")) + 1])
    body_q, body_nose, body_top = tuples_in(text.splitlines()[text.splitlines().index(
        line_with(text, "body frame")) + 1])
    np.testing.assert_allclose(world_q, [0.5, 0.5, -0.5, 0.5], atol=5e-4)  # qx * qz
    np.testing.assert_allclose(body_q, [0.5, 0.5, 0.5, 0.5], atol=5e-4)  # qz * qx
    np.testing.assert_allclose(world_nose, [0, 0, 1], atol=5e-4)
    np.testing.assert_allclose(body_nose, [0, 1, 0], atol=5e-4)
    np.testing.assert_allclose(body_top, [1, 0, 0], atol=5e-4)
    np.testing.assert_allclose(world_top, [0, -1, 0], atol=5e-4)
    assert "same result? False" in text


def test_gimbal_lock_section(text):
    d = math.radians(60)
    expected = np.array([[0, -math.sin(d), math.cos(d)], [0, math.cos(d), math.sin(d)], [-1, 0, 0]])
    rows = [
        np.array([float(v) for v in re.findall(NUM, ln)])
        for ln in text.splitlines()
        if re.fullmatch(rf"\s*\[{NUM} {NUM} {NUM}\]", ln)
    ]
    assert len(rows) == 6
    np.testing.assert_allclose(np.array(rows[:3]), expected, atol=5e-4)
    np.testing.assert_allclose(np.array(rows[3:]), expected, atol=5e-4)
    (angles,) = tuples_in(line_with(text, "as_euler('ZYX')"))
    np.testing.assert_allclose(angles, [60, 90, 0], atol=5e-4)
    assert "GimbalLockWarning raised: True" in text
