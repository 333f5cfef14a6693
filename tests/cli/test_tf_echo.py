"""tf2_echo: output text byte for byte (docs/specs/tf2.md §11.1) and the tool against a live
buffer."""

import io

import pytest

from posekit.cli.tf_echo import USAGE, format_echo_block, main, parse_rate
from posekit.msgs.geometry_msgs import TransformStamped
from posekit.runtime.context import Context
from posekit.runtime.node import Node
from posekit.tf2 import quat_from_rpy
from posekit.tf2_ros import StaticTransformBroadcaster

SPEC_BLOCK = """At time 1700000000.5000000
- Translation: [1.000, -2.500, 0.123]
- Rotation: in Quaternion [0.103, 0.043, 0.992, 0.065]
- Rotation: in RPY (radian) [0.100, -0.200, 3.000]
- Rotation: in RPY (degree) [5.730, -11.459, 171.887]
- Matrix:
 -0.970 -0.121  0.210  1.000
  0.138 -0.988  0.071 -2.500
  0.199  0.098  0.975  0.123
  0.000  0.000  0.000  1.000
"""


def test_block_matches_real_tf2_echo_output() -> None:
    # docs/specs/tf2.md's block was printed by the real tf2_echo for t=(1,-2.5,0.123456),
    # rpy=(0.1,-0.2,3).
    q = quat_from_rpy(0.1, -0.2, 3.0)
    assert format_echo_block(1700000000, 5_000_000, (1.0, -2.5, 0.123456), q) == SPEC_BLOCK


@pytest.mark.parametrize(("text", "code"), [("abc", 2), ("1.0foo", 3)])
def test_rate_errors_have_tf2_exit_codes(text: str, code: int) -> None:
    err = io.StringIO()
    assert main(["a", "b", text], out=io.StringIO(), err=err) == code
    expected = f"Failed to convert rate argument '{text}' to a floating-point number\n"
    assert err.getvalue() == expected


def test_rate_parses_like_stof() -> None:
    assert parse_rate("2.5") == 2.5
    assert parse_rate("10") == 10.0


def test_wrong_argument_count_prints_usage() -> None:
    out = io.StringIO()
    assert main(["only_one"], out=out) == 1
    assert out.getvalue() == USAGE


def test_echo_against_a_static_broadcaster_in_process() -> None:
    context = Context()
    context.init(transport="inprocess")
    try:
        node = Node("publisher", context=context)
        t = TransformStamped()
        t.header.frame_id = "map"
        t.child_frame_id = "base"
        t.transform.translation.x = 1.0
        t.transform.translation.y = -2.0
        t.transform.rotation.z = 1.0  # 180 degrees about z, after normalisation (0, 0, 1, 0)
        t.transform.rotation.w = 0.0
        StaticTransformBroadcaster(node).sendTransform(t)
        out = io.StringIO()
        assert main(["map", "base", "--count", "1"], context=context, out=out, timeout_s=5) == 0
        lines = out.getvalue().splitlines()
        # Static lookups at time 0 echo stamp 0.
        assert lines[0] == "At time 0.0"
        assert lines[1] == "- Translation: [1.000, -2.000, 0.000]"
        assert lines[2] == "- Rotation: in Quaternion [0.000, 0.000, 1.000, 0.000]"
        assert lines[3] == "- Rotation: in RPY (radian) [0.000, -0.000, 3.142]"
        assert lines[6].split()[0::3] == ["-1.000", "1.000"]
        assert lines[7] == "  0.000 -1.000  0.000 -2.000"
    finally:
        context.shutdown()
