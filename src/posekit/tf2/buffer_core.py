"""BufferCore: tf2's transform tree with ROS 2 semantics (``tf2/src/buffer_core.cpp``).

Frames get small integer ids in the order they are first seen (child before parent, id 0 is
``NO_PARENT``); each child frame owns one cache (:class:`TimeCache` or :class:`StaticCache`)
of parent_T_child samples. Times are integer nanoseconds; 0 means "latest common time".

A lookup ``lookup_transform_core(target, source, t)`` returns T_target_source: it maps
coordinates expressed in ``source`` into ``target``, and its translation is the origin of
``source`` expressed in ``target``. Quaternions are (x, y, z, w) everywhere.

The method names follow tf2_py's ``BufferCore`` so code written for ROS 2 runs unchanged;
:class:`posekit.tf2.Buffer` adds tf2_ros's waiting API on top.
"""

from __future__ import annotations

import logging
import math
import numbers
import threading
from bisect import bisect_right as _bisect_right
from collections.abc import Iterable
from typing import Any

from posekit.msgs.builtin_interfaces import Time as TimeMsg
from posekit.msgs.geometry_msgs import Quaternion, Transform, TransformStamped, Vector3
from posekit.msgs.std_msgs import Header
from posekit.tf2 import introspection
from posekit.tf2._linear_math import matrix_from_quat, quat_from_matrix
from posekit.tf2.exceptions import (
    ConnectivityException,
    ExtrapolationException,
    InvalidArgumentException,
    LookupException,
    TransformException,
)
from posekit.tf2.static_cache import StaticCache
from posekit.tf2.time_cache import (
    DEFAULT_CACHE_TIME_NS,
    Sample,
    TimeCache,
    display_time,
)
from posekit.tf2.time_cache import (
    slerp_terms as _slerp_terms,
)
from posekit.time import Duration, Time

__all__ = ["MAX_GRAPH_DEPTH", "BufferCore", "time_to_ns"]

#: tf2's walk limit; a longer walk is reported as a loop.
MAX_GRAPH_DEPTH = 1000

_logger = logging.getLogger("posekit.tf2")
_sqrt = math.sqrt
_sin = math.sin
_NS = 1_000_000_000
_INF = math.inf

Cache = TimeCache | StaticCache
# Raw result of a walk: (qx, qy, qz, qw), (tx, ty, tz), before tf2's matrix round trip.
_Raw = tuple[tuple[float, float, float, float], tuple[float, float, float]]
_IDENTITY: _Raw = ((0.0, 0.0, 0.0, 1.0), (0.0, 0.0, 0.0))

# Fast-path walk shapes (see BufferCore._build_path): target is an ancestor of the source
# (or the top), source is an ancestor of the target, or both walk to the top.
_UP = "up"
_DOWN = "down"
_FULL = "full"
# One edge of a cached path: a TimeCache's (stamps, parents, data, slerp memo) lists (mutated
# in place, never replaced), the parent id the edge must have, and the StaticCache if static.
_Edge = tuple[Any, Any, Any, Any, int, Any]
# [shape, chain(s), edge that must evaluate without error or None, target id, source id,
#  memo]: a list so the memo of the last evaluated result can be replaced in place. The memo
# is None or (buffer version, requested time ns, *_Result) of the last fast-path answer.
_Path = list[Any]
# A finished lookup result: (stamp sec, stamp nanosec, qx, qy, qz, qw, vx, vy, vz), the
# quaternion after tf2's matrix round trip.
_Result = tuple[int, int, float, float, float, float, float, float, float]


