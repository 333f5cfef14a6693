"""The runnable examples in the docstrings of the public geometry and tf2 API.

Each module below is run through :mod:`doctest`; a module must keep at least the examples it
has (so they cannot vanish silently) and every one must print what its docstring says.
Oracle: the expected values in the docstrings, each derived there in closed form (half-angle
quaternions, also through tf2's setRPY / getRPY, the Hamilton product,
``t_a_c = t_a_b + R_a_b t_b_c``, linear interpolation and slerp), not produced by running
posekit.
"""

from __future__ import annotations

import doctest
import importlib

import pytest

#: module -> the least number of examples (``>>>`` lines) it holds.
MODULES = {
    "posekit.geometry.rotation": 14,
    "posekit.geometry.transform": 7,
    "posekit.geometry.scalar": 13,
    "posekit.tf2.buffer": 17,
    "posekit.tf2._linear_math": 3,
}


@pytest.mark.parametrize("name", sorted(MODULES))
def test_docstring_examples_run(name: str) -> None:
    module = importlib.import_module(name)
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    report: list[str] = []
    for test in finder.find(module, name):
        runner.run(test, out=report.append)
    results = runner.summarize(verbose=False)
    assert results.attempted >= MODULES[name], f"{name}: only {results.attempted} examples"
    assert results.failed == 0, "".join(report)
