"""Argument parsing of ``static_transform_publisher`` (tf2_ros), reproduced exactly.

Flags take one value each and may appear in any order (a later flag wins); any other token is
positional. The deprecated positional forms are ``x y z yaw pitch roll frame child`` (8) and
``x y z qx qy qz qw frame child`` (9). Float parsing follows ``std::stod``: a numeric prefix
is enough (``1.5abc`` reads as 1.5).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

__all__ = ["USAGE", "StaticArgsError", "StaticTransformArgs", "parse_static_args", "stod"]

USAGE = (
    "usage: static_transform_publisher [--x X] [--y Y] [--z Z] [--qx QX] [--qy QY] [--qz QZ]"
    " [--qw QW] [--roll ROLL] [--pitch PITCH] [--yaw YAW] --frame-id FRAME_ID"
    " --child-frame-id CHILD_FRAME_ID\n"
    "\n"
    "A command line utility for manually sending a transform.\n"
    "\n"
    "optional arguments:\n"
    "  -h, --help                            show this help message and exit\n"
    "  --x X                                 x component of a vector for translation\n"
    "  --y Y                                 y component of a vector for translation\n"
    "  --z Z                                 z component of a vector for translation\n"
    "  --qx QX                               x component of a quaternion for rotation\n"
    "  --qy QY                               y component of a quaternion for rotation\n"
    "  --qz QZ                               z component of a quaternion for rotation\n"
    "  --qw QW                               w component of a quaternion for rotation\n"
    "  --roll ROLL                           roll component Euler angles for rotation\n"
    "  --pitch PITCH                         pitch component Euler angles for rotation\n"
    "  --yaw YAW                             yaw component Euler angles for rotation\n"
    "  --frame-id FRAME_ID                   parent frame\n"
    "  --child-frame-id CHILD_FRAME_ID       child frame id\n"
    "\n"
    "A few examples of usage:\n"
    "  - Publish a static transform from mystamp to mychild with no translation or rotation:\n"
    "      static_transform_publisher --frame-id mystamp --child-frame-id mychild\n"
    "  - Publish a static transform with translation and quaternion rotation:\n"
    "      static_transform_publisher --x 1 --y 2 --z 3 --qx 0 --qy 0 --qz 0 --qw 1"
    " --frame-id world --child-frame-id robot\n"
)

_FLOAT_PREFIX = re.compile(
    r"\s*[+-]?(?:(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|inf(?:inity)?|nan)", re.IGNORECASE
)


class StaticArgsError(ValueError):
    """A command line that static_transform_publisher rejects; ``str()`` is tf2_ros's text."""


def stod(text: str) -> float:
    """Parse like C++ ``std::stod``: the longest numeric prefix; ValueError when there is none."""
    match = _FLOAT_PREFIX.match(text)
    if match is None:
        raise ValueError(text)
    return float(match.group(0))


@dataclass(slots=True)
class StaticTransformArgs:
    """The parsed transform. ``rpy`` is set when Euler angles were given (radians)."""

    translation: tuple[float, float, float]
    quaternion_xyzw: tuple[float, float, float, float] | None
    rpy: tuple[float, float, float] | None
    frame_id: str
    child_frame_id: str
    old_style: bool = False
    show_help: bool = False


_FLOAT_FLAGS = ("--x", "--y", "--z", "--qx", "--qy", "--qz", "--qw", "--roll", "--pitch", "--yaw")
_STRING_FLAGS = ("--frame-id", "--child-frame-id")


def _parse_float(flag: str, value: str) -> float:
    try:
        return stod(value)
    except ValueError:
        raise StaticArgsError(f"Failed to parse {flag} argument as float") from None


def parse_static_args(argv: list[str]) -> StaticTransformArgs:
    """Parse static_transform_publisher's arguments, raising StaticArgsError with tf2's text."""
    values: dict[str, float] = {}
    strings: dict[str, str] = {}
    positional: list[str] = []
    i = 0
    while i < len(argv):
        token = argv[i]
        if token in ("--help", "-h"):
            return StaticTransformArgs((0.0, 0.0, 0.0), None, None, "", "", show_help=True)
        if token in _FLOAT_FLAGS or token in _STRING_FLAGS:
            if i + 1 >= len(argv):
                raise StaticArgsError(f"Not enough arguments for {token}")
            if token in _FLOAT_FLAGS:
                values[token] = _parse_float(token, argv[i + 1])
            else:
                strings[token] = argv[i + 1]
            i += 2
            continue
        positional.append(token)
        i += 1

    quat_given = any(f in values for f in ("--qx", "--qy", "--qz", "--qw"))
    rpy_given = any(f in values for f in ("--roll", "--pitch", "--yaw"))
    if quat_given and rpy_given:
        raise StaticArgsError("Cannot specify both quaternion and Euler rotations")
    new_style = bool(strings) or quat_given or any(f in values for f in ("--x", "--y", "--z"))
    if positional and new_style:
        raise StaticArgsError("Cannot specify both new-style (flags) and old-style (arguments)")

    if len(positional) in (8, 9):
        nums = [_parse_float("positional", p) for p in positional[: len(positional) - 2]]
        frame_id, child = positional[-2], positional[-1]
        translation = (nums[0], nums[1], nums[2])
        if len(positional) == 8:
            yaw, pitch, roll = nums[3], nums[4], nums[5]
            parsed = StaticTransformArgs(translation, None, (roll, pitch, yaw), frame_id, child)
        else:
            quat = (nums[3], nums[4], nums[5], nums[6])
            parsed = StaticTransformArgs(translation, quat, None, frame_id, child)
        parsed.old_style = True
    elif positional:
        raise StaticArgsError("Extra unparsed arguments on command-line")
    else:
        translation = (values.get("--x", 0.0), values.get("--y", 0.0), values.get("--z", 0.0))
        quat_xyzw = (
            values.get("--qx", 0.0),
            values.get("--qy", 0.0),
            values.get("--qz", 0.0),
            values.get("--qw", 1.0),
        )
        rpy = (values.get("--roll", 0.0), values.get("--pitch", 0.0), values.get("--yaw", 0.0))
        parsed = StaticTransformArgs(
            translation,
            None if rpy_given else quat_xyzw,
            rpy if rpy_given else None,
            strings.get("--frame-id", ""),
            strings.get("--child-frame-id", ""),
        )
    if not parsed.frame_id:
        raise StaticArgsError("Frame id must not be empty")
    if not parsed.child_frame_id:
        raise StaticArgsError("Child frame id must not be empty")
    return parsed