def _latest_up(chain: tuple[_Edge, ...]) -> int:
    """tf2's latest common time when the target is an ancestor of the source: the oldest of
    the chain's newest non-zero stamps (0 if none), provided every edge's newest sample has
    the cached parent, which is when getLatestCommonTime walks exactly this chain; else -1."""
    common = -1
    for stamps, parents, _, _, expected, static in chain:
        if stamps is None:
            if static.parent != expected:
                return -1
        elif not stamps or parents[-1] != expected:
            return -1
        else:
            stamp = stamps[-1]
            if stamp != 0 and (common < 0 or stamp < common):
                common = stamp
    return common if common >= 0 else 0


def _edge_evaluates(edge: _Edge, t: int) -> bool:
    """Whether TimeCache.get(t) certainly succeeds on this edge (static edges always do)."""
    stamps = edge[0]
    return stamps is None or bool(stamps and stamps[0] < t <= stamps[-1])


_INT32 = 1 << 31
_UINT32 = 1 << 32


def _check_stamp(sec: Any, nanosec: Any, child: Any) -> tuple[int, int]:
    """``(sec, nanosec)`` as ints, or raise for a header stamp that is not a
    builtin_interfaces/Time (int32 sec, uint32 nanosec), as rclpy refuses such values when
    they are assigned to the message. numpy integers are accepted."""
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
    if duration is None:
        return 0
    ns = getattr(duration, "nanoseconds", None)
    if ns is not None:
        return int(ns)
    if isinstance(duration, int):
        return duration
    return int(duration.sec) * _NS + int(duration.nanosec)


_new = object.__new__


def _make_stamped(
    target: str, source: str, stamp_ns: int, q: tuple[float, ...], v: tuple[float, ...]
) -> TransformStamped:
    """The result message with quaternion ``q`` and translation ``v`` as given."""
    sec, nanosec = divmod(stamp_ns, _NS)
    return _stamped(target, source, (sec, nanosec, q[0], q[1], q[2], q[3], v[0], v[1], v[2]))


def _make_stamped_canonical(
    target: str, source: str, stamp_ns: int, q: tuple[float, ...], v: tuple[float, ...]
) -> TransformStamped:
    """``_make_stamped(target, source, stamp_ns, _canonical(q), v)``: the raw quaternion
    through tf2's matrix round trip."""
    return _stamped(target, source, _result(stamp_ns, (q, v)))  # type: ignore[arg-type]


def _result(stamp_ns: int, raw: _Raw) -> _Result:
    """The finished values of a lookup: the stamp split as builtin_interfaces/Time and the
    raw quaternion through tf2's matrix round trip (positive-trace branch of getRotation
    inlined, the others in :func:`_canonical`)."""
    (x, y, z, w), (vx, vy, vz) = raw
    sec, nanosec = divmod(stamp_ns, _NS)
    d = x * x + y * y + z * z + w * w
    s = 2.0 / d
    xs, ys, zs = x * s, y * s, z * s
    wx, wy, wz = w * xs, w * ys, w * zs
    xx, xy, xz = x * xs, x * ys, x * zs
    yy, yz, zz = y * ys, y * zs, z * zs
    trace = (1.0 - (yy + zz)) + (1.0 - (xx + zz)) + (1.0 - (xx + yy))
    if not trace > 0.0:
        qx, qy, qz, qw = _canonical((x, y, z, w))
        return sec, nanosec, qx, qy, qz, qw, vx, vy, vz
    s = _sqrt(trace + 1.0)
    qw = s * 0.5
    s = 0.5 / s
    return (
        sec,
        nanosec,
        ((yz + wx) - (yz - wx)) * s,
        ((xz + wy) - (xz - wy)) * s,
        ((xy + wz) - (xy - wz)) * s,
        qw,
        vx,
        vy,
        vz,
    )


