"""Exceptions raised by :mod:`posekit.worlds`."""

from __future__ import annotations

__all__ = ["WorldError"]


class WorldError(ValueError):
    """A world description (or a box model) is malformed; the message names the world and
    the field."""
