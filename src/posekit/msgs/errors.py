"""Exceptions raised by :mod:`posekit.msgs` (every one carries a human-readable reason)."""

from __future__ import annotations

__all__ = [
    "CdrError",
    "ImageConversionError",
    "MessageError",
    "UnknownMessageTypeError",
]


class MessageError(ValueError):
    """Base class of every message-layer error."""


class UnknownMessageTypeError(MessageError, LookupError):
    """A message type name (``pkg/msg/Type``) or class that posekit cannot resolve."""


class CdrError(MessageError):
    """CDR bytes could not be produced from a message or decoded into one.

    Raised for truncated or corrupted input, a bad encapsulation header, invalid UTF-8 in a
    string, impossible sequence lengths, and for messages whose fields do not fit their ROS
    types (a negative ``uint32``, a covariance of the wrong length, ...).
    """


class ImageConversionError(MessageError):
    """An Image could not be converted to or from a numpy array (encoding, shape, size)."""
