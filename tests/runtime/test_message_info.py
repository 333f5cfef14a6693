"""Subscription callbacks taking ``(msg, info)``: rclpy's MessageInfo.

Oracle: the real rclpy (Jazzy, in .venv-ros2): the keys of the info its two-argument
callbacks receive, and which callbacks count as two-argument ones.
"""

from __future__ import annotations

import json
import time
from collections.abc import Iterator
from typing import Any

import pytest

from _support.ros2 import run_ros2_script
from posekit.msgs.std_msgs import String
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node

RCLPY_INFO = """
import json, rclpy
from rclpy.node import Node
from std_msgs.msg import String
rclpy.init()
node = Node("info_probe")
got = {}
def with_info(msg, info):
    got["keys"] = sorted(info.keys()) if isinstance(info, dict) else sorted(vars(info))
def with_default(msg, extra=None):
    got["default_extra"] = extra
node.create_subscription(String, "probe", with_info, 10)
node.create_subscription(String, "probe", with_default, 10)
pub = node.create_publisher(String, "probe", 10)
for _ in range(200):
    pub.publish(String(data="x"))
    rclpy.spin_once(node, timeout_sec=0.05)
    if len(got) == 2:
        break
print(json.dumps(got))
"""


@pytest.fixture
def ctx() -> Iterator[Context]:
    context = Context()
    context.init(transport="inprocess")
    yield context
    context.try_shutdown()


@pytest.mark.slow
def test_message_info_keys_match_rclpy(ctx: Context) -> None:
    done = run_ros2_script(RCLPY_INFO, domain_id=57)
    assert done.returncode == 0, done.stderr
    reference = json.loads(done.stdout.strip().splitlines()[-1])
    node = Node("probe", context=ctx)
    got: dict[str, Any] = {}
    node.create_subscription(String, "probe",
                             lambda msg, info: got.setdefault("info", info), 10)
    node.create_subscription(String, "probe",
                             lambda msg, extra=None: got.setdefault("default_extra", extra), 10)
    node.create_publisher(String, "probe", 10).publish(String(data="x"))
    executor = SingleThreadedExecutor(context=ctx)
    executor.add_node(node)
    executor.spin_some()
    assert sorted(got["info"]) == reference["keys"]
    assert got["default_extra"] is None
    assert reference["default_extra"] is None
    assert 0 < time.time_ns() - got["info"]["received_timestamp"] < 10 * 10**9
