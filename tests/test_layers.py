"""The layer contract: which posekit package may import which.

Oracle: the table below, which is the architecture the README and docs/architecture describe
(msgs at the bottom; geometry, tf2 and the worlds on numpy alone; runtime and transports
above; robot, vision and launch above them; demos, cli, viewer and bag on top). Every
``import`` in the source, including function-level (lazy) ones, is read with :mod:`ast`; a
package may import only packages of a strictly lower layer. A new package fails this test
until it is given a layer here, so the contract is decided, not drifted into. A second test
checks that the core imports with numpy alone, in a fresh interpreter.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "posekit"

# Layer of each top-level module or package of posekit (lower = more basic).
LAYERS: dict[str, int] = {
    "__init__": 0,
    "msgs": 0,
    "time": 1,
    "geometry": 1,
    "cv_bridge": 1,  # msgs <-> OpenCV arrays (OpenCV loaded only to convert colours)
    "tf2": 2,
    "kdl": 2,
    "worlds": 2,  # the scenes (world files, the ArUco box model): numpy and geometry alone
    "runtime": 3,
    "transport": 4,
    "rclpy": 4,
    "tf2_ros": 4,
    "launch": 4,
    "robot": 5,
    "vision": 6,
    "bag": 7,
    "demos": 7,
    "viewer": 7,
    "cli": 8,
}


def _package_of(path: Path) -> str:
    rel = path.relative_to(SRC)
    return rel.parts[0].removesuffix(".py") if len(rel.parts) > 1 else rel.stem


def _imported_packages(path: Path) -> set[tuple[str, int]]:
    found: set[tuple[str, int]] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        names: list[str] = []
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names = [node.module]
        elif isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        for name in names:
            parts = name.split(".")
            if parts[0] == "posekit" and len(parts) > 1:
                found.add((parts[1], node.lineno))
    return found


def test_every_package_has_a_layer() -> None:
    packages = {_package_of(p) for p in SRC.rglob("*.py")}
    missing = sorted(packages - set(LAYERS))
    assert not missing, f"give these packages a layer in tests/test_layers.py: {missing}"


def test_imports_point_down_the_layers() -> None:
    violations = []
    for path in sorted(SRC.rglob("*.py")):
        mine = _package_of(path)
        for target, line in sorted(_imported_packages(path)):
            if target == mine:
                continue
            if LAYERS.get(target, 99) >= LAYERS.get(mine, -1):
                violations.append(f"{path.relative_to(SRC.parent)}:{line} ({mine}, layer "
                                  f"{LAYERS.get(mine)}) imports {target} (layer "
                                  f"{LAYERS.get(target)})")
    assert not violations, "imports against the layer contract:\n" + "\n".join(violations)


@pytest.mark.parametrize("module", ["posekit.geometry", "posekit.msgs", "posekit.tf2",
                                    "posekit.worlds"])
def test_core_imports_with_numpy_alone(module: str) -> None:
    heavy = ["rosbags", "cv2", "zenoh", "cyclonedds", "aiohttp", "matplotlib", "scipy",
             "posekit.runtime", "posekit.transport"]
    code = (f"import sys, {module}\n"
            f"print(sorted(m for m in {heavy!r} if m in sys.modules))")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            timeout=60, check=True)
    assert result.stdout.strip() == "[]", result.stdout
