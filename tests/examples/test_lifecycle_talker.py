"""ROS 2's lifecycle demo across processes: ``examples/lifecycle_talker.py`` driven by
``posekit lifecycle`` and watched by ``posekit topic echo``, each in its own process on Zenoh.

Oracle: the demo's behaviour (ROS 2 ``lifecycle`` package): nothing on ``lifecycle_chatter``
until the node is activated, then ``Lifecycle HelloWorld #N`` once a second; rcl_lifecycle's
states as ``ros2 lifecycle get`` prints them.
"""

from __future__ import annotations

import os
import re
import signal
import sys
from pathlib import Path

import pytest

from _support.ports import free_port
from _support.procs import Proc

pytestmark = pytest.mark.slow

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_the_talker_publishes_only_once_activated_from_another_terminal(tmp_path: Path) -> None:
    pytest.importorskip("zenoh")
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("ZENOH_", "ROS_DOMAIN", "POSEKIT_"))}
    env.update(POSEKIT_ZENOH_ROUTER=f"tcp/127.0.0.1:{free_port()}", PYTHONUNBUFFERED="1",
               POSEKIT_TRANSPORT="zenoh")
    def cli(*args: str) -> Proc:
        return Proc([sys.executable, "-m", "posekit.cli.main", *args], env, cwd=tmp_path)

    talker = Proc([sys.executable, str(EXAMPLES / "lifecycle_talker.py")], env, cwd=tmp_path)
    echo = None
    try:
        get = cli("lifecycle", "get", "/lc_talker")
        assert get.finish(40, "get") == "unconfigured [1]\n", get.describe()
        assert cli("lifecycle", "set", "/lc_talker", "configure").finish(40, "configure") == (
            "Transitioning successful\n")
        talker.wait_stderr("Messages are not published.", 20, "the inactive timer's line")
        echo = cli("topic", "echo", "/lifecycle_chatter", "std_msgs/msg/String")
        assert cli("lifecycle", "set", "/lc_talker", "activate").finish(40, "activate") == (
            "Transitioning successful\n")
        line = echo.wait_line(lambda s: s.startswith("data:"), 30, "a message once active")
        # (quoted as PyYAML quotes a " #", as ros2 topic echo prints it)
        assert re.fullmatch(r"data: 'Lifecycle HelloWorld #\d+'\n", line), line
        assert cli("lifecycle", "get", "/lc_talker").finish(40, "get") == "active [3]\n"
        # every message echoed came after the activation the talker logged
        number = int(line.rsplit("#", 1)[1].rstrip("'\n"))
        activated = next(i for i, s in enumerate(talker.err) if "on_activate() is called." in s)
        inactive = [s for s in talker.err[:activated] if "currently inactive" in s]
        assert number > len(inactive) >= 1
    finally:
        for proc in (echo, talker):
            if proc is not None:
                proc.kill(signal.SIGINT)
                proc.kill()
