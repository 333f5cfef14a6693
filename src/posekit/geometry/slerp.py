"""Spherical linear interpolation through a sequence of key rotations (scipy's ``Slerp``).

Between keys ``i`` and ``i + 1`` at times ``t_i < t_{i+1}`` the rotation at ``t`` is
``r_i * (r_i.inv() * r_{i+1}) ** alpha`` with ``alpha = (t - t_i) / (t_{i+1} - t_i)``: the
shortest arc at constant angular speed. A time equal to a key's gives that key.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from posekit.geometry._lazy import lazy_module
from posekit.geometry.errors import ShapeError
from posekit.geometry.rotation import Rotation

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt
else:
    np = lazy_module("numpy")

__all__ = ["Slerp"]


class Slerp:
    """``Slerp(times, rotations)(t)``: the rotation(s) at time(s) ``t``, as scipy.

    Args:
        times: ``(N,)`` strictly increasing key times (any unit), N >= 2.
        rotations: a batch of N key rotations.

    Raises:
        ShapeError: not a batch of N >= 2 rotations, or times of another length.
        ValueError: times not strictly increasing or not finite.
    """

    def __init__(self, times: npt.ArrayLike, rotations: Rotation) -> None:
        if rotations.single or len(rotations) < 2:
            raise ShapeError("`rotations` must be a sequence of at least 2 rotations")
        t = np.asarray(times, dtype=np.float64)
        if t.ndim != 1 or len(t) != len(rotations):
            raise ShapeError(f"{t.size} times for {len(rotations)} rotations")
        if not np.isfinite(t).all():
            raise ValueError("times must be finite")
        if (np.diff(t) <= 0.0).any():
            raise ValueError("times must be in strictly increasing order")
        self.times = t
        self.rotations = rotations
        #: rotation vector from each key to the next
        self._steps = (rotations[:-1].inv() * rotations[1:]).as_rotvec()

    def __call__(self, times: npt.ArrayLike) -> Rotation:
        """The rotation at each of ``times`` (a scalar gives a single rotation).

        Raises:
            ValueError: a time outside ``[times[0], times[-1]]``.
        """
        t = np.asarray(times, dtype=np.float64)
        flat = t.reshape(-1)
        first, last = self.times[0], self.times[-1]
        if not ((flat >= first) & (flat <= last)).all():
            raise ValueError(
                f"interpolation times must be within [{first}, {last}], both inclusive")
        index = np.clip(np.searchsorted(self.times, flat, side="right") - 1, 0,
                        len(self.times) - 2)
        alpha = (flat - self.times[index]) / (self.times[index + 1] - self.times[index])
        keys = self.rotations[index]
        result = keys * Rotation.from_rotvec(alpha[:, None] * self._steps[index])
        return result[0] if t.ndim == 0 else result
