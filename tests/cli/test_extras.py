"""A missing optional dependency is reported before anything runs, in one line naming the
extra to install. Oracle: the extras of pyproject.toml (read with tomllib) and the command's
own output; modules are made missing by hiding them from the import system."""

from __future__ import annotations

import sys
import tomllib
from pathlib import Path

import pytest

from posekit.cli import main as cli
from posekit.cli._extras import EXTRA_MODULES, missing_extra, require

REPO = Path(__file__).resolve().parents[2]


def test_every_checked_extra_exists_in_pyproject() -> None:
    extras = tomllib.loads((REPO / "pyproject.toml").read_text())["project"][
        "optional-dependencies"]
    assert set(EXTRA_MODULES) <= set(extras)
    assert all(missing_extra(extra) == [] for extra in EXTRA_MODULES)  # dev installs all
    assert require("posekit launch", [("--plot", "plot")]) is None


@pytest.mark.parametrize(("argv", "module", "extra", "what"), [
    (["launch", "p_controller", "--until-sim-time", "30", "--plot", "odom.png"],
     "matplotlib", "plot", "--plot"),
    (["launch", "p_controller", "--until-sim-time", "1", "--viewer"], "aiohttp", "viewer",
     "--viewer"),
    (["launch", "p_controller", "--until-sim-time", "1", "--zenoh"], "zenoh", "zenoh",
     "--zenoh"),
    (["launch", "p_controller", "--until-sim-time", "1", "--isolated", "--record", "run1"],
     "rosbags", "bag",
     "--record"),
    (["plot", "odometry", "--scenario", "p_controller"], "matplotlib", "plot", "plotting"),
    (["view", "--scenario", "empty_world", "--port", "0"], "aiohttp", "viewer",
     "posekit view"),
    (["bag", "info", "run1"], "rosbags", "bag", "ROS 2 bags"),
])
def test_missing_extra_is_one_line_before_the_run(
    argv: list[str], module: str, extra: str, what: str, tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
) -> None:
    monkeypatch.chdir(tmp_path)
    monkeypatch.setitem(sys.modules, module, None)  # find_spec -> None: "not installed"
    assert cli.main(argv) == 2
    out, err = capsys.readouterr()
    assert out == ""  # nothing ran: no scenario summary
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert f"{what} needs {module}" in lines[0]
    assert lines[0].endswith(f"pip install 'posekit[{extra}]'")
    assert list(tmp_path.iterdir()) == []  # no plot, no bag written


def test_vision_scenarios_name_their_extra(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
) -> None:
    import posekit.vision.scenarios  # noqa: F401 - registers them
    from posekit.demos.scenarios import SCENARIO_EXTRAS
    from posekit.launch.scenarios import get_scenario, scenario_names

    vision = {n for n in scenario_names()
              if get_scenario(n).factory.__module__ == "posekit.vision.scenarios"}
    assert set(SCENARIO_EXTRAS) == vision
    monkeypatch.setitem(sys.modules, "cv2", None)
    assert cli.main(["launch", "dynamic_detector", "--until-sim-time", "1"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == ("posekit launch: scenario dynamic_detector needs cv2, which is not installed: "
                   "pip install 'posekit[vision]'")
