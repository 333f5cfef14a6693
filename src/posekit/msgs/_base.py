"""Shared helpers for the message dataclasses."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["array_aware_eq"]


def array_aware_eq(self: Any, other: object) -> bool:
    """Field-wise equality that compares numpy array fields by value (``np.array_equal``)."""
    if type(other) is not type(self):
        return NotImplemented
    for name in self.__dataclass_fields__:
        a, b = getattr(self, name), getattr(other, name)
        if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
            if not np.array_equal(a, b):
                return False
        elif a != b:
            return False
    return True
