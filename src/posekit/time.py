"""Time and Duration modelled on rclpy: integer nanoseconds inside, never float seconds.

``Time()`` is time zero, which tf2 lookups read as "the latest common time".

The stamp conversions every layer above uses live here too, on
``builtin_interfaces/Time``-like objects (``sec``, ``nanosec``): :func:`stamp_to_ns`,
:func:`stamp_from_ns`, :func:`stamp_to_seconds` and :func:`stamp_from_seconds`.
"""

from __future__ import annotations

import enum
from typing import Any, overload

from posekit.msgs import builtin_interfaces

__all__ = [
    "NS_PER_S",
    "ClockType",
    "Duration",
    "Time",
    "stamp_from_ns",
    "stamp_from_seconds",
    "stamp_to_ns",
    "stamp_to_seconds",
]

#: Nanoseconds per second.
NS_PER_S = 1_000_000_000
_NS_PER_S = NS_PER_S


def stamp_to_ns(stamp: Any) -> int:
    """Nanoseconds of a ``builtin_interfaces/Time``-like object (``sec``, ``nanosec``)."""
    return int(stamp.sec) * _NS_PER_S + int(stamp.nanosec)


def stamp_from_ns(ns: int) -> builtin_interfaces.Time:
    """``builtin_interfaces/Time`` of ``ns`` nanoseconds (``sec, nanosec = divmod(ns, 1e9)``)."""
    sec, nanosec = divmod(int(ns), _NS_PER_S)
    return builtin_interfaces.Time(sec, nanosec)  # positional: 2x faster than keywords


def stamp_to_seconds(stamp: Any) -> float:
    """Seconds (float) of a ``builtin_interfaces/Time``-like object: ``sec + 1e-9 * nanosec``.

    A double keeps nanoseconds below about 100 days (simulated time); a wall-clock stamp
    (seconds since 1970) keeps about 0.2 us. Compare or subtract stamps with
    :func:`stamp_to_ns`.
    """
    return float(stamp.sec) + 1e-9 * float(stamp.nanosec)


def stamp_from_seconds(t: float) -> builtin_interfaces.Time:
    """``builtin_interfaces/Time`` of ``t`` seconds, rounded to the nearest nanosecond.

    Raises:
        ValueError: ``t`` is negative (a stamp is a time since the clock's epoch).
    """
    ns = round(t * _NS_PER_S)
    if ns < 0:
        raise ValueError(f"a stamp cannot be negative, got {t} s")
    sec, nanosec = divmod(ns, _NS_PER_S)
    return builtin_interfaces.Time(sec, nanosec)


class ClockType(enum.IntEnum):
    """Which clock a Time was read from (values as rcl's ``rcl_clock_type_t``)."""

    UNINITIALIZED = 0
    ROS_TIME = 1
    SYSTEM_TIME = 2
    STEADY_TIME = 3


def _to_ns(seconds: float | int, nanoseconds: int) -> int:
    if isinstance(seconds, int):
        return seconds * _NS_PER_S + int(nanoseconds)
    # Split off whole seconds first so large float stamps do not lose nanoseconds.
    whole = int(seconds)
    return whole * _NS_PER_S + round((seconds - whole) * _NS_PER_S) + int(nanoseconds)


#: rcl's limits: a time point or duration is a signed 64-bit count of nanoseconds.
_NS_LIMIT = 2**63
#: rmw's infinite duration (RMW_DURATION_INFINITE); ``str()`` of it is ``'Infinite'``.
_INFINITE_NS = _NS_LIMIT - 1


class Duration:
    """A signed span of time in integer nanoseconds (rclpy.duration.Duration, Jazzy).

    As in Jazzy it has no arithmetic of its own (``Duration + Duration``, ``-d``, ``d * 2``
    raise TypeError: use ``Duration(nanoseconds=a.nanoseconds + b.nanoseconds)``); it takes
    part in :class:`Time` arithmetic (``t + d``, ``t - d``, ``t2 - t1``), compares with
    other durations and is unhashable. Fractions of ``seconds`` are rounded to the nearest
    nanosecond (rclpy truncates ``seconds * 1e9``, which can lose one).
    """

    __slots__ = ("_ns",)

    def __init__(self, *, seconds: float | int = 0, nanoseconds: int = 0) -> None:
        ns = _to_ns(seconds, nanoseconds)
        if not -_NS_LIMIT <= ns < _NS_LIMIT:
            raise OverflowError("Total nanoseconds value is too large to store in C duration.")
        self._ns = ns

    @property
    def nanoseconds(self) -> int:
        """The span in nanoseconds."""
        return self._ns

    def to_seconds(self) -> float:
        """The span in seconds (float; for display; posekit's, not in rclpy)."""
        return self._ns / _NS_PER_S

    def to_msg(self) -> builtin_interfaces.Duration:
        """As builtin_interfaces/Duration (sec floored, nanosec in [0, 1e9))."""
        sec, nanosec = divmod(self._ns, _NS_PER_S)
        return builtin_interfaces.Duration(sec=sec, nanosec=nanosec)

    @classmethod
    def from_msg(cls, msg: Any) -> Duration:
        """From a builtin_interfaces/Duration (any object with ``sec`` and ``nanosec``)."""
        if not (hasattr(msg, "sec") and hasattr(msg, "nanosec")):
            raise TypeError("Must pass a builtin_interfaces.msg.Duration object")
        return cls(seconds=int(msg.sec), nanoseconds=int(msg.nanosec))

    def __repr__(self) -> str:
        return f"Duration(nanoseconds={self._ns})"

    def __str__(self) -> str:
        if self._ns == _INFINITE_NS:
            return "Infinite"
        return f"{self._ns} nanoseconds"

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Duration):
            return self._ns == other._ns
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]  # as Jazzy's: defines __eq__, no __hash__

    def __lt__(self, other: Duration) -> bool:
        if not isinstance(other, Duration):
            return NotImplemented
        return self._ns < other._ns

    def __le__(self, other: Duration) -> bool:
        if not isinstance(other, Duration):
            return NotImplemented
        return self._ns <= other._ns

    def __gt__(self, other: Duration) -> bool:
        if not isinstance(other, Duration):
            return NotImplemented
        return self._ns > other._ns

    def __ge__(self, other: Duration) -> bool:
        if not isinstance(other, Duration):
            return NotImplemented
        return self._ns >= other._ns


