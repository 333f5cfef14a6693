"""posekit action list|info|send_goal against the P controller's navigate_to_pose server.

The scenario runs in real time in a background thread (as a separate process would); the
tool talks to it on the same in-process context. Oracles: ros2action's output format
(Jazzy sources: headings, indentation, status names), the controller's tolerance for the
final distance, and the feedback arithmetic (distances shrink towards the goal).
Real processes over Zenoh: tests/cli/test_action_cross_process.py.
"""

from __future__ import annotations

import io
import re
import threading
from collections.abc import Iterator
from typing import Any

import pytest

import posekit.robot.scenarios  # noqa: F401 - registers the robot's scenarios
from posekit.cli import action_cmd
from posekit.cli.main import main as posekit_main
from posekit.launch.scenarios import start_scenario

NAV = "posekit_interfaces/action/NavigateToPose"


@pytest.fixture(scope="module")
def live() -> Iterator[Any]:
    run = start_scenario("p_controller", {"goal_x": 0.0, "goal_y": 0.0, "goal_yaw": 0.0},
                         realtime=True)
    stop = threading.Event()

    def spin() -> None:
        while not stop.is_set():
            run.executor.run_for(0.05)

    thread = threading.Thread(target=spin, daemon=True)
    thread.start()
    try:
        yield run
    finally:
        stop.set()
        thread.join(10)
        run.shutdown()


def call(live: Any, *argv: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    verb = {"list": action_cmd.main_list, "info": action_cmd.main_info,
            "send_goal": action_cmd.main_send_goal}[argv[0]]
    code = verb(list(argv[1:]), context=live.context, out=out, err=err)
    return code, out.getvalue(), err.getvalue()


def test_list_and_info(live: Any) -> None:
    assert call(live, "list") == (0, "/navigate_to_pose\n", "")
    assert call(live, "list", "-t") == (0, f"/navigate_to_pose [{NAV}]\n", "")
    assert call(live, "list", "-c") == (0, "1\n", "")
    assert call(live, "info", "/navigate_to_pose") == (
        0, "Action: /navigate_to_pose\nAction clients: 0\nAction servers: 1\n"
           "    /p_controller\n", "")
    assert call(live, "info", "navigate_to_pose", "-t", "-c") == (
        0, "Action: navigate_to_pose\nAction clients: 0\nAction servers: 1\n", "")


def test_send_goal_prints_feedback_and_the_result(live: Any) -> None:
    code, out, err = call(
        live, "send_goal", "/navigate_to_pose", NAV,
        "{pose: {header: {frame_id: odom}, pose: {position: {x: 0.35}}}}", "-f",
        "--timeout", "60")
    assert code == 0, err
    assert out.startswith("Waiting for an action server to become available...\n"
                          "Sending goal:\n     pose:\n  header:\n")
    assert re.search(r"\nGoal accepted with ID: [0-9a-f]{32}\n\n", out)
    distances = [float(d) for d in re.findall(r"Feedback:\n    distance_remaining: (\S+)\n", out)]
    assert len(distances) > 5
    assert distances[0] == pytest.approx(0.35, abs=0.02)
    assert distances[-1] < distances[0] - 0.2
    result = re.search(r"Result:\n    distance_remaining: (\S+)\n\n"
                       r"Goal finished with status: SUCCEEDED\n$", out)
    assert result is not None, out[-500:]
    assert float(result.group(1)) <= 0.10  # goal_tolerance


def test_bad_input_is_one_line(live: Any) -> None:
    assert call(live, "send_goal", "/navigate_to_pose", "nope/action/X") == (
        1, "", "The passed action type is invalid\n")
    code, _, err = call(live, "send_goal", "/navigate_to_pose", NAV, "{speed: 3}")
    assert code == 1
    assert err.startswith("Failed to populate message fields: ")
    assert err.count("\n") == 1
    code, out, err = call(live, "send_goal", "/nobody_here", NAV, "--timeout", "0.5")
    assert out == "Waiting for an action server to become available...\n"
    assert code == 1
    assert err == "action server '/nobody_here' did not become available within 0.5 s\n"


def test_registered_in_the_posekit_command(capsys: pytest.CaptureFixture[str]) -> None:
    # a fresh in-process graph of its own: no actions
    assert posekit_main(["action", "list", "-c", "--transport", "inprocess"]) == 0
    assert capsys.readouterr().out == "0\n"
