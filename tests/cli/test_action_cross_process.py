"""posekit action between real processes over Zenoh: the P controller's navigate_to_pose.

``posekit launch p_controller --zenoh --realtime`` (started without a goal) serves the
action; ``posekit action list/info/send_goal`` run as separate processes on the same fresh
loopback endpoint. Oracles: ros2action's output format and the controller's goal tolerance.
Every process is killed at the end; waits are bounded.
"""

from __future__ import annotations

import os
import re
import sys
from pathlib import Path

import pytest

from _support.ports import free_port
from _support.procs import Proc

NAV = "posekit_interfaces/action/NavigateToPose"


@pytest.mark.slow
def test_send_goal_to_the_p_controller_in_another_process(tmp_path: Path) -> None:
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("ZENOH_", "ROS_DOMAIN", "POSEKIT_"))}
    env.update(POSEKIT_ZENOH_ROUTER=f"tcp/127.0.0.1:{free_port()}", PYTHONUNBUFFERED="1")
    procs: list[Proc] = []

    def cli(*args: str) -> Proc:
        proc = Proc([sys.executable, "-m", "posekit.cli.main", *args], env, cwd=tmp_path)
        procs.append(proc)
        return proc

    try:
        launch = cli("launch", "p_controller", "goal_x:=0.0", "goal_y:=0.0", "goal_yaw:=0.0",
                     "--zenoh", "--realtime")
        launch.wait_stderr("waiting for goal_pose", 60, "the controller to start")
        listed = ""
        for _ in range(20):  # discovery across processes: bounded retries
            listed = cli("action", "list", "-t").finish(30, "posekit action list")
            if listed:
                break
        assert listed == f"/navigate_to_pose [{NAV}]\n"
        info = cli("action", "info", "/navigate_to_pose").finish(30, "posekit action info")
        assert info == ("Action: /navigate_to_pose\nAction clients: 0\nAction servers: 1\n"
                        "    /p_controller\n")
        sender = cli("action", "send_goal", "/navigate_to_pose", NAV,
                     "{pose: {header: {frame_id: odom}, pose: {position: {x: 0.4}}}}",
                     "--feedback", "--timeout", "60")
        out = sender.finish(90, "posekit action send_goal")
        assert sender.popen.returncode == 0, sender.describe()
        assert "Feedback:\n    distance_remaining: " in out
        result = re.search(r"Result:\n    distance_remaining: (\S+)\n\n"
                           r"Goal finished with status: SUCCEEDED\n$", out)
        assert result is not None, sender.describe()
        assert float(result.group(1)) <= 0.10
    finally:
        for proc in reversed(procs):
            proc.kill()
