"""BufferCore: tf2's transform tree with ROS 2 semantics (``tf2/src/buffer_core.cpp``).

Frames get small integer ids in the order they are first seen (child before parent, id 0 is
``NO_PARENT``); each child frame owns one cache (:class:`TimeCache` or :class:`StaticCache`)
of parent_T_child samples. Times are integer nanoseconds; 0 means "latest common time".

A lookup ``lookup_transform_core(target, source, t)`` returns T_target_source: it maps
coordinates expressed in ``source`` into ``target``, and its translation is the origin of
``source`` expressed in ``target``. Quaternions are (x, y, z, w) everywhere.

The method names follow tf2_py's ``BufferCore`` so code written for ROS 2 runs unchanged;
:class:`posekit.tf2.Buffer` adds tf2_ros's waiting API on top.

:meth:`BufferCore._walk` is tf2's walk written to be read, and the reference for every
result and error. Lookups between two known frames go through a cached path
(:mod:`posekit.tf2.path`): its evaluation policies answer the common case and hand
everything else back to the reference walk.
"""

from __future__ import annotations

import logging
import math
import numbers
import threading
from collections.abc import Iterable
from typing import Any

from posekit.msgs.builtin_interfaces import Time as TimeMsg
from posekit.msgs.geometry_msgs import TransformStamped
from posekit.tf2 import introspection
from posekit.tf2._linear_math import matrix_from_quat, quat_from_matrix
from posekit.tf2.exceptions import (
    ConnectivityException,
    ExtrapolationException,
    InvalidArgumentException,
    LookupException,
    TransformException,
)
from posekit.tf2.path import (
    UP,
    FramePath,
    accumulate,
    build_path,
    canonical,
    evaluate,
    inverse_compose,
    latest_up,
    result_python,
    sample_from_msg,
    stamped,
)
from posekit.tf2.static_cache import StaticCache
from posekit.tf2.time_cache import DEFAULT_CACHE_TIME_NS, Sample, TimeCache, display_time
from posekit.time import Duration, Time

__all__ = ["MAX_GRAPH_DEPTH", "BufferCore", "time_to_ns"]

#: tf2's walk limit; a longer walk is reported as a loop.
MAX_GRAPH_DEPTH = 1000

_logger = logging.getLogger("posekit.tf2")
_NS = 1_000_000_000
_INF = math.inf

Cache = TimeCache | StaticCache
# The walk's identity result (raw results are (qx, qy, qz, qw, tx, ty, tz), before tf2's
# matrix round trip).
_IDENTITY: Sample = (0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0)


_INT32 = 1 << 31
_UINT32 = 1 << 32


def _check_stamp(sec: Any, nanosec: Any, child: Any) -> tuple[int, int]:
    """``(sec, nanosec)`` as ints; raises for a stamp that is no builtin_interfaces/Time.

    The Time fields are int32 sec and uint32 nanosec; rclpy refuses other values when they are
    assigned to the message. numpy integers are accepted.
    """
    where = f"transform for child_frame_id {child!r}: header.stamp"
    out = []
    for field_name, value, low, high in (("sec", sec, -_INT32, _INT32),
                                         ("nanosec", nanosec, 0, _UINT32)):
        if isinstance(value, bool) or not isinstance(value, numbers.Integral):
            raise TypeError(f"{where}.{field_name} must be an int, got {value!r}")
        if not low <= int(value) < high:
            raise ValueError(
                f"{where}.{field_name} must be in [{low}, {high - 1}], got {value}"
            )
        out.append(int(value))
    return out[0], out[1]


def time_to_ns(time: Any) -> int:
    """Integer nanoseconds of a stamp, with no float rounding.

    Accepts :class:`posekit.time.Time` (or rclpy's, anything with ``.nanoseconds``), a
    ``builtin_interfaces/Time`` (anything with ``.sec`` and ``.nanosec``), or a plain int
    (nanoseconds). ``0`` / ``Time()`` means "latest".
    """
    if type(time) is Time:
        return time.nanoseconds
    ns = getattr(time, "nanoseconds", None)
    if ns is not None:
        return int(ns)
    if isinstance(time, int) and not isinstance(time, bool):
        return time
    sec = getattr(time, "sec", None)
    if sec is not None:
        return int(sec) * _NS + int(time.nanosec)
    raise TypeError(
        f"expected a Time, builtin_interfaces/Time or int nanoseconds, got {type(time).__name__}"
    )


