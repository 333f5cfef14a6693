"""Deferred import of numpy, so ``import posekit.geometry`` stays cheap.

The single-item path (plain floats) never touches numpy; the first array operation loads it.
After that first access the module object *is* numpy (``importlib.util.LazyLoader`` swaps
its class), so later attribute lookups cost nothing extra.
"""

from __future__ import annotations

import importlib.util
import sys
from types import ModuleType

__all__ = ["lazy_module"]


def lazy_module(name: str) -> ModuleType:
    """Return ``sys.modules[name]`` if loaded, else a module that loads on first attribute use."""
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.find_spec(name)
    if spec is None or spec.loader is None:
        raise ImportError(f"cannot find module {name!r}")
    loader = importlib.util.LazyLoader(spec.loader)
    spec.loader = loader
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    loader.exec_module(module)
    return module
