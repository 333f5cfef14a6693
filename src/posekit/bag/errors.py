"""Exceptions raised by :mod:`posekit.bag` (each message names the bag and the reason)."""

from __future__ import annotations

__all__ = [
    "BagError",
    "BagExistsError",
    "BagFormatError",
    "BagNotFoundError",
    "BagOptionError",
]


class BagError(Exception):
    """Base class of every bag error."""


class BagNotFoundError(BagError, FileNotFoundError):
    """The bag directory (or its ``metadata.yaml``) does not exist."""


class BagExistsError(BagError, FileExistsError):
    """The output directory of a recording exists already (bags are never overwritten)."""


class BagFormatError(BagError):
    """The bag exists but cannot be read.

    Corrupted or truncated storage file, invalid ``metadata.yaml``, unsupported version, storage
    plugin or serialization format.
    """


class BagOptionError(BagError, ValueError):
    """An invalid recording or playback option (metadata version, rate, topic name...)."""
