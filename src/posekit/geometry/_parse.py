"""Input parsing shared by the geometry classes: one item -> float tuple, many -> (N, k) array."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from posekit.geometry._lazy import lazy_module

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    F64 = npt.NDArray[np.float64]
else:
    np = lazy_module("numpy")

from posekit.geometry.errors import NonFiniteError, ShapeError

__all__ = ["check_finite", "check_finite_array", "parse_rows", "parse_scalar_or_array"]



def parse_rows(obj: Any, width: int, what: str) -> tuple[float, ...] | F64:
    """Return a ``width``-tuple of floats for one item or a C-contiguous ``(N, width)`` array.

    Plain tuples/lists of numbers take a numpy-free path (the single-item fast path).
    """
    items: Any = obj
    try:  # one item: exactly ``width`` numbers (list, tuple or 1-D array), no numpy needed
        if width == 3:
            a, b, c = items
            return (float(a), float(b), float(c))
        if width == 4:
            a, b, c, d = items
            return (float(a), float(b), float(c), float(d))
        if width == 2:
            a, b = items
            return (float(a), float(b))
    except (TypeError, ValueError):
        pass  # not ``width`` scalars: a batch (or an error), handled below
    arr = np.asarray(obj, dtype=np.float64)
    if arr.shape == (width,):
        return tuple(arr.tolist())
    if arr.ndim == 2 and arr.shape[1] == width:
        return np.ascontiguousarray(arr)
    raise ShapeError(
        f"{what} must have shape ({width},) or (N, {width}), got shape {arr.shape}"
    )


def parse_scalar_or_array(obj: Any, what: str) -> float | F64:
    """A float for a scalar, a 1-D float array for a sequence of values."""
    if isinstance(obj, (int, float)):
        return float(obj)
    arr = np.asarray(obj, dtype=np.float64)
    if arr.ndim == 0:
        return float(arr)
    if arr.ndim == 1:
        return arr
    raise ShapeError(f"{what} must be a scalar or a 1-D sequence, got shape {arr.shape}")


def check_finite(values: tuple[float, ...], what: str) -> None:
    """Raise :class:`NonFiniteError` if any value is NaN or infinite."""
    for v in values:
        if not math.isfinite(v):
            raise NonFiniteError(f"{what} contains NaN or infinity: {values!r}")


def check_finite_array(arr: F64, what: str) -> None:
    """Raise :class:`NonFiniteError` naming the first non-finite row."""
    ok = np.isfinite(arr)
    if not ok.all():
        bad = np.flatnonzero(~ok.reshape(len(arr), -1).all(axis=1))
        idx = int(bad[0])
        raise NonFiniteError(
            f"{what} contains NaN or infinity in {bad.size} row(s); first at index {idx}: "
            f"{arr[idx].tolist()}"
        )
