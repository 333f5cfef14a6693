"""/rosout between real processes over Zenoh.

A talker process logs one line and keeps running; ``posekit topic echo /rosout --once``,
started afterwards in another process, still receives it (TRANSIENT_LOCAL history, as
rcl's rosout QoS asks), with the fields rclpy fills. Oracle: what the talker logged (level,
logger name, text, its function and line in the script). Processes are killed at the end.
"""

from __future__ import annotations

import os
import sys
import textwrap
from pathlib import Path

import pytest

from _support.ports import free_port
from _support.procs import Proc

TALKER = """
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
ctx = Context(); ctx.init()
node = Node("talker", context=ctx)
def say():
    node.get_logger().warning("hello from talker")
say()
print("logged", flush=True)
executor = SingleThreadedExecutor(context=ctx)
executor.add_node(node)
executor.spin()
"""


@pytest.mark.slow
def test_a_late_echo_receives_a_log_line_from_another_process(tmp_path: Path) -> None:
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("ZENOH_", "ROS_DOMAIN", "POSEKIT_"))}
    env.update(POSEKIT_ZENOH_ROUTER=f"tcp/127.0.0.1:{free_port()}", PYTHONUNBUFFERED="1",
               POSEKIT_TRANSPORT="zenoh")
    talker = Proc([sys.executable, "-c", textwrap.dedent(TALKER)], env, cwd=tmp_path)
    echo: Proc | None = None
    try:
        talker.wait_line(lambda s: s == "logged\n", 30, "the talker's log line")
        echo = Proc([sys.executable, "-m", "posekit.cli.main", "topic", "echo", "/rosout",
                     "--once"], env, cwd=tmp_path)
        out = echo.finish(60, "posekit topic echo /rosout --once")
        assert "level: 30\n" in out, echo.describe()
        assert "name: talker\n" in out
        assert "msg: hello from talker\n" in out
        assert "function: say\n" in out
        assert "line: 8\n" in out  # the log call's line in the script
    finally:
        if echo is not None:
            echo.kill()
        talker.kill()