def _duration_ns(duration: Any) -> int:
    """Nanoseconds of a Duration, a ``builtin_interfaces/Duration``, an int (ns) or None (0).

    A float (seconds) is refused with a TypeError that says what to pass: tf2_ros in ROS 2
    takes ``rclpy.duration.Duration`` only (and fails obscurely on a float).
    """
    if duration is None:
        return 0
    ns = getattr(duration, "nanoseconds", None)
    if ns is not None:
        return int(ns)
    if isinstance(duration, int):
        return duration
    if hasattr(duration, "sec") and hasattr(duration, "nanosec"):
        return int(duration.sec) * _NS + int(duration.nanosec)
    raise TypeError(
        f"expected an rclpy Duration, e.g. Duration(seconds={duration!r}), got "
        f"{type(duration).__name__} {duration!r} (tf2_ros takes no float seconds)"
    )


def _make_stamped(target: str, source: str, stamp_ns: int, raw: Sample) -> TransformStamped:
    """The result message of a raw walk result.

    Its quaternion goes through tf2's matrix round trip; the stamp is split as
    builtin_interfaces/Time.
    """
    return stamped(target, source, result_python(stamp_ns, raw))


class LockedView:
    """The part of a :class:`BufferCore` that a lookup policy outside this module may use.

    The policy holds the core's lock meanwhile (``posekit.tf2.batch`` does): validated frame
    ids, each frame's cache, tf2's latest common time, and the reference single lookup.
    """

    __slots__ = ("_core",)

    #: tf2's walk limit; a longer walk is a loop.
    max_depth = MAX_GRAPH_DEPTH

    def __init__(self, core: BufferCore) -> None:
        self._core = core

    def frame_id(self, name: str, arg: str) -> int:
        """The id of a frame lookups may name, else tf2's exception naming ``arg``."""
        return self._core._validate(name, arg)

    def cache(self, frame_id: int) -> TimeCache | StaticCache | None:
        """The frame's cache of parent_T_frame samples (None: no data, e.g. a root)."""
        return self._core._caches[frame_id]

    def latest_common_time(self, target_id: int, source_id: int) -> int:
        """tf2 ``getLatestCommonTime`` in ns; raises tf2's exceptions."""
        return self._core._latest_common_time(target_id, source_id)

    def lookup_raw(self, target: str, source: str, t: int) -> tuple[Sample, int]:
        """The reference lookup: raw (qx, qy, qz, qw, tx, ty, tz) and the time used.

        Raw means before the matrix round trip; raises tf2's exceptions.
        """
        return self._core._lookup_raw(target, source, t)


