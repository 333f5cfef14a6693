"""tf2's exception hierarchy (``tf2/exceptions.h`` and the ``tf2_py`` classes).

Python's tf2 surfaces six classes: :class:`TransformException` and its direct subclasses
:class:`ConnectivityException`, :class:`LookupException`, :class:`ExtrapolationException`,
:class:`InvalidArgumentException` and :class:`TimeoutException`. posekit also keeps the C++
refinements of extrapolation (:class:`ForwardExtrapolationException`,
:class:`BackwardExtrapolationException`, :class:`NoDataForExtrapolationException`) as
subclasses of :class:`ExtrapolationException`, so ``except ExtrapolationException`` code
written for ROS 2 catches them unchanged. The message is ``str(exc)``.
"""

from __future__ import annotations

__all__ = [
    "BackwardExtrapolationException",
    "ConnectivityException",
    "ExtrapolationException",
    "ForwardExtrapolationException",
    "InvalidArgumentException",
    "LookupException",
    "NoDataForExtrapolationException",
    "TimeoutException",
    "TransformException",
    "TypeException",
]


class TransformException(Exception):  # noqa: N818 - tf2's name
    """Base class of every tf2 lookup failure."""


class ConnectivityException(TransformException):
    """The two frames exist but are not part of the same tree (at the requested time)."""


class LookupException(TransformException):
    """A frame name is unknown, or the tree contains a loop (more than 1000 edges)."""


class ExtrapolationException(TransformException):
    """An edge has no data at the requested time; tf2 never extrapolates."""


class BackwardExtrapolationException(ExtrapolationException):
    """The requested time is older than the oldest sample of an edge."""


class ForwardExtrapolationException(ExtrapolationException):
    """The requested time is newer than the newest sample of an edge."""


class NoDataForExtrapolationException(ExtrapolationException):
    """An edge holds zero samples, or one sample at a different stamp."""


class InvalidArgumentException(TransformException):
    """A frame name is empty or starts with '/'."""


class TimeoutException(TransformException):
    """Only for explicit waits; ``Buffer.lookup_transform`` never raises it (as tf2_ros)."""


class TypeException(Exception):  # noqa: N818 - tf2_ros's name
    """``Buffer.transform`` got an object type with no registered transform function (tf2_ros)."""
