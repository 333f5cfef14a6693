"""Shared helpers for the message dataclasses."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

__all__ = ["array_aware_eq"]


def array_aware_eq(lhs: Any, other: object) -> bool:
    """Field-wise equality that compares numpy array fields by value (``np.array_equal``)."""
    if type(other) is not type(lhs):
        result: bool = NotImplemented
        return result
    for f in dataclasses.fields(lhs):  # type: ignore[arg-type]
        a, b = getattr(lhs, f.name), getattr(other, f.name)
        if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
            if not np.array_equal(a, b):
                return False
        elif a != b:
            return False
    return True
