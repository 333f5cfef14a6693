"""The compiled batch quaternion -> matrix kernel (``posekit.geometry._accel``) gives the same
bits as the numpy kernel.

Oracle: ``posekit.geometry._batch.to_matrix_numpy`` (itself checked against scipy in the
rotation tests), on the same random arrays: unit and non-unit rows, signed zeros, NaN and
infinities, sizes around the numpy kernel's block size. Compared as raw bytes, so every bit
of every float (and NaN payloads) must agree. Skipped, saying so, where the extension was not
built (no C compiler at install time); ``to_matrix`` then is the numpy kernel.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from posekit.geometry import Rotation
from posekit.geometry import _batch as vk

accel = pytest.importorskip(
    "posekit.geometry._accel",
    reason="posekit.geometry._accel was not built (no C compiler at install)",
)

_rows = hnp.arrays(
    np.float64,
    st.tuples(st.integers(0, 40), st.just(4)),
    elements=st.floats(allow_nan=True, allow_infinity=True) | st.sampled_from([0.0, -0.0, 1.0]),
)


@given(_rows)
def test_compiled_equals_numpy_bit_for_bit(q: np.ndarray) -> None:
    got = vk.to_matrix(q)
    with np.errstate(all="ignore"):  # inf and NaN rows: numpy warns, C stays quiet
        want = vk.to_matrix_numpy(q)
    assert got.shape == want.shape == (len(q), 3, 3)
    assert got.tobytes() == want.tobytes()


@pytest.mark.parametrize("n", [1, 4095, 4096, 4097, 20_000])
def test_compiled_equals_numpy_across_blocks(n: int) -> None:
    q = vk.normalize(np.random.default_rng(n).normal(size=(n, 4)))
    assert vk.to_matrix(q).tobytes() == vk.to_matrix_numpy(q).tobytes()


def test_public_api_uses_it_and_non_contiguous_input_falls_back() -> None:
    assert vk._accel is accel
    q = np.random.default_rng(1).normal(size=(50, 8))[:, ::2]  # strided: numpy kernel
    r = Rotation.from_quat(q)
    assert r.as_matrix().tobytes() == vk.to_matrix_numpy(r._qs).tobytes()
    assert vk.to_matrix(q).tobytes() == vk.to_matrix_numpy(q).tobytes()


def test_bad_buffers_are_refused() -> None:
    with pytest.raises(TypeError):
        accel.quat_to_matrix(np.zeros((2, 4), dtype=np.float32), np.empty((2, 3, 3)))
    with pytest.raises(ValueError, match=r"\(N, 4\)"):
        accel.quat_to_matrix(np.zeros((2, 4)), np.empty((3, 3, 3)))
