"""Every tf2 test runs once per lookup policy: pure Python, and the compiled kernels where
they were built (``posekit.tf2._accel``), so both are held to the same oracles."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from posekit.tf2 import buffer_core, path

POLICIES = ["python", "compiled"] if path.accelerated else ["python"]


@pytest.fixture(scope="module", autouse=True, params=POLICIES)
def lookup_policy(request: pytest.FixtureRequest) -> Iterator[str]:
    """The policy BufferCore uses during the module: ``python`` swaps in the pure-Python
    evaluate / stamped / sample_from_msg, ``compiled`` keeps the selected ones."""
    with pytest.MonkeyPatch.context() as mp:
        if request.param == "python":
            mp.setattr(buffer_core, "evaluate", path.evaluate_python)
            mp.setattr(buffer_core, "stamped", path.stamped_python)
            mp.setattr(buffer_core, "sample_from_msg", path._no_sample)
        yield request.param
