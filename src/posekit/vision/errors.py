"""Exceptions raised by :mod:`posekit.vision`."""

from __future__ import annotations

__all__ = ["CameraModelError", "InvalidImageError", "VisionError"]


class VisionError(Exception):
    """Base class of every error raised by :mod:`posekit.vision`."""


class InvalidImageError(VisionError, ValueError):
    """An image array is empty, has the wrong dtype, or the wrong shape / channel count."""


class CameraModelError(VisionError, ValueError):
    """Camera intrinsics or a camera pose are malformed (non-finite, non-positive, wrong shape)."""
