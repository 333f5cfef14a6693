"""TimeCache: the time-ordered samples of one dynamic child frame (tf2 ``cache.cpp``).

Stamps are integer nanoseconds. Storage is ascending by (stamp, insertion order), i.e. tf2's
newest-first list read backwards, so every tf2 rule maps onto list positions exactly:
a duplicate stamp is inserted after the equal-stamp run (tf2: in front of it), the newest
sample is ``[-1]`` and the oldest ``[0]``. Each sample is a parent id and a 7-tuple
``(qx, qy, qz, qw, tx, ty, tz)`` meaning parent_T_child.
"""

from __future__ import annotations

import math
from bisect import bisect_left, bisect_right
from typing import Any

from posekit.tf2.exceptions import (
    BackwardExtrapolationException,
    ForwardExtrapolationException,
    NoDataForExtrapolationException,
)

__all__ = [
    "DEFAULT_CACHE_TIME_NS",
    "EMPTY_CACHE_MESSAGE",
    "Sample",
    "TimeCache",
    "display_time",
    "slerp_terms",
]

#: tf2's ``BUFFER_CORE_DEFAULT_CACHE_TIME`` / ``TIMECACHE_DEFAULT_MAX_STORAGE_TIME``: 10 s.
DEFAULT_CACHE_TIME_NS = 10_000_000_000

Sample = tuple[float, float, float, float, float, float, float]

_sqrt = math.sqrt
_acos = math.acos
_sin = math.sin

# Deferred drops are carried out once this many samples are below the window.
_PRUNE_BATCH = 64

#: ROS 2 Jazzy reports an empty cache with an empty message (rolling added a text later).
EMPTY_CACHE_MESSAGE = ""


def display_time(ns: int) -> str:
    """tf2 ``displayTimePoint``: ``%.6f`` seconds, whole and fractional parts scaled apart."""
    nsec = int(ns % 1_000_000_000) if ns >= 0 else -((-ns) % 1_000_000_000)
    sec = (ns - nsec) // 1_000_000_000
    return f"{float(sec) + 1e-9 * float(nsec):.6f}"


def _no_data(t: int, stamp: int) -> NoDataForExtrapolationException:
    return NoDataForExtrapolationException(
        f"Lookup would require extrapolation at time {display_time(t)}, "
        f"but only time {display_time(stamp)} is in the buffer"
    )


def _forward(t: int, newest: int) -> ForwardExtrapolationException:
    return ForwardExtrapolationException(
        f"Lookup would require extrapolation into the future.  Requested time {display_time(t)} "
        f"but the latest data is at time {display_time(newest)}"
    )


def _backward(t: int, oldest: int) -> BackwardExtrapolationException:
    return BackwardExtrapolationException(
        f"Lookup would require extrapolation into the past.  Requested time {display_time(t)} "
        f"but the earliest data is at time {display_time(oldest)}"
    )


def slerp_terms(
    x1: float, y1: float, z1: float, w1: float, x2: float, y2: float, z2: float, w2: float
) -> tuple[float, float, bool]:
    """tf2 slerp's terms that depend only on the two samples: (angle, 1/sin(angle) or 0 when
    the angle is 0, whether the second quaternion is negated for the shortest path)."""
    dot = x1 * x2 + y1 * y2 + z1 * z2 + w1 * w2
    c = (-dot if dot < 0.0 else dot) / _sqrt(
        (x1 * x1 + y1 * y1 + z1 * z1 + w1 * w1) * (x2 * x2 + y2 * y2 + z2 * z2 + w2 * w2)
    )
    theta = _acos(-1.0 if c < -1.0 else (1.0 if c > 1.0 else c))
    return theta, 1.0 / _sin(theta) if theta != 0.0 else 0.0, dot < 0.0