class BufferCore:
    """tf2's frame graph and caches (thread-safe; every public method takes the lock).

    Args:
        cache_time: how long dynamic samples are kept, as a :class:`posekit.time.Duration`
            (or anything with ``.nanoseconds``, or int ns). ``None`` means tf2's 10 s.
    """

    def __init__(self, cache_time: Duration | Any | None = None) -> None:
        ns = _duration_ns(cache_time)
        self._cache_time_ns = ns if cache_time is not None else DEFAULT_CACHE_TIME_NS
        # Re-entrant so the Buffer's Condition can share it while calling core methods.
        self._lock = threading.RLock()
        self._names: list[str] = ["NO_PARENT"]
        self._ids: dict[str, int] = {"NO_PARENT": 0}
        self._caches: list[Cache | None] = [None]
        self._authority: dict[int, str] = {}
        # cached paths per (target, source) name pair; emptied whenever a cache is created,
        # replaced or forgotten (the tree's structure may then change)
        self._paths: dict[tuple[str, str], FramePath] = {}
        # dynamic caches with a deferred drop of samples older than their window (see
        # TimeCache): pruned before the lists are read directly (path evaluation, forget)
        self._unpruned: set[TimeCache] = set()
        # bumped by every change of the stored data (insert attempts, clear, forget_frames):
        # a path's memoised result is valid while the version it was computed at is current
        self._version = 0

    @property
    def cache_time(self) -> Duration:
        """How long dynamic samples are kept."""
        return Duration(nanoseconds=self._cache_time_ns)

    # ------------------------------------------------------------------------------------------
    # insertion
    # ------------------------------------------------------------------------------------------
    def set_transform(self, transform: Any, authority: str) -> bool:
        """Insert a dynamic ``TransformStamped``; True if stored, False if tf2 rejects it.

        The parent is ``header.frame_id``, the child ``child_frame_id``. A rejection's reason is
        logged on logger ``posekit.tf2`` with tf2's text. A stamp that is no
        builtin_interfaces/Time (``sec`` not an int32, ``nanosec`` not a uint32, e.g. 1.5 or
        2**70) raises TypeError or ValueError naming the field, as rclpy refuses it on the
        message.
        """
        return self._set(transform, authority, False)

    def set_transform_static(self, transform: Any, authority: str) -> bool:
        """Insert a static transform (valid at every time, survives :meth:`clear`)."""
        return self._set(transform, authority, True)

    def _set(self, msg: Any, authority: str, is_static: bool) -> bool:
        got = sample_from_msg(msg)  # compiled: the common valid message, or None
        if got is None:
            got = self._checked_sample(msg, authority)
            if got is None:
                return False
        stamp_ns, parent, child, sample = got
        with self._lock:
            self._version += 1
            ids = self._ids
            caches = self._caches
            cid = ids.get(child)
            if cid is None:
                cid = self._add_frame(child)
            cache = caches[cid]
            if cache is None or cache.is_static is not is_static:
                cache = (StaticCache() if is_static
                         else TimeCache(self._cache_time_ns, self._unpruned))
                caches[cid] = cache
                self._paths.clear()
            pid = ids.get(parent)
            if pid is None:
                pid = self._add_frame(parent)
            if not cache.insert(stamp_ns, pid, sample):
                _logger.warning(
                    "TF_OLD_DATA ignoring data from the past for frame %s at time %s according "
                    "to authority %s\nPossible reasons are listed at "
                    "http://wiki.ros.org/tf/Errors%%20explained",
                    child,
                    display_time(stamp_ns),
                    authority,
                )
                return False
            self._authority[cid] = authority
            self._on_new_data_locked()
        self._on_new_data()
        return True

    def _checked_sample(self, msg: Any, authority: str) -> tuple[int, str, str, Sample] | None:
        """(stamp ns, parent, child, stored sample) of a message, or None if tf2 rejects it.

        The reason is logged with tf2's text; raises for a stamp that is no
        builtin_interfaces/Time.

        The reference conversion: the compiled ``sample_from_msg`` gives the same values for
        the messages it accepts (exact floats and ints, names without a leading '/').
        """
        tr = msg.transform
        t = tr.translation
        r = tr.rotation
        tx = t.x
        ty = t.y
        tz = t.z
        # tf2 builds a Matrix3x3 from the quaternion (s = 2/|q|^2) and reads it back with
        # getRotation: the stored quaternion is unit-norm with a canonical sign.
        x = r.x
        y = r.y
        z = r.z
        w = r.w
        _float = float
        if not (type(tx) is _float and type(ty) is _float and type(tz) is _float
                and type(x) is _float and type(y) is _float and type(z) is _float
                and type(w) is _float):  # ints, numpy scalars, ...: as float() reads them
            tx, ty, tz = float(tx), float(ty), float(tz)
            x, y, z, w = float(x), float(y), float(z), float(w)
        d = x * x + y * y + z * z + w * w
        if 0.0 < d < _INF:
            qx, qy, qz, qw = canonical((x, y, z, w))
        else:  # zero, infinite, NaN or overflowing |q|^2: tf2's arithmetic decides (mostly NaN)
            qx, qy, qz, qw = quat_from_matrix(matrix_from_quat((x, y, z, w)))
        header = msg.header
        stamp = header.stamp
        if type(stamp) is TimeMsg:
            sec = stamp.sec
            nanosec = stamp.nanosec
            if not (type(sec) is int and -_INT32 <= sec < _INT32 and type(nanosec) is int
                    and 0 <= nanosec < _UINT32):
                sec, nanosec = _check_stamp(sec, nanosec, msg.child_frame_id)
            stamp_ns = sec * _NS + nanosec
        else:
            stamp_ns = time_to_ns(stamp)
        parent = header.frame_id
        child = msg.child_frame_id
        if parent[:1] == "/":
            parent = parent[1:]
        if child[:1] == "/":
            child = child[1:]

        rot_nan = qx != qx or qy != qy or qz != qz or qw != qw
        if (child != parent and child and parent and not rot_nan
                and tx == tx and ty == ty and tz == tz):  # the common case: nothing to reject
            pass
        elif not self._accept(authority, parent, child, tx, ty, tz, qx, qy, qz, qw):
            return None
        return stamp_ns, parent, child, (qx, qy, qz, qw, tx, ty, tz)

    @staticmethod
    def _accept(
        authority: str, parent: str, child: str,
        tx: float, ty: float, tz: float, qx: float, qy: float, qz: float, qw: float,
    ) -> bool:  # fmt: skip
        """tf2's input checks, each failure logged with tf2's text; True if none failed."""
        ok = True
        if child == parent:
            _logger.error(
                'TF_SELF_TRANSFORM: Ignoring transform from authority "%s" with frame_id and  '
                'child_frame_id "%s" because they are the same',
                authority,
                child,
            )
            ok = False
        if not child:
            _logger.error(
                'TF_NO_CHILD_FRAME_ID: Ignoring transform from authority "%s" because '
                "child_frame_id not set ",
                authority,
            )
            ok = False
        if not parent:
            _logger.error(
                'TF_NO_FRAME_ID: Ignoring transform with child_frame_id "%s"  from authority "%s" '
                "because frame_id not set",
                child,
                authority,
            )
            ok = False
        rot_nan = qx != qx or qy != qy or qz != qz or qw != qw
        if rot_nan or tx != tx or ty != ty or tz != tz:
            _logger.error(
                'TF_NAN_INPUT: Ignoring transform for child_frame_id "%s" from authority "%s" '
                "because of a nan value in the transform (%f %f %f) (%f %f %f %f)",
                child,
                authority,
                tx,
                ty,
                tz,
                qx,
                qy,
                qz,
                qw,
            )
            ok = False
        if rot_nan:
            # tf2 tests | |q|^2 - 1 | < 0.01 on the already normalised quaternion, so (ROS 2)
            # only a NaN rotation fails it; it is then logged in addition to TF_NAN_INPUT.
            _logger.error(
                'TF_DENORMALIZED_QUATERNION: Ignoring transform for child_frame_id "%s" from '
                'authority "%s" because of an invalid quaternion in the transform '
                "(%f %f %f %f)",
                child,
                authority,
                qx,
                qy,
                qz,
                qw,
            )
            ok = False
        return ok

    def _prune_pending(self) -> None:
        """Carry out every cache's deferred drop of samples older than its window."""
        for cache in self._unpruned:
            cache.prune()
        self._unpruned.clear()

    def _add_frame(self, name: str) -> int:
        fid = len(self._names)
        self._names.append(name)
        self._ids[name] = fid
        self._caches.append(None)
        return fid

    def _on_new_data_locked(self) -> None:
        """Hook run with the lock held after every accepted insert (Buffer: notify waiters)."""

    def _on_new_data(self) -> None:
        """Hook run without the lock after every accepted insert (Buffer: async callbacks)."""

    def clear(self) -> None:
        """Empty every dynamic cache; static transforms, frame ids and authorities stay."""
        with self._lock:
            self._version += 1
            for cache in self._caches:
                if cache is not None:
                    cache.clear()

    def forget_frames(self, frames: Iterable[str]) -> int:
        """Forget frames entirely (posekit extension); returns how many names were dropped.

        tf2 has no way to drop a frame. Their transforms (dynamic and static) and their
        authority go, and their names unless a frame that stays still has one of them as its
        parent; frames left with no data and no child go too. Waiting lookups are unaffected; a
        forgotten frame is unknown until it is set again.
        """
        with self._lock:
            self._version += 1
            self._prune_pending()
            caches = self._caches
            for name in frames:
                fid = self._ids.get(name[1:] if name[:1] == "/" else name)
                if fid:
                    caches[fid] = None
                    self._authority.pop(fid, None)
            # Frames that stay: those with a cache, and every parent one of them refers to.
            keep = {0}
            for fid, cache in enumerate(caches):
                if cache is None:
                    continue
                keep.add(fid)
                if isinstance(cache, StaticCache):
                    keep.add(cache.parent)
                else:
                    keep.update(cache.parents)
            dropped = len(caches) - len(keep)
            if not dropped:
                return 0
            remap = {old: new for new, old in enumerate(sorted(keep))}
            names = [self._names[old] for old in sorted(keep)]
            new_caches: list[Cache | None] = [caches[old] for old in sorted(keep)]
            for cache in new_caches:
                if cache is None:
                    continue
                if isinstance(cache, StaticCache):
                    cache.parent = remap[cache.parent]
                else:
                    cache.parents[:] = [remap[p] for p in cache.parents]
                cache._arrays = None
            # In place: readers such as tf2.batch hold references to these containers.
            self._names[:] = names
            caches[:] = new_caches
            self._ids.clear()
            self._ids.update((name, fid) for fid, name in enumerate(names))
            authority = {remap[f]: a for f, a in self._authority.items() if f in remap}
            self._authority.clear()
            self._authority.update(authority)
            self._paths.clear()
            return dropped

    # ------------------------------------------------------------------------------------------
    # validation
    # ------------------------------------------------------------------------------------------
    def _validate(self, name: str, arg: str) -> int:
        """Frame id of ``name``, else tf2's InvalidArgument/Lookup exception naming ``arg``."""
        fid = self._ids.get(name)
        if fid and name[0] != "/":  # "//x" inserts as "/x", which lookups must still refuse
            return fid
        if not name:
            raise InvalidArgumentException(
                f'Invalid argument "{name}" passed to {arg} - in tf2 frame_ids cannot be empty'
            )
        if name[0] == "/":
            raise InvalidArgumentException(
                f'Invalid argument "{name}" passed to {arg} - '
                "in tf2 frame_ids cannot start with a '/'"
            )
        raise LookupException(f'"{name}" passed to {arg} does not exist. ')

    def _validate_msg(self, name: str, arg: str) -> tuple[int, str]:
        """Non-raising validation for canTransform: (id or 0, message)."""
        fid = self._ids.get(name)
        if fid and name[0] != "/":
            return fid, ""
        if not name:
            why = "in tf2 frame_ids cannot be empty"
        elif name[0] == "/":
            why = "in tf2 frame_ids cannot start with a '/'"
        else:
            why = "frame does not exist"
        return 0, f'Invalid frame ID "{name}" passed to {arg} - {why}'

    # ------------------------------------------------------------------------------------------
    # the walk
    # ------------------------------------------------------------------------------------------
    def _loop_error(self) -> LookupException:
        return LookupException(
            "The tf tree is invalid because it contains a loop.\n"
            + self._frames_as_string_locked()
            + "\n"
        )

    def _latest_common_time(self, tid: int, sid: int) -> int:
        """tf2 ``getLatestCommonTime`` (lock held).

        The minimum of the newest non-zero stamps below the common ancestor, using each frame's
        current newest sample and parent; 0 when every edge there is static. Two walks up the
        tree, as in tf2: from the source (which ends here if the target is an ancestor of
        it), then from the target (:meth:`_latest_common_time_from_target`).
        """
        caches = self._caches
        if sid == tid:
            cache = caches[sid]
            return cache.latest_stamp() if cache is not None else 0
        source_up: dict[int, int] = {}  # parent -> stamp of the edge into it, in walk order
        earliest = -1  # none seen yet (tf2 starts from TimePoint::max)
        depth = 0
        frame = sid
        while frame != 0:
            cache = caches[frame]
            if cache is None:
                break
            stamp, parent = cache.latest_time_and_parent()
            if parent == 0:
                break
            if stamp != 0 and (earliest < 0 or stamp < earliest):
                earliest = stamp
            if parent == tid:  # the target is an ancestor of the source
                return earliest if earliest >= 0 else 0
            source_up[parent] = stamp
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                raise self._loop_error()
            frame = parent
        return self._latest_common_time_from_target(tid, sid, source_up)

    def _latest_common_time_from_target(
        self, tid: int, sid: int, source_up: dict[int, int]
    ) -> int:
        """The second walk of :meth:`_latest_common_time`: up from the target (lock held).

        ``source_up`` is the first walk's edges (parent -> stamp of the edge into it, in walk
        order). The walk ends at the source (an ancestor of the target: the target's edges
        decide) or where it meets a parent in ``source_up`` (the common parent: the target's
        edges and the source's edges below it decide). Raises tf2's connectivity error when
        it meets neither, its loop error past :data:`MAX_GRAPH_DEPTH` edges.
        """
        caches = self._caches
        earliest = -1
        depth = 0
        frame = tid
        while True:
            cache = caches[frame]
            if cache is None:
                raise self._connectivity_error(sid, tid)
            stamp, parent = cache.latest_time_and_parent()
            if parent == 0:
                raise self._connectivity_error(sid, tid)
            if stamp != 0 and (earliest < 0 or stamp < earliest):
                earliest = stamp
            if parent in source_up:
                break
            if parent == sid:  # the source is an ancestor of the target
                return earliest if earliest >= 0 else 0
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                raise self._loop_error()
            frame = parent
        for reached, stamp in source_up.items():  # the source's edges up to the common parent
            if stamp != 0 and (earliest < 0 or stamp < earliest):
                earliest = stamp
            if reached == parent:
                break
        return earliest if earliest >= 0 else 0

    def _connectivity_error(self, sid: int, tid: int) -> ConnectivityException:
        names = self._names
        return ConnectivityException(
            f"Could not find a connection between '{names[tid]}' and '{names[sid]}' because they "
            "are not part of the same tree.Tf has two or more unconnected trees."
        )

    def _suffixed(self, exc: ExtrapolationException, sid: int, tid: int) -> ExtrapolationException:
        names = self._names
        return type(exc)(
            f"{exc}, when looking up transform from frame [{names[sid]}] to frame [{names[tid]}]"
        )

    def _walk(self, tid: int, sid: int, t: int) -> Sample:
        """tf2 ``walkToTopParent`` + ``TransformAccum`` at time ``t`` != 0 (lock held).

        The reference for every lookup's values and errors.

        Returns the raw T_target_source (qx, qy, qz, qw, tx, ty, tz) before tf2's final
        matrix round trip; raises tf2's exceptions.
        """
        caches = self._caches
        # source -> top, accumulating parent_T_source
        frame = sid
        top = sid
        depth = 0
        src_err: ExtrapolationException | None = None
        source_chain: Sample | None = None
        while frame != 0:
            cache = caches[frame]
            if cache is None:
                top = frame
                break
            try:
                parent, e = cache.get(t)
            except ExtrapolationException as exc:
                src_err = exc
                top = frame
                break
            if frame == tid:  # target is an ancestor of the source
                return _IDENTITY if source_chain is None else source_chain
            source_chain = e if source_chain is None else accumulate(e, source_chain)
            top = frame
            frame = parent
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                raise self._loop_error()

        # target -> top, accumulating parent_T_target
        frame = tid
        depth = 0
        target_chain: Sample | None = None
        while frame != top:
            cache = caches[frame]
            if cache is None:
                break
            try:
                parent, e = cache.get(t)
            except ExtrapolationException as exc:
                raise self._suffixed(exc, sid, tid) from None
            if frame == sid:  # source is an ancestor of the target: inverse(target chain)
                return inverse_compose(_IDENTITY if target_chain is None else target_chain, None)
            target_chain = e if target_chain is None else accumulate(e, target_chain)
            frame = parent
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                raise self._loop_error()
        if frame != top:
            if src_err is not None:
                raise self._suffixed(src_err, sid, tid) from None
            raise self._connectivity_error(sid, tid)
        source = _IDENTITY if source_chain is None else source_chain
        if target_chain is None:  # target is the top: T_target_source = source chain
            return source
        return inverse_compose(target_chain, source)

    def _build_path(self, tid: int, sid: int) -> FramePath | None:
        """The path to cache for a lookup that the reference walk just answered."""
        return build_path(self._caches, tid, sid, MAX_GRAPH_DEPTH)

    def _lookup_raw(self, target: str, source: str, t: int) -> tuple[Sample, int]:
        """(raw result, time used) for lookupTransform (lock held)."""
        if target == source:
            if t == 0:
                fid = self._ids.get(target)
                cache = self._caches[fid] if fid else None
                t = cache.latest_stamp() if cache is not None else 0
            return _IDENTITY, t
        tid = self._validate(target, "lookupTransform argument target_frame")
        sid = self._validate(source, "lookupTransform argument source_frame")
        if t == 0:
            # 0 stays 0 on an all-static path; caches then answer with their newest sample
            t = self._latest_common_time(tid, sid)
        return self._walk(tid, sid, t), t

    # ------------------------------------------------------------------------------------------
    # public lookups
    # ------------------------------------------------------------------------------------------
    def lookup_transform_core(
        self, target_frame: str, source_frame: str, time: Any
    ) -> TransformStamped:
        """T_target_source at ``time`` (0 / ``Time()`` = latest common time).

        Raises tf2's exceptions. ``header.stamp`` is the time actually used.
        """
        t = time.nanoseconds if type(time) is Time else time_to_ns(time)
        with self._lock:
            key = (target_frame, source_frame)
            path = self._paths.get(key)
            if path is None:
                return self._lookup_uncached(key, t)
            version = self._version
            memo = path.memo
            if memo is not None and memo[0] == version and memo[1] == t:
                # the same question on unchanged data: the last answer, in a new message
                return stamped(target_frame, source_frame, memo[2])
            if self._unpruned:
                self._prune_pending()
            asked = t
            if not t:
                t = latest_up(path.up) if path.mode == UP else -1
                if t < 0:
                    t = self._latest_common_time(path.target_id, path.source_id)
            result = evaluate(path.mode, path.up, path.down, path.check, t)
            if result is None:  # the path does not apply at t: the reference walk decides
                del self._paths[key]
                raw = self._walk(path.target_id, path.source_id, t)
                return _make_stamped(target_frame, source_frame, t, raw)
            path.memo = (version, asked, result)
        return stamped(target_frame, source_frame, result)

    def _lookup_uncached(self, key: tuple[str, str], t: int) -> TransformStamped:
        """lookupTransform by the reference walk (lock held).

        Caches the pair's path after a successful walk between two known, distinct frames.
        """
        target, source = key
        ids = self._ids
        tid = ids.get(target)
        sid = ids.get(source)
        if tid and sid and tid != sid and target[0] != "/" and source[0] != "/":
            if not t:
                t = self._latest_common_time(tid, sid)
            raw = self._walk(tid, sid, t)
            path = self._build_path(tid, sid)
            if path is not None:
                self._paths[key] = path
            return _make_stamped(target, source, t, raw)
        raw, used = self._lookup_raw(target, source, t)
        return _make_stamped(target, source, used, raw)

    def lookup_transform_full_core(
        self,
        target_frame: str,
        target_time: Any,
        source_frame: str,
        source_time: Any,
        fixed_frame: str,
    ) -> TransformStamped:
        """Time travel: T_target(target_time)_source(source_time) through ``fixed_frame``.

        ``fixed_frame`` is assumed not to move. ``header.stamp`` = the resolved target time.
        """
        tt = time_to_ns(target_time)
        st = time_to_ns(source_time)
        with self._lock:
            self._validate(target_frame, "lookupTransform argument target_frame")
            self._validate(source_frame, "lookupTransform argument source_frame")
            self._validate(fixed_frame, "lookupTransform argument fixed_frame")
            raw1, _ = self._lookup_raw(fixed_frame, source_frame, st)
            raw2, used = self._lookup_raw(target_frame, fixed_frame, tt)
        q, v = _transform_mul(raw2[:4], raw2[4:], raw1[:4], raw1[4:])
        sec, nanosec = divmod(used, _NS)
        return stamped(target_frame, source_frame, (sec, nanosec, *q, *v))

    def can_transform_core(
        self, target_frame: str, source_frame: str, time: Any
    ) -> tuple[bool, str]:
        """(possible, tf2's error text or "") for a lookup at ``time``; never raises tf2 errors."""
        t = time_to_ns(time)
        if target_frame == source_frame:
            return True, ""
        with self._lock:
            if self._unpruned:
                self._prune_pending()
            path = self._paths.get((target_frame, source_frame))
            if path is not None and t and evaluate(
                path.mode, path.up, path.down, path.check, t
            ) is not None:  # the can-transform policy: the cached path evaluates at t
                return True, ""
            tid, msg = self._validate_msg(target_frame, "canTransform argument target_frame")
            if not tid:
                return False, msg
            sid, msg = self._validate_msg(source_frame, "canTransform argument source_frame")
            if not sid:
                return False, msg
            return self._can_internal(tid, sid, t)

    def _can_internal(self, tid: int, sid: int, t: int) -> tuple[bool, str]:
        if tid == sid:
            return True, ""
        try:
            if t == 0:
                t = self._latest_common_time(tid, sid)
            self._walk(tid, sid, t)
        except TransformException as exc:
            return False, str(exc)
        return True, ""

    def can_transform_full_core(
        self,
        target_frame: str,
        target_time: Any,
        source_frame: str,
        source_time: Any,
        fixed_frame: str,
    ) -> tuple[bool, str]:
        """canTransform for :meth:`lookup_transform_full_core`: (possible, message)."""
        tt = time_to_ns(target_time)
        st = time_to_ns(source_time)
        with self._lock:
            tid, msg = self._validate_msg(target_frame, "canTransform argument target_frame")
            if not tid:
                return False, msg
            sid, msg = self._validate_msg(source_frame, "canTransform argument source_frame")
            if not sid:
                return False, msg
            fid, msg = self._validate_msg(fixed_frame, "canTransform argument fixed_frame")
            if not fid:
                return False, msg
            ok, msg = self._can_internal(tid, fid, tt)
            if not ok:
                return ok, msg
            return self._can_internal(fid, sid, st)

    def lookup_transforms(
        self, target_frame: str, source_frame: str, times_ns: Any
    ) -> tuple[Any, Any]:
        """T_target_source at many stamps at once (beyond tf2), with single-lookup semantics.

        Args:
            target_frame: frame the results map into.
            source_frame: frame the results map from.
            times_ns: 1-D integer array of stamps in nanoseconds (0 = latest common time).

        Returns:
            ``(translations, quaternions)``: float64 arrays of shape (N, 3) and (N, 4), the
            quaternions as (x, y, z, w) with tf2's canonical sign.

        Raises:
            tf2's exception for the first stamp (in array order) whose single lookup would
            fail; the text is tf2's plus ``(first failing stamp: times_ns[i] = ...)``, and the
            exception has ``index`` and ``stamp_ns`` attributes.
        """
        import numpy as np

        from posekit.tf2.batch import lookup_transforms_locked

        times = np.asarray(times_ns)
        if times.ndim != 1:
            raise ValueError(f"times_ns must be 1-D, got shape {times.shape}")
        if times.dtype.kind not in "iu" and times.size:
            raise TypeError(f"times_ns must be integer nanoseconds, got dtype {times.dtype}")
        times = times.astype(np.int64, copy=False)
        with self._lock:
            return lookup_transforms_locked(LockedView(self), target_frame, source_frame, times)

    def get_latest_common_time(self, target_frame: str, source_frame: str) -> Time:
        """The time a ``Time()`` lookup would use; failures raise plain TransformException."""
        with self._lock:
            tid = self._validate(target_frame, "getLatestCommonTime argument target_frame")
            sid = self._validate(source_frame, "getLatestCommonTime argument source_frame")
            try:
                ns = self._latest_common_time(tid, sid)
            except TransformException as exc:
                raise TransformException(str(exc)) from None
        return Time(nanoseconds=ns)

    # ------------------------------------------------------------------------------------------
    # introspection
    # ------------------------------------------------------------------------------------------
    def _frames_as_string_locked(self) -> str:
        return introspection.frames_as_string(self._names, self._caches)

    def all_frames_as_string(self) -> str:
        """``Frame <child> exists with parent <parent>.`` per cached frame, in id order."""
        with self._lock:
            return self._frames_as_string_locked()

    def all_frames_as_yaml(self, current_time: Any = 0) -> str:
        """tf2's YAML dump of every frame with data (``[]`` for an empty buffer)."""
        now = time_to_ns(current_time)
        with self._lock:
            return introspection.frames_as_yaml(self._names, self._caches, self._authority, now)

    def _allFramesAsDot(self, time: Any = 0) -> str:
        """tf2's own dot dump (``_allFramesAsDot``), byte for byte."""
        now = time_to_ns(time)
        with self._lock:
            return introspection.frames_as_dot_core(self._names, self._caches, self._authority, now)

    def to_dot(self, recorded_at: Any = None) -> str:
        """The graph text tf2_tools' ``view_frames`` writes (its ``generate_dot`` of our YAML).

        ``recorded_at`` is the legend time (default: the wall clock now).
        """
        if recorded_at is None:
            import time as _time

            ns = _time.time_ns()
        else:
            ns = time_to_ns(recorded_at)
        with self._lock:
            yaml_text = introspection.frames_as_yaml(self._names, self._caches, self._authority, 0)
        return introspection.view_frames_dot(yaml_text, divmod(ns, _NS))

    def _frameExists(self, frame_id: str) -> bool:
        """Whether the name was ever registered (True even after ``clear()``)."""
        with self._lock:
            return frame_id in self._ids

    def _getFrameStrings(self) -> list[str]:
        """All registered frame names in id order."""
        with self._lock:
            return list(self._names[1:])

    def get_all_frame_names(self) -> list[str]:
        """All registered frame names in id order (tf2 ``getAllFrameNames``)."""
        return self._getFrameStrings()


def _transform_mul(
    q2: tuple[float, float, float, float],
    v2: tuple[float, float, float],
    q1: tuple[float, float, float, float],
    v1: tuple[float, float, float],
) -> tuple[tuple[float, float, float, float], tuple[float, float, float]]:
    """tf2 ``Transform * Transform`` on matrices built from raw quaternions: (R2 R1, R2 v1 + v2).

    The rotation is read back with getRotation.
    """
    a = matrix_from_quat(q2)
    b = matrix_from_quat(q1)
    m = tuple(
        a[3 * r] * b[c] + a[3 * r + 1] * b[3 + c] + a[3 * r + 2] * b[6 + c]
        for r in range(3)
        for c in range(3)
    )
    v = tuple(
        a[3 * r] * v1[0] + a[3 * r + 1] * v1[1] + a[3 * r + 2] * v1[2] + v2[r] for r in range(3)
    )
    return quat_from_matrix(m), (v[0], v[1], v[2])  # type: ignore[arg-type]
