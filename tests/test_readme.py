"""The README's Python examples run as written and show what they claim."""

import re
from pathlib import Path
from typing import Any

import numpy as np

README = Path(__file__).resolve().parents[1] / "README.md"


def _python_blocks() -> list[str]:
    return re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), re.S)


def test_readme_has_python_examples() -> None:
    assert len(_python_blocks()) >= 3


def test_readme_examples_run() -> None:
    namespace: dict[str, Any] = {}
    for block in _python_blocks():
        exec(compile(block, str(README), "exec"), namespace)
    q = namespace["q"]
    np.testing.assert_allclose(q.as_quat(scalar_first=True),
                               [np.sqrt(0.5), np.sqrt(0.5), 0.0, 0.0], atol=1e-15)
    T_odom_cam = namespace["T_odom_cam"]
    # T_odom_base (yaw 1.57 about z, at (1, 2, 0)) applied to the camera offset (0.1, 0, 0.3)
    expected = [1.0 + 0.1 * np.cos(1.57), 2.0 + 0.1 * np.sin(1.57), 0.3]
    np.testing.assert_allclose(T_odom_cam.translation, expected, atol=1e-12)
    translations = namespace["translations"]
    assert np.shape(translations) == (1000, 3)
