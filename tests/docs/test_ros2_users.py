"""docs/ros2-users.md is true of the code: every posekit import it shows imports, every
``posekit GROUP VERB`` it names is a command, every scenario it names exists, and each
lecture launch command of its table resolves (``posekit launch PACKAGE FILE.launch.py``) to a
scenario, for a world the very one the table names beside it.

Oracles: the document's own text, read here with regular expressions; the CLI's command
table and the scenario registry.
"""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import pytest

import posekit.demos.scenarios  # noqa: F401  (registers every scenario)
from posekit.cli.main import _COMMANDS
from posekit.demos.lecture import resolve_launch
from posekit.launch.scenarios import scenario_names

DOC = Path(__file__).resolve().parents[2] / "docs" / "ros2-users.md"
TEXT = DOC.read_text(encoding="utf-8")
CODE = re.findall(r"`([^`]+)`", TEXT)


def test_every_import_shown_imports() -> None:
    imports = [c for c in CODE if re.match(r"(from posekit\S* import |import posekit)", c)]
    assert len(imports) >= 8, imports
    for line in imports:
        match = re.match(r"from (\S+) import (.+)", line)
        if match is None:
            importlib.import_module(line.split()[1])
            continue
        module = importlib.import_module(match.group(1))
        for name in (n.strip() for n in match.group(2).split(",")):
            if not hasattr(module, name):  # a submodule, as "from posekit import rclpy"
                importlib.import_module(f"{match.group(1)}.{name}")


def test_every_command_named_exists() -> None:
    groups = {g for g, _ in _COMMANDS}
    named = 0
    for code in CODE:
        for match in re.finditer(r"posekit ([a-z_]+)(?: ([a-z_/]+))?", code):
            group, verbs = match.group(1), match.group(2)
            if group in ("rclpy", "tf2_ros", "import"):  # module paths, not commands
                continue
            assert group in groups, (group, code)
            named += 1
            if (group, None) in _COMMANDS or verbs is None:
                continue
            for verb in verbs.split("/"):  # "topic list/info/hz/pub"
                assert (group, verb) in _COMMANDS, (group, verb, code)
    assert named >= 20


@pytest.mark.parametrize("row", [r for r in TEXT.splitlines()
                                 if r.startswith("| `ros2 launch ")])
def test_lecture_launch_commands_map_to_the_scenario_beside_them(row: str) -> None:
    lecture, posekit = (cell.strip() for cell in row.strip("|").split("|")[:2])
    words = re.match(r"`ros2 launch (\S+) (\S+)`", lecture)
    assert words is not None, row
    scenario = re.match(r"`posekit launch ([a-z_]+)`", posekit)
    assert scenario is not None, row
    assert scenario.group(1) in scenario_names(), row
    resolved = resolve_launch([words.group(1), words.group(2)])  # the lecture's own command
    assert resolved in scenario_names(), row
    if words.group(1) == "rosbot_gazebo":  # a world: the same scenario either way
        assert resolved == scenario.group(1), row
    # a demo: the lecture's command runs its nodes against a world started elsewhere
    # (PACKAGE/NAME); the table may name a scenario that also includes the world