def _stamped(target: str, source: str, r: tuple[Any, ...]) -> TransformStamped:
    """A fresh TransformStamped from a :data:`_Result` (``r``), field by field (skipping the
    dataclass __init__ chain, which costs more than a tree walk); tests check it equals the
    normally built message."""
    sec, nanosec, qx, qy, qz, qw, vx, vy, vz = r
    stamp = _new(TimeMsg)
    stamp.sec = sec
    stamp.nanosec = nanosec
    header = _new(Header)
    header.stamp = stamp
    header.frame_id = target
    vec = _new(Vector3)
    vec.x = vx
    vec.y = vy
    vec.z = vz
    rot = _new(Quaternion)
    rot.x = qx
    rot.y = qy
    rot.z = qz
    rot.w = qw
    tr = _new(Transform)
    tr.translation = vec
    tr.rotation = rot
    msg = _new(TransformStamped)
    msg.header = header
    msg.child_frame_id = source
    msg.transform = tr
    return msg


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
        # fast-path walks per (target, source) name pair; emptied whenever a cache is created
        self._paths: dict[tuple[str, str], _Path] = {}
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
        """Insert a dynamic ``TransformStamped`` (parent ``header.frame_id``, child
        ``child_frame_id``). Returns True if stored, False if tf2 rejects it (reason logged
        on logger ``posekit.tf2`` with tf2's text). A stamp that is no
        builtin_interfaces/Time (``sec`` not an int32, ``nanosec`` not a uint32, e.g. 1.5 or
        2**70) raises TypeError or ValueError naming the field, as rclpy refuses it on the
        message."""
        return self._set(transform, authority, False)

    def set_transform_static(self, transform: Any, authority: str) -> bool:
        """Insert a static transform (valid at every time, survives :meth:`clear`)."""
        return self._set(transform, authority, True)

    def _set(self, msg: Any, authority: str, is_static: bool) -> bool:
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
            s = 2.0 / d
            xs, ys, zs = x * s, y * s, z * s
            wx, wy, wz = w * xs, w * ys, w * zs
            xx, xy, xz = x * xs, x * ys, x * zs
            yy, yz, zz = y * ys, y * zs, z * zs
            m00 = 1.0 - (yy + zz)
            m11 = 1.0 - (xx + zz)
            m22 = 1.0 - (xx + yy)
            trace = m00 + m11 + m22
            if trace > 0.0:
                s = _sqrt(trace + 1.0)
                qw = s * 0.5
                s = 0.5 / s
                qx = ((yz + wx) - (yz - wx)) * s
                qy = ((xz + wy) - (xz - wy)) * s
                qz = ((xy + wz) - (xy - wz)) * s
            else:
                qx, qy, qz, qw = _canonical((x, y, z, w))
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
            return False
        sample: Sample = (qx, qy, qz, qw, tx, ty, tz)
        with self._lock:
            self._version += 1
            ids = self._ids
            caches = self._caches
            cid = ids.get(child)
            if cid is None:
                cid = self._add_frame(child)
            cache = caches[cid]
            if cache is None or cache.is_static is not is_static:
                cache = StaticCache() if is_static else TimeCache(self._cache_time_ns)
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
        """Forget frames entirely (posekit extension; tf2 has no way to drop a frame): their
        transforms (dynamic and static), their authority, and their names unless a frame
        that stays still has one of them as its parent; frames left with no data and no
        child go too. Returns how many names were dropped. Waiting lookups are unaffected;
        a forgotten frame is unknown until it is set again."""
        with self._lock:
            self._version += 1
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
        """tf2 ``getLatestCommonTime`` (lock held): min of the newest non-zero stamps below
        the common ancestor, using each frame's current newest sample and parent."""
        caches = self._caches
        if sid == tid:
            cache = caches[sid]
            return cache.latest_stamp() if cache is not None else 0
        src_list: list[tuple[int, int]] = []
        frame = sid
        depth = 0
        common = -1  # -1 = none seen yet (tf2 uses TimePoint::max)
        while frame != 0:
            cache = caches[frame]
            if cache is None:
                break
            stamp, parent = cache.latest_time_and_parent()
            if parent == 0:
                break
            if stamp != 0 and (common < 0 or stamp < common):
                common = stamp
            src_list.append((stamp, parent))
            frame = parent
            if frame == tid:
                return common if common >= 0 else 0
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                raise self._loop_error()
        src_parents = {p for _, p in src_list}
        frame = tid
        depth = 0
        common = -1
        common_parent = 0
        while True:
            cache = caches[frame]
            if cache is None:
                break
            stamp, parent = cache.latest_time_and_parent()
            if parent == 0:
                break
            if stamp != 0 and (common < 0 or stamp < common):
                common = stamp
            if parent in src_parents:
                common_parent = parent
                break
            frame = parent
            if frame == sid:
                return common if common >= 0 else 0
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                raise self._loop_error()
        if common_parent == 0:
            raise self._connectivity_error(sid, tid)
        for stamp, parent in src_list:
            if stamp != 0 and (common < 0 or stamp < common):
                common = stamp
            if parent == common_parent:
                break
        return common if common >= 0 else 0

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

    def _walk(self, tid: int, sid: int, t: int) -> _Raw:
        """tf2 ``walkToTopParent`` + ``TransformAccum`` at time ``t`` != 0 (lock held).

        Returns the raw (quaternion, translation) of T_target_source before tf2's final
        matrix round trip; raises tf2's exceptions.
        """
        caches = self._caches
        # source -> top, accumulating parent_T_source: v = rotate(q_e, v) + t_e, q = q_e * q
        frame = sid
        top = sid
        depth = 0
        src_err: ExtrapolationException | None = None
        sx = sy = sz = 0.0
        sqx = sqy = sqz = 0.0
        sqw = 1.0
        first = True
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
            if frame == tid:
                return (sqx, sqy, sqz, sqw), (sx, sy, sz)
            qx, qy, qz, qw, ex, ey, ez = e
            if first:
                sqx, sqy, sqz, sqw, sx, sy, sz = qx, qy, qz, qw, ex, ey, ez
                first = False
            else:
                px = qw * sx + qy * sz - qz * sy
                py = qw * sy + qz * sx - qx * sz
                pz = qw * sz + qx * sy - qy * sx
                pw = -qx * sx - qy * sy - qz * sz
                sx = px * qw - pw * qx - py * qz + pz * qy + ex
                sy = py * qw - pw * qy - pz * qx + px * qz + ey
                sz = pz * qw - pw * qz - px * qy + py * qx + ez
                sqx, sqy, sqz, sqw = (
                    qw * sqx + qx * sqw + qy * sqz - qz * sqy,
                    qw * sqy + qy * sqw + qz * sqx - qx * sqz,
                    qw * sqz + qz * sqw + qx * sqy - qy * sqx,
                    qw * sqw - qx * sqx - qy * sqy - qz * sqz,
                )
            top = frame
            frame = parent
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                raise self._loop_error()

        # target -> top
        frame = tid
        depth = 0
        vx = vy = vz = 0.0
        tqx = tqy = tqz = 0.0
        tqw = 1.0
        first = True
        while frame != top:
            cache = caches[frame]
            if cache is None:
                break
            try:
                parent, e = cache.get(t)
            except ExtrapolationException as exc:
                raise self._suffixed(exc, sid, tid) from None
            if frame == sid:
                # source is an ancestor of target: result = inverse(target chain)
                return _inverse_rotate(tqx, tqy, tqz, tqw, vx, vy, vz, 0.0, 0.0, 0.0)
            qx, qy, qz, qw, ex, ey, ez = e
            if first:
                tqx, tqy, tqz, tqw, vx, vy, vz = qx, qy, qz, qw, ex, ey, ez
                first = False
            else:
                px = qw * vx + qy * vz - qz * vy
                py = qw * vy + qz * vx - qx * vz
                pz = qw * vz + qx * vy - qy * vx
                pw = -qx * vx - qy * vy - qz * vz
                vx = px * qw - pw * qx - py * qz + pz * qy + ex
                vy = py * qw - pw * qy - pz * qx + px * qz + ey
                vz = pz * qw - pw * qz - px * qy + py * qx + ez
                tqx, tqy, tqz, tqw = (
                    qw * tqx + qx * tqw + qy * tqz - qz * tqy,
                    qw * tqy + qy * tqw + qz * tqx - qx * tqz,
                    qw * tqz + qz * tqw + qx * tqy - qy * tqx,
                    qw * tqw - qx * tqx - qy * tqy - qz * tqz,
                )
            frame = parent
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                raise self._loop_error()
        if frame != top:
            if src_err is not None:
                raise self._suffixed(src_err, sid, tid) from None
            raise self._connectivity_error(sid, tid)
        if first:  # target is the top: T_target_source = source chain
            return (sqx, sqy, sqz, sqw), (sx, sy, sz)
        # full path: q = conj(q_t) * q_s, v = rotate(conj(q_t), v_s) + rotate(conj(q_t), -v_t)
        return _inverse_rotate(tqx, tqy, tqz, tqw, vx, vy, vz, sx, sy, sz, (sqx, sqy, sqz, sqw))

    # ------------------------------------------------------------------------------------------
    # fast path for single lookups (the general walk above is the reference)
    # ------------------------------------------------------------------------------------------
    # A lookup between two known, distinct frames repeats the same walk most of the time. The
    # path (which caches the walk visits, and the parent each edge must have) is cached per
    # (target, source) name pair, built from the newest parents. At lookup time every edge is
    # evaluated with TimeCache.get's arithmetic inlined, checking that the sample's parent is
    # the cached one; any surprise (re-parented sample, stamp outside the common case,
    # extrapolation) returns None and the caller runs the general walk, which then decides
    # results and errors. The fast path only reads (plus the same slerp memo get() fills), so
    # falling back is always safe. Cache objects change only where set() creates or replaces
    # one, which empties the path cache; tests/tf2/test_fast_paths.py checks bit-identity.

    def _build_path(self, tid: int, sid: int) -> _Path | None:
        """The walk's shape from the newest parents, or None if the fast path cannot serve it."""
        caches = self._caches

        def edge(frame: int) -> tuple[_Edge, int] | None:
            cache = caches[frame]
            if cache is None:
                return None
            parent = cache.latest_time_and_parent()[1]
            if parent == 0:
                return None
            if isinstance(cache, TimeCache):
                return (cache.stamps, cache.parents, cache.data, cache._iv, parent, None), parent
            return (None, None, None, None, parent, cache), parent

        src: list[_Edge] = []
        frame = sid
        while True:
            if len(src) >= MAX_GRAPH_DEPTH:
                return None
            cache = caches[frame]
            if cache is None:
                top = frame
                break
            got = edge(frame)
            if got is None:
                return None
            if frame == tid:  # target is an ancestor: its edge must only evaluate
                return [_UP, tuple(src), got[0], tid, sid, None]
            src.append(got[0])
            frame = got[1]
        if top == tid:
            return [_UP, tuple(src), None, tid, sid, None]
        tgt: list[_Edge] = []
        frame = tid
        while frame != top:
            if len(tgt) >= MAX_GRAPH_DEPTH:
                return None
            got = edge(frame)
            if got is None:
                return None
            if frame == sid:  # source is an ancestor of the target
                return [_DOWN, (tuple(src), tuple(tgt)), got[0], tid, sid, None]
            tgt.append(got[0])
            frame = got[1]
        return [_FULL, (tuple(src), tuple(tgt)), None, tid, sid, None]

    @staticmethod
    def _chain(chain: tuple[_Edge, ...], t: int) -> tuple[float, ...] | None:
        """Accumulated parent_T_child along ``chain`` at ``t`` (the walk's arithmetic, fused
        with TimeCache.get's lerp + slerp), or None to fall back to the general walk."""
        sqx = sqy = sqz = sx = sy = sz = 0.0
        sqw = 1.0
        first = True
        for stamps, parents, data, ivs, expected, static in chain:
            if stamps is None:
                if static.parent != expected:
                    return None
                qx, qy, qz, qw, ex, ey, ez = static.sample
            elif stamps and stamps[0] < t < stamps[-1]:
                i = _bisect_right(stamps, t) - 1
                if parents[i] != expected:
                    return None
                if parents[i + 1] != expected:  # re-parented in between: no interpolation
                    qx, qy, qz, qw, ex, ey, ez = data[i]
                else:
                    s0 = stamps[i]
                    r = (t - s0) / (stamps[i + 1] - s0)
                    u = 1.0 - r
                    x1, y1, z1, w1, ax, ay, az = data[i]
                    x2, y2, z2, w2, bx, by, bz = data[i + 1]
                    iv = ivs[i]
                    if iv is None:
                        iv = _slerp_terms(x1, y1, z1, w1, x2, y2, z2, w2)
                        ivs[i] = iv
                    theta, d, flip = iv
                    ex = u * ax + r * bx
                    ey = u * ay + r * by
                    ez = u * az + r * bz
                    if theta == 0.0:
                        qx, qy, qz, qw = x1, y1, z1, w1
                    else:
                        s0f = _sin(u * theta)
                        s1f = -_sin(r * theta) if flip else _sin(r * theta)
                        qx = (x1 * s0f + x2 * s1f) * d
                        qy = (y1 * s0f + y2 * s1f) * d
                        qz = (z1 * s0f + z2 * s1f) * d
                        qw = (w1 * s0f + w2 * s1f) * d
            elif stamps and t == stamps[-1]:
                if parents[-1] != expected:
                    return None
                qx, qy, qz, qw, ex, ey, ez = data[-1]
            else:
                return None
            if first:
                sqx, sqy, sqz, sqw, sx, sy, sz = qx, qy, qz, qw, ex, ey, ez
                first = False
            else:
                px = qw * sx + qy * sz - qz * sy
                py = qw * sy + qz * sx - qx * sz
                pz = qw * sz + qx * sy - qy * sx
                pw = -qx * sx - qy * sy - qz * sz
                sx = px * qw - pw * qx - py * qz + pz * qy + ex
                sy = py * qw - pw * qy - pz * qx + px * qz + ey
                sz = pz * qw - pw * qz - px * qy + py * qx + ez
                sqx, sqy, sqz, sqw = (
                    qw * sqx + qx * sqw + qy * sqz - qz * sqy,
                    qw * sqy + qy * sqw + qz * sqx - qx * sqz,
                    qw * sqz + qz * sqw + qx * sqy - qy * sqx,
                    qw * sqw - qx * sqx - qy * sqy - qz * sqz,
                )
        return sqx, sqy, sqz, sqw, sx, sy, sz

    def _walk_fast(self, path: _Path, t: int) -> _Raw | None:
        """:meth:`_walk` over a cached path, or None (fall back) if the path does not apply."""
        mode = path[0]
        chains = path[1]
        check = path[2]
        if check is not None and not _edge_evaluates(check, t):
            return None
        if mode is _UP:
            a = self._chain(chains, t)
            if a is None:
                return None
            return (a[0], a[1], a[2], a[3]), (a[4], a[5], a[6])
        if mode is _DOWN:
            # the general walk first walks the source to the top (a loop there raises), then
            # returns when the target walk reaches the source
            if self._chain(chains[0], t) is None:
                return None
            b = self._chain(chains[1], t)
            if b is None:
                return None
            return _inverse_rotate(b[0], b[1], b[2], b[3], b[4], b[5], b[6], 0.0, 0.0, 0.0)
        a = self._chain(chains[0], t)
        if a is None:
            return None
        b = self._chain(chains[1], t)
        if b is None:
            return None
        if not chains[1]:  # target is the top
            return (a[0], a[1], a[2], a[3]), (a[4], a[5], a[6])
        return _inverse_rotate(
            b[0], b[1], b[2], b[3], b[4], b[5], b[6], a[4], a[5], a[6], (a[0], a[1], a[2], a[3])
        )

    def _lookup_raw(self, target: str, source: str, t: int) -> tuple[_Raw, int]:
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
        """T_target_source at ``time`` (0 / ``Time()`` = latest common time); raises tf2's
        exceptions. ``header.stamp`` is the time actually used."""
        t = time.nanoseconds if type(time) is Time else time_to_ns(time)
        with self._lock:
            key = (target_frame, source_frame)
            path = self._paths.get(key)
            if path is not None:  # known, distinct, valid names with a cached walk
                memo = path[5]
                version = self._version
                if memo is not None and memo[0] == version and memo[1] == t:
                    # the same question on unchanged data: the last answer, rebuilt
                    return _stamped(target_frame, source_frame, memo[2:])
                asked = t
                if not t:
                    t = _latest_up(path[1]) if path[0] is _UP else -1
                    if t < 0:
                        t = self._latest_common_time(path[3], path[4])
                raw = self._walk_fast(path, t)
                if raw is None:  # the path does not apply at t: the general walk decides
                    del self._paths[key]
                    q, v = self._walk(path[3], path[4], t)
                    return _make_stamped_canonical(target_frame, source_frame, t, q, v)
                result = _result(t, raw)
                path[5] = (version, asked, *result)
                return _stamped(target_frame, source_frame, result)
            ids = self._ids
            tid = ids.get(target_frame)
            sid = ids.get(source_frame)
            if tid and sid and tid != sid and target_frame[0] != "/" and source_frame[0] != "/":
                if not t:
                    t = self._latest_common_time(tid, sid)
                q, v = self._walk(tid, sid, t)
                used = t
                # only after a successful walk: a path is cached for working lookups
                new_path = self._build_path(tid, sid)
                if new_path is not None:
                    self._paths[key] = new_path
            else:
                (q, v), used = self._lookup_raw(target_frame, source_frame, t)
        return _make_stamped_canonical(target_frame, source_frame, used, q, v)

    def lookup_transform_full_core(
        self,
        target_frame: str,
        target_time: Any,
        source_frame: str,
        source_time: Any,
        fixed_frame: str,
    ) -> TransformStamped:
        """Time travel: T_target(target_time)_source(source_time) through ``fixed_frame``,
        which is assumed not to move. ``header.stamp`` = the resolved target time."""
        tt = time_to_ns(target_time)
        st = time_to_ns(source_time)
        with self._lock:
            self._validate(target_frame, "lookupTransform argument target_frame")
            self._validate(source_frame, "lookupTransform argument source_frame")
            self._validate(fixed_frame, "lookupTransform argument fixed_frame")
            (q1, v1), _ = self._lookup_raw(fixed_frame, source_frame, st)
            (q2, v2), used = self._lookup_raw(target_frame, fixed_frame, tt)
        q, v = _transform_mul(q2, v2, q1, v1)
        return _make_stamped(target_frame, source_frame, used, q, v)

    def can_transform_core(
        self, target_frame: str, source_frame: str, time: Any
    ) -> tuple[bool, str]:
        """(possible, tf2's error text or "") for a lookup at ``time``; never raises tf2 errors."""
        t = time_to_ns(time)
        if target_frame == source_frame:
            return True, ""
        with self._lock:
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
            return lookup_transforms_locked(self, target_frame, source_frame, times)

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


