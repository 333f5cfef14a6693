"""``posekit view`` arguments and attaching a viewer to a launch run (cli/view_cmd.py)."""

from __future__ import annotations

import json
import urllib.request
from typing import Any

import pytest

pytest.importorskip("aiohttp")

import posekit.robot.scenarios  # noqa: F401 - registers the robot's scenarios
from posekit.cli.view_cmd import attach_to_run, find_world, main
from posekit.launch.scenarios import start_scenario

pytestmark = pytest.mark.slow  # real processes, sessions or a browser


def test_bad_arguments_exit_2(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--port", "70000"]) == 2
    assert "--port" in capsys.readouterr().err
    assert main(["--scenario", "p_controller", "--zenoh"]) == 2
    assert "cannot be combined" in capsys.readouterr().err
    assert main(["--scenario", "no_such_scenario"]) == 2
    assert "unknown scenario" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["--help"])


def test_a_config_that_is_not_a_saved_view_stops_with_one_line(
    tmp_path: Any, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = tmp_path / "view.json"
    bad.write_text('{"something": "else"}')
    assert main(["--scenario", "p_controller", "--port", "0", "--config", str(bad)]) == 1
    err = capsys.readouterr().err
    assert "not a posekit view configuration" in err
    assert len(err.strip().splitlines()) == 1
    assert "Traceback" not in err


def test_attach_to_a_stepped_run_uses_its_world_and_sim_time() -> None:
    run = start_scenario("empty_world", {"world": "aruco_box_world"})
    try:
        assert find_world(run) == "aruco_box_world"
        server = attach_to_run(run, port=0)
        try:
            run.executor.run_until(2.0)
            server.tap.refresh()
            run.executor.run_until(3.0)
            with urllib.request.urlopen(server.url + "api/state") as response:
                state = json.load(response)
            assert state["error"] is None
            assert "base_link" in {r[0] for r in state["frames"]}
            assert server.tap.now_ns() == 3_000_000_000  # the executor's simulated time
            tree = {f["name"]: f for f in state["tree"]}
            assert tree["base_link"]["age"] < 0.1
            assert tree["base_link"]["rate"] == pytest.approx(20.0)
            hello = server._hello()
            assert hello["world"]["name"] == "aruco_box_world"
            assert len(hello["world"]["boxes"]) == 3
        finally:
            server.stop()
    finally:
        run.shutdown()
