"""static_transform_publisher argument parsing against tf2_ros's behaviour (docs/specs/tf2.md
§11.2)."""

import math

import pytest

from posekit.cli.static_args import StaticArgsError, parse_static_args, stod


def test_flag_form_defaults_and_order_independence() -> None:
    a = parse_static_args(["--child-frame-id", "b", "--x", "1", "--frame-id", "a", "--x", "2"])
    assert a.translation == (2.0, 0.0, 0.0)  # later flag wins
    assert a.quaternion_xyzw == (0.0, 0.0, 0.0, 1.0)
    assert (a.frame_id, a.child_frame_id) == ("a", "b")
    assert not a.old_style


def test_quaternion_flags_are_not_normalised() -> None:
    a = parse_static_args(["--qz", "1", "--frame-id", "a", "--child-frame-id", "b"])
    assert a.quaternion_xyzw == (0.0, 0.0, 1.0, 1.0)


def test_rpy_flags() -> None:
    a = parse_static_args(["--yaw", "1.5", "--frame-id", "a", "--child-frame-id", "b"])
    assert a.rpy == (0.0, 0.0, 1.5)
    assert a.quaternion_xyzw is None


def test_old_style_eight_args_are_yaw_pitch_roll() -> None:
    a = parse_static_args(["1", "2", "3", "0.3", "0.2", "0.1", "map", "base"])
    assert a.old_style
    assert a.translation == (1.0, 2.0, 3.0)
    assert a.rpy == (0.1, 0.2, 0.3)
    assert (a.frame_id, a.child_frame_id) == ("map", "base")


def test_old_style_nine_args_quaternion() -> None:
    a = parse_static_args(["1", "2", "3", "0", "0", "0.6", "0.8", "map", "base"])
    assert a.quaternion_xyzw == (0.0, 0.0, 0.6, 0.8)


def test_stod_accepts_numeric_prefix() -> None:
    assert stod("1.5abc") == 1.5
    assert stod("  -2e3x") == -2000.0
    assert math.isinf(stod("inf"))
    with pytest.raises(ValueError, match="abc"):
        stod("abc")


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--frame-id", "a", "--child-frame-id", "b", "--x"], "Not enough arguments for --x"),
        (["--x", "abc", "--frame-id", "a", "--child-frame-id", "b"],
         "Failed to parse --x argument as float"),
        (["--qx", "0", "--roll", "1", "--frame-id", "a", "--child-frame-id", "b"],
         "Cannot specify both quaternion and Euler rotations"),
        (["1", "2", "3", "0", "0", "0", "a", "b", "--x", "1"],
         "Cannot specify both new-style (flags) and old-style (arguments)"),
        (["1", "2", "3"], "Extra unparsed arguments on command-line"),
        (["--child-frame-id", "b"], "Frame id must not be empty"),
        (["--frame-id", "a"], "Child frame id must not be empty"),
    ],
)
def test_errors_have_tf2_texts(argv: list[str], message: str) -> None:
    with pytest.raises(StaticArgsError) as info:
        parse_static_args(argv)
    assert str(info.value) == message


def test_rpy_flags_mixed_with_positional_not_detected_like_tf2() -> None:
    # tf2 does not notice positional args mixed with --roll/--pitch/--yaw; the old form wins.
    a = parse_static_args(["1", "2", "3", "0", "0", "0", "a", "b", "--roll", "1"])
    assert a.old_style


def test_help() -> None:
    assert parse_static_args(["--x", "1", "-h"]).show_help