def _inverse_rotate(
    tqx: float, tqy: float, tqz: float, tqw: float,
    vx: float, vy: float, vz: float,
    sx: float, sy: float, sz: float,
    sq: tuple[float, float, float, float] | None = None,
) -> _Raw:  # fmt: skip
    """tf2 finalize: inv = conj(q_t); v = rotate(inv, v_s) + rotate(inv, -v_t); q = inv * q_s."""
    ix, iy, iz, iw = -tqx, -tqy, -tqz, tqw
    out = []
    for ux, uy, uz in ((-vx, -vy, -vz), (sx, sy, sz)):
        px = iw * ux + iy * uz - iz * uy
        py = iw * uy + iz * ux - ix * uz
        pz = iw * uz + ix * uy - iy * ux
        pw = -ix * ux - iy * uy - iz * uz
        out.append((
            px * iw - pw * ix - py * iz + pz * iy,
            py * iw - pw * iy - pz * ix + px * iz,
            pz * iw - pw * iz - px * iy + py * ix,
        ))  # fmt: skip
    (ax, ay, az), (bx, by, bz) = out
    if sq is None:
        return (ix, iy, iz, iw), (ax, ay, az)
    qx, qy, qz, qw = sq
    return (
        (
            iw * qx + ix * qw + iy * qz - iz * qy,
            iw * qy + iy * qw + iz * qx - ix * qz,
            iw * qz + iz * qw + ix * qy - iy * qx,
            iw * qw - ix * qx - iy * qy - iz * qz,
        ),
        (bx + ax, by + ay, bz + az),
    )


