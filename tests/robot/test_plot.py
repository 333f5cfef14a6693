"""posekit plot odometry backend: error series by hand, PNG output, recordings on disk."""

from __future__ import annotations

import math

import numpy as np
import pytest

from posekit.robot.nodes import OdometryRecording
from posekit.robot.plot import PlotError, errors_against_truth, plot_odometry, plot_odometry_file
from posekit.robot.scenarios import run_robot_scenario

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _recording() -> OdometryRecording:
    t = np.arange(0.0, 2.01, 0.05)
    truth = np.column_stack([t, t, 0.5 * t, 3.0 - 0.1 * t, np.ones_like(t), -0.1 * np.ones_like(t)])
    wheels = truth.copy()
    wheels[:, 2] += 0.1  # 10 cm to the left
    wheels[:, 3] = truth[:, 3] + 0.3  # crosses +pi: the error must wrap
    filtered = truth[::2].copy()
    filtered[:, 0] += 0.025  # stamps between truth samples: interpolated reference
    return OdometryRecording({"ground_truth": truth, "wheels": wheels, "filtered": filtered}, [1.5])


def test_errors_against_truth_interpolate_and_wrap() -> None:
    rec = _recording()
    _, pos, dyaw = errors_against_truth(rec, "wheels")
    assert np.allclose(pos, 0.1)
    assert np.allclose(dyaw, 0.3)  # 3.0 + 0.3 - 0.1 t is past pi, still 0.3 after wrapping
    _t, pos, dyaw = errors_against_truth(rec, "filtered")
    # Filtered = truth 25 ms earlier; truth moves at (1, 0.5) m/s and -0.1 rad/s.
    assert np.allclose(pos[:-1], 0.025 * math.hypot(1.0, 0.5))
    assert np.allclose(dyaw[:-1], 0.0025)
    final = rec.final_errors()
    assert final["wheels"] == pytest.approx((0.1, 0.3))


def test_plot_writes_a_png_and_recordings_round_trip(tmp_path) -> None:
    rec = _recording()
    out = plot_odometry(rec, tmp_path / "odom", title="synthetic", dpi=50)
    assert out.name == "odom.png"
    assert out.read_bytes()[:8] == PNG_SIGNATURE
    import matplotlib.image as mpimg

    assert mpimg.imread(out).shape[:2] == (250, 750)  # 15 x 5 inches at 50 dpi
    saved = rec.save(tmp_path / "run.npz")
    loaded = OdometryRecording.load(saved)
    assert loaded.goal_reached == [1.5]
    for name, rows in rec.series.items():
        assert np.array_equal(loaded.series[name], rows)
    again = plot_odometry_file(saved, tmp_path / "from_file.png", dpi=50)
    assert again.read_bytes()[:8] == PNG_SIGNATURE


def test_plot_errors_are_named(tmp_path) -> None:
    with pytest.raises(PlotError, match="no odometry messages"):
        plot_odometry(OdometryRecording({"wheels": np.zeros((0, 6))}), tmp_path / "x.png")
    bad = tmp_path / "bad.npz"
    np.savez(bad, something=np.zeros(3))
    with pytest.raises(PlotError, match="not a posekit recording"):
        plot_odometry_file(bad, tmp_path / "y.png")
    with pytest.raises(PlotError, match="cannot read recording"):
        plot_odometry_file(tmp_path / "missing.npz", tmp_path / "z.png")


def test_p_controller_scenario_can_write_the_plot_at_the_end(tmp_path) -> None:
    result = run_robot_scenario(
        "p_controller", seed=0, until_sim_time=3.0, plot_path=tmp_path / "pc.png"
    )
    assert result.plot_path == tmp_path / "pc.png"
    assert result.plot_path.read_bytes()[:8] == PNG_SIGNATURE
