"""Bad values a user or a file can hand the runtime: timer periods, None for typed
parameters, transform stamps that are no builtin_interfaces/Time.

Oracle: the real rclpy (ROS 2 Jazzy, ``tests/_support/ros2.py``) run on the same inputs: the
exception type for each timer period, and the SetParametersResult for ``None``. For stamps,
rclpy's message field checks (int32 ``sec``, uint32 ``nanosec``) define what is refused.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from _support.ros2 import run_ros2_script
from posekit.msgs.geometry_msgs import TransformStamped
from posekit.runtime.node import Node
from posekit.runtime.parameters import Parameter
from posekit.tf2 import Buffer

PERIODS = [math.nan, math.inf, -1.0, 0.0, 0.5]

RCLPY = """
import json, math, rclpy
from rclpy.node import Node
from rclpy.parameter import Parameter
rclpy.init()
n = Node("probe")
out = {"timers": []}
for p in [float(x) for x in %r]:
    try:
        n.create_timer(p, lambda: None)
        out["timers"].append("ok")
    except Exception as e:
        out["timers"].append(type(e).__name__)
n.declare_parameter("x", 1.0)
r = n.set_parameters([Parameter("x", value=None)])[0]
out["param"] = [r.successful, r.reason, n.get_parameter("x").value]
print(json.dumps(out))
"""


@pytest.fixture(scope="module")
def rclpy_answers() -> dict[str, object]:
    done = run_ros2_script(RCLPY % ([repr(p) for p in PERIODS],), domain_id=93)
    assert done.returncode == 0, done.stderr
    return dict(json.loads(done.stdout.strip().splitlines()[-1]))


def test_timer_periods_fail_like_rclpy(ctx, rclpy_answers: dict[str, object]) -> None:
    node = Node("timers", context=ctx)
    ours = []
    for p in PERIODS:
        try:
            node.create_timer(p, lambda: None)
            ours.append("ok")
        except (ValueError, OverflowError) as exc:
            ours.append(type(exc).__name__)
    theirs = rclpy_answers["timers"]
    # rclpy raises its RCLError for a negative period; posekit a ValueError.
    assert ours == [("ValueError" if t == "RCLError" else t) for t in theirs]  # type: ignore[union-attr]
    with pytest.raises(ValueError, match="nan"):
        node.create_timer(np.float64("nan"), lambda: None)  # numpy NaN too


def test_none_for_a_typed_parameter_is_refused_like_rclpy(
    ctx, rclpy_answers: dict[str, object]
) -> None:
    node = Node("params", context=ctx)
    node.declare_parameter("x", 1.0)
    result = node.set_parameters([Parameter("x", value=None)])[0]
    assert [result.successful, result.reason, node.get_parameter("x").value] == (
        rclpy_answers["param"])


def _tf(sec: object, nanosec: object = 0) -> TransformStamped:
    t = TransformStamped()
    t.header.frame_id = "odom"
    t.child_frame_id = "base_link"
    t.header.stamp.sec = sec  # type: ignore[assignment]
    t.header.stamp.nanosec = nanosec  # type: ignore[assignment]
    t.transform.rotation.w = 1.0
    return t


@pytest.mark.parametrize(
    ("sec", "nanosec", "error", "field"),
    [(1.5, 0, TypeError, "sec"), (2**70, 0, ValueError, "sec"), (-(2**31) - 1, 0, ValueError,
     "sec"), (1, -1, ValueError, "nanosec"), (1, 2**32, ValueError, "nanosec"),
     (True, 0, TypeError, "sec"), ("1", 0, TypeError, "sec")],
)
def test_stamps_that_are_no_time_are_refused_with_the_reason(
    sec: object, nanosec: object, error: type[Exception], field: str
) -> None:
    buffer = Buffer()
    with pytest.raises(error, match=rf"header\.stamp\.{field}"):
        buffer.set_transform(_tf(sec, nanosec), "test")
    assert buffer.get_all_frame_names() == []  # nothing half-stored


def test_valid_edge_stamps_and_numpy_ints_are_accepted() -> None:
    assert Buffer().set_transform(_tf(2**31 - 1, 2**32 - 1), "test")
    assert Buffer().set_transform(_tf(np.int64(5), np.uint32(7)), "test")
    assert Buffer().set_transform_static(_tf(-(2**31)), "test")
