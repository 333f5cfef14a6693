"""StaticCache: the single, time-independent sample of a static frame (tf2 ``static_cache.cpp``)."""

from __future__ import annotations

from typing import Any

from posekit.tf2.time_cache import Sample

__all__ = ["StaticCache"]


class StaticCache:
    """One parent_T_child valid at every time; every insert overwrites it (parent included)."""

    __slots__ = ("_arrays", "parent", "sample")

    is_static = True

    def __init__(self) -> None:
        self.parent = 0
        self.sample: Sample = (0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0)
        self._arrays: Any = None

    def insert(self, stamp: int, parent: int, sample: Sample) -> bool:
        """Overwrite the stored value (stamp ignored). Always accepted."""
        self.parent = parent
        self.sample = sample
        self._arrays = None
        return True

    def clear(self) -> None:
        """Nothing: static transforms survive ``clear()`` (tf2)."""

    def get(self, t: int) -> tuple[int, Sample]:
        """The stored edge, whatever ``t`` is."""
        return self.parent, self.sample

    def get_parent(self, t: int) -> int:
        """The stored parent id."""
        return self.parent

    def latest_stamp(self) -> int:
        """Always 0 for static data."""
        return 0

    def oldest_stamp(self) -> int:
        """Always 0 for static data."""
        return 0

    def __len__(self) -> int:
        return 1

    def latest_time_and_parent(self) -> tuple[int, int]:
        """(0, parent id)."""
        return 0, self.parent
