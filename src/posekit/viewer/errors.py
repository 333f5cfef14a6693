"""Errors of the viewer."""

from __future__ import annotations

__all__ = ["ViewerError", "ViewerOptionError"]


class ViewerError(RuntimeError):
    """The viewer cannot start or serve (address in use, missing dependency, bad option)."""


class ViewerOptionError(ViewerError, ValueError):
    """A viewer option is out of range (a port, a rate, a quality); the text says which."""
