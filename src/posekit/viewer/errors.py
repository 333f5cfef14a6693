"""Errors of the viewer."""

from __future__ import annotations

__all__ = ["ViewerError"]


class ViewerError(RuntimeError):
    """The viewer cannot start or serve (address in use, missing dependency, bad option)."""