class TimeCache:
    """Samples of one dynamic frame within ``cache_time_ns`` of its newest stamp."""

    __slots__ = ("_arrays", "_iv", "_pending", "_prune_limit", "cache_time_ns", "data", "parents",
                 "stamps")

    is_static = False

    def __init__(
        self, cache_time_ns: int = DEFAULT_CACHE_TIME_NS, pending: set[TimeCache] | None = None
    ) -> None:
        self.cache_time_ns = int(cache_time_ns)
        # tf2 drops the samples older than the window on every insert. Dropping the front of
        # four lists moves every element, so with ``pending`` (the owner's set of caches with
        # a deferred drop) the drop is done in batches: samples below ``_prune_limit`` are
        # already gone for tf2 but still in the lists until :meth:`prune`, which every reader
        # of the lists runs first (this class's methods do; the owner before reading the
        # lists directly).
        self._prune_limit: int | None = None
        self._pending = pending
        self.stamps: list[int] = []
        self.parents: list[int] = []
        self.data: list[Sample] = []
        # _iv[i]: memo of tf2 slerp's angle terms for the interval (i, i+1), or None. They
        # depend only on the two samples, so repeated lookups between the same samples
        # skip the dot product, norms, acos and one sin.
        self._iv: list[tuple[float, float, bool] | None] = []
        self._arrays: Any = None

    # -- insertion ---------------------------------------------------------------------------
    def insert(self, stamp: int, parent: int, sample: Sample) -> bool:
        """tf2 ``insertData``: prune against the current newest, refuse too-old data, keep order.

        Returns False only for data older than ``newest - cache_time`` (TF_OLD_DATA). An exact
        duplicate (same stamp, parent and values) is accepted without being stored twice.
        """
        stamps = self.stamps
        if stamps:
            latest = stamps[-1]
            limit = latest - self.cache_time_ns
            if stamps[0] < limit:  # drop strictly older than the window, before inserting
                pending = self._pending
                if pending is None:
                    self._prune_limit = limit
                    self.prune()
                else:
                    self._prune_limit = limit
                    pending.add(self)
                    if len(stamps) > _PRUNE_BATCH and stamps[_PRUNE_BATCH] < limit:
                        self.prune()
            if stamp < limit:
                return False
            if stamp > latest:
                stamps.append(stamp)
                self.parents.append(parent)
                self.data.append(sample)
                self._iv.append(None)
                self._arrays = None
                return True
            lo = bisect_left(stamps, stamp)
            hi = bisect_right(stamps, stamp)
            for i in range(lo, hi):
                if self.parents[i] == parent and self.data[i] == sample:
                    return True
            stamps.insert(hi, stamp)
            self.parents.insert(hi, parent)
            self.data.insert(hi, sample)
            self._iv.insert(hi, None)
            if hi:
                self._iv[hi - 1] = None
        else:
            stamps.append(stamp)
            self.parents.append(parent)
            self.data.append(sample)
            self._iv.append(None)
        self._arrays = None
        return True

    def prune(self) -> None:
        """Carry out the deferred drop of the samples older than the window (see __init__)."""
        limit = self._prune_limit
        if limit is None:
            return
        self._prune_limit = None
        k = bisect_left(self.stamps, limit)
        if k:
            del self.stamps[:k]
            del self.parents[:k]
            del self.data[:k]
            del self._iv[:k]
            self._arrays = None

    def clear(self) -> None:
        """Drop every sample (tf2 ``clearList``)."""
        self._prune_limit = None
        self.stamps.clear()
        self.parents.clear()
        self.data.clear()
        self._iv.clear()
        self._arrays = None

    # -- lookup ------------------------------------------------------------------------------
    def get(self, t: int) -> tuple[int, Sample]:
        """The edge (parent id, parent_T_child) at time ``t`` ns (0 = newest); tf2 ``getData``.

        Raises an :class:`ExtrapolationException` subclass with tf2's text (without the
        ``, when looking up ...`` suffix, which the walk adds).
        """
        if self._prune_limit is not None:
            self.prune()
        stamps = self.stamps
        if stamps and stamps[0] < t < stamps[-1]:  # the common case: strictly inside
            pass
        else:
            n = len(stamps)
            if n == 0:
                raise NoDataForExtrapolationException(EMPTY_CACHE_MESSAGE)
            if t == 0:
                return self.parents[-1], self.data[-1]
            if n == 1:
                if stamps[0] == t:
                    return self.parents[0], self.data[0]
                raise _no_data(t, stamps[0])
            newest = stamps[-1]
            if t == newest:
                return self.parents[-1], self.data[-1]
            oldest = stamps[0]
            if t == oldest:
                return self.parents[0], self.data[0]
            if t > newest:
                raise _forward(t, newest)
            raise _backward(t, oldest)
        i = bisect_right(stamps, t) - 1  # older: the last inserted sample with stamp <= t
        parent = self.parents[i]
        a = self.data[i]
        if self.parents[i + 1] != parent:  # re-parented in between: no interpolation
            return parent, a
        b = self.data[i + 1]
        s0 = stamps[i]
        # int / int is correctly rounded, i.e. equal to double(dt) / double(span) for spans
        # below 2**53 ns (104 days), which is what tf2 computes
        r = (t - s0) / (stamps[i + 1] - s0)
        u = 1.0 - r
        # posekit.tf2.path.interpolate (tf2 slerp + lerp) inlined, with the per-interval slerp
        # terms memoised; tests/tf2/test_kernels.py checks it bit for bit against the reference
        x1, y1, z1, w1, ax, ay, az = a
        x2, y2, z2, w2, bx, by, bz = b
        iv = self._iv[i]
        if iv is None:
            iv = self._iv[i] = slerp_terms(x1, y1, z1, w1, x2, y2, z2, w2)
        theta, d, flip = iv
        if theta == 0.0:
            return parent, (x1, y1, z1, w1, u * ax + r * bx, u * ay + r * by, u * az + r * bz)
        s0f = _sin(u * theta)
        s1f = -_sin(r * theta) if flip else _sin(r * theta)
        return parent, (
            (x1 * s0f + x2 * s1f) * d,
            (y1 * s0f + y2 * s1f) * d,
            (z1 * s0f + z2 * s1f) * d,
            (w1 * s0f + w2 * s1f) * d,
            u * ax + r * bx,
            u * ay + r * by,
            u * az + r * bz,
        )

    def get_parent(self, t: int) -> int:
        """Parent id of the edge used at ``t`` (raises like :meth:`get`); tf2 ``getParent``."""
        return self.get(t)[0]

    # -- introspection -----------------------------------------------------------------------
    def latest_stamp(self) -> int:
        """Newest stamp in ns, 0 if empty."""
        return self.stamps[-1] if self.stamps else 0

    def oldest_stamp(self) -> int:
        """Oldest stamp in ns, 0 if empty."""
        self.prune()
        return self.stamps[0] if self.stamps else 0

    def __len__(self) -> int:
        self.prune()
        return len(self.stamps)

    def latest_time_and_parent(self) -> tuple[int, int]:
        """(newest stamp, its parent id), or (0, 0) if empty."""
        if not self.stamps:
            return 0, 0
        return self.stamps[-1], self.parents[-1]

    def arrays(self) -> Any:
        """Cached numpy copies: stamps, parents, samples (7, n), and per-interval slerp terms."""
        self.prune()
        arrs = self._arrays
        if arrs is None:
            import numpy as np

            data = np.ascontiguousarray(np.array(self.data, dtype=np.float64).reshape(-1, 7).T)
            # tf2 slerp's angle terms per interval (i, i+1), as in get(); last entry padding
            a, b = data[:4, :-1], data[:4, 1:]
            dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
            n1 = a[0] * a[0] + a[1] * a[1] + a[2] * a[2] + a[3] * a[3]
            n2 = b[0] * b[0] + b[1] * b[1] + b[2] * b[2] + b[3] * b[3]
            theta = np.zeros(len(self.stamps))
            theta[:-1] = np.arccos(np.minimum(np.abs(dot) / np.sqrt(n1 * n2), 1.0))
            with np.errstate(divide="ignore"):
                inv_sin = 1.0 / np.sin(theta)
            flip = np.zeros(len(self.stamps), dtype=bool)
            flip[:-1] = dot < 0.0
            arrs = (
                np.array(self.stamps, dtype=np.int64),
                np.array(self.parents, dtype=np.int64),
                data,  # (7, n): one row per component
                theta,
                inv_sin,
                flip,
            )
            self._arrays = arrs
        return arrs