def _canonical(q: tuple[float, float, float, float]) -> tuple[float, float, float, float]:
    """tf2 ``Transform::setRotation`` then ``getRotation`` (normalise, canonical sign)."""
    x, y, z, w = q
    d = x * x + y * y + z * z + w * w
    s = 2.0 / d
    xs, ys, zs = x * s, y * s, z * s
    wx, wy, wz = w * xs, w * ys, w * zs
    xx, xy, xz = x * xs, x * ys, x * zs
    yy, yz, zz = y * ys, y * zs, z * zs
    trace = (1.0 - (yy + zz)) + (1.0 - (xx + zz)) + (1.0 - (xx + yy))
    if trace > 0.0:
        s = _sqrt(trace + 1.0)
        qw = s * 0.5
        s = 0.5 / s
        return (
            ((yz + wx) - (yz - wx)) * s,
            ((xz + wy) - (xz - wy)) * s,
            ((xy + wz) - (xy - wz)) * s,
            qw,
        )
    # getRotation's other branch, unrolled for the index of the largest diagonal element
    m00 = 1.0 - (yy + zz)
    m11 = 1.0 - (xx + zz)
    m22 = 1.0 - (xx + yy)
    m01, m10 = xy - wz, xy + wz
    m02, m20 = xz + wy, xz - wy
    m12, m21 = yz - wx, yz + wx
    i = (2 if m11 < m22 else 1) if m00 < m11 else (2 if m00 < m22 else 0)
    if i == 0:
        s = _sqrt(m00 - m11 - m22 + 1.0)
        h = s * 0.5
        s = 0.5 / s
        return h, (m10 + m01) * s, (m20 + m02) * s, (m21 - m12) * s
    if i == 1:
        s = _sqrt(m11 - m22 - m00 + 1.0)
        h = s * 0.5
        s = 0.5 / s
        return (m01 + m10) * s, h, (m21 + m12) * s, (m02 - m20) * s
    s = _sqrt(m22 - m00 - m11 + 1.0)
    h = s * 0.5
    s = 0.5 / s
    return (m02 + m20) * s, (m12 + m21) * s, h, (m10 - m01) * s


def _transform_mul(
    q2: tuple[float, float, float, float],
    v2: tuple[float, float, float],
    q1: tuple[float, float, float, float],
    v1: tuple[float, float, float],
) -> tuple[tuple[float, float, float, float], tuple[float, float, float]]:
    """tf2 ``Transform * Transform`` on matrices built from raw quaternions, read back with
    getRotation: (R2 R1, R2 v1 + v2)."""
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
