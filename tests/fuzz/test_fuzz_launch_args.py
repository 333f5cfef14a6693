"""Bounded, seeded fuzzer: launch arguments and parameter values from a command line
(``posekit launch SCENARIO name:=value``).

Oracle: the contract of posekit.runtime.parameters.parse_parameter_value (every string gives
a value of a ROS 2 parameter type: bool, int, float, str or a list of one of those, or
raises RCLError as rcl does) and of the launch command's argument parser (its one-line
usage error for text without ``:=``); and that a value accepted here makes a Parameter.
"""

from __future__ import annotations

import random
import string

from posekit.cli.launch_cmd import _parse_assignment, _UsageError
from posekit.runtime.arguments import RCLError
from posekit.runtime.parameters import Parameter, parse_parameter_value

CHARS = string.printable + "[],:=\"'é\u202e"


def _is_parameter_value(value: object) -> bool:
    if isinstance(value, bool | int | float | str):
        return True
    return isinstance(value, list) and all(_is_parameter_value(v) and not isinstance(v, list)
                                           for v in value)


def test_random_assignments_parse_or_raise_a_usage_error() -> None:
    rng = random.Random(41)
    parsed = refused = 0
    for _ in range(3000):
        text = "".join(rng.choice(CHARS) for _ in range(rng.randint(0, 40)))
        if rng.random() < 0.6:
            text = f"p{rng.randrange(9)}:=" + text
        try:
            name, value = _parse_assignment(text)
        except (_UsageError, RCLError):
            refused += 1
            continue
        parsed += 1
        assert _is_parameter_value(value), (text, value)
        again = parse_parameter_value(text.split(":=", 1)[1])
        assert again == value or (again != again and value != value), (text, value)  # NaN
        Parameter(name or "x", value=value)
    assert parsed > 0
    assert refused > 0