class Time:
    """A point in time in integer nanoseconds (rclpy.time.Time, Jazzy). Never negative.

    As in Jazzy: ``t + d`` and ``t - d`` (a :class:`Duration`) give a Time, ``t2 - t1`` a
    Duration; times of different clock types neither compare nor subtract (TypeError); a
    Time is unhashable (key dictionaries by ``t.nanoseconds``); values outside a signed 64-bit
    nanosecond count raise OverflowError.
    """

    __slots__ = ("_clock_type", "_ns")

    def __init__(
        self,
        *,
        seconds: float | int = 0,
        nanoseconds: int = 0,
        clock_type: ClockType = ClockType.SYSTEM_TIME,
    ) -> None:
        # Enum checks by isinstance are slow; lecture code builds Time() for every lookup
        if type(clock_type) is not ClockType:
            raise TypeError("Clock type must be a ClockType enum")
        if seconds or type(nanoseconds) is not int:
            if seconds < 0:
                raise ValueError("Seconds value must not be negative")
            if nanoseconds < 0:
                raise ValueError("Nanoseconds value must not be negative")
            ns = _to_ns(seconds, nanoseconds)
        else:
            ns = nanoseconds
            if ns < 0:
                raise ValueError("Nanoseconds value must not be negative")
        if ns >= _NS_LIMIT:
            raise OverflowError("Total nanoseconds value is too large to store in C time point.")
        self._ns = ns
        self._clock_type = clock_type

    @classmethod
    def _of(cls, ns: int, clock_type: ClockType) -> Time:
        """A Time of ``ns`` (checked by the caller: 0 <= ns < 2**63) without the checks."""
        t = cls.__new__(cls)
        t._ns = ns
        t._clock_type = clock_type
        return t

    @property
    def nanoseconds(self) -> int:
        """Nanoseconds since the clock's epoch."""
        return self._ns

    @property
    def clock_type(self) -> ClockType:
        """The clock this time belongs to."""
        return self._clock_type

    def seconds_nanoseconds(self) -> tuple[int, int]:
        """Whole seconds and the remaining nanoseconds."""
        return divmod(self._ns, _NS_PER_S)

    def to_msg(self) -> builtin_interfaces.Time:
        """As builtin_interfaces/Time."""
        sec, nanosec = divmod(self._ns, _NS_PER_S)
        return builtin_interfaces.Time(sec=sec, nanosec=nanosec)

    @classmethod
    def from_msg(cls, msg: Any, clock_type: ClockType = ClockType.ROS_TIME) -> Time:
        """From a builtin_interfaces/Time (any object with ``sec`` and ``nanosec``).

        rclpy's default clock type here is ROS_TIME.
        """
        if not (hasattr(msg, "sec") and hasattr(msg, "nanosec")):
            raise TypeError("Must pass a builtin_interfaces.msg.Time object")
        return cls(seconds=int(msg.sec), nanoseconds=int(msg.nanosec), clock_type=clock_type)

    def __repr__(self) -> str:
        return f"Time(nanoseconds={self._ns}, clock_type={self._clock_type.name})"

    def _check(self, other: Time) -> None:
        if self._clock_type != other._clock_type:
            raise TypeError("Can't compare times with different clock types")

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Time):
            self._check(other)
            return self._ns == other._ns
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]  # as Jazzy's: defines __eq__, no __hash__

    def __lt__(self, other: Time) -> bool:
        if not isinstance(other, Time):
            return NotImplemented
        self._check(other)
        return self._ns < other._ns

    def __le__(self, other: Time) -> bool:
        if not isinstance(other, Time):
            return NotImplemented
        self._check(other)
        return self._ns <= other._ns

    def __gt__(self, other: Time) -> bool:
        if not isinstance(other, Time):
            return NotImplemented
        self._check(other)
        return self._ns > other._ns

    def __ge__(self, other: Time) -> bool:
        if not isinstance(other, Time):
            return NotImplemented
        self._check(other)
        return self._ns >= other._ns

    def __add__(self, other: Duration) -> Time:
        if isinstance(other, Duration):
            ns = self._ns + other.nanoseconds
            if ns >= _NS_LIMIT:
                raise OverflowError("Addition leads to overflow in C storage.")
            if ns < 0:
                raise ValueError("Nanoseconds value must not be negative")
            return Time._of(ns, self._clock_type)
        return NotImplemented

    __radd__ = __add__

    @overload
    def __sub__(self, other: Time) -> Duration: ...
    @overload
    def __sub__(self, other: Duration) -> Time: ...
    def __sub__(self, other: Time | Duration) -> Time | Duration:
        if isinstance(other, Time):
            if self._clock_type != other._clock_type:
                raise TypeError("Can't subtract times with different clock types")
            return Duration(nanoseconds=self._ns - other._ns)
        if isinstance(other, Duration):
            ns = self._ns - other.nanoseconds
            if ns < 0:
                raise ValueError("Subtraction leads to negative time.")
            if ns >= _NS_LIMIT:
                raise OverflowError(
                    "Total nanoseconds value is too large to store in C time point.")
            return Time._of(ns, self._clock_type)
        return NotImplemented
