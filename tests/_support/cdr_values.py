"""Random message values for CDR tests, from a rosbags typestore's field definitions."""

from __future__ import annotations

import random
from typing import Any

import numpy as np
from rosbags.interfaces import Nodetype

__all__ = ["build_message", "random_values"]

INT_RANGES = {
    "int8": (-(2**7), 2**7 - 1),
    "uint8": (0, 2**8 - 1),
    "byte": (-(2**7), 2**7 - 1),  # rosbags packs byte as a signed char
    "char": (0, 2**8 - 1),
    "int16": (-(2**15), 2**15 - 1),
    "uint16": (0, 2**16 - 1),
    "int32": (-(2**31), 2**31 - 1),
    "uint32": (0, 2**32 - 1),
    "int64": (-(2**63), 2**63 - 1),
    "uint64": (0, 2**64 - 1),
}
TEXTS = ["", "odom", "base_link", "kamera_vorn_ü", "相机/光学", "🤖 rosbot", "x" * 300]


def _scalar(rng: random.Random, base: str) -> Any:
    if base == "bool":
        return rng.random() < 0.5
    if base in ("float32", "float64"):
        v = rng.choice([0.0, -0.0, 1.5, -2.25, float("inf"), rng.uniform(-1e6, 1e6)])
        return float(np.float32(v)) if base == "float32" else v
    if base == "string":
        return rng.choice(TEXTS)
    lo, hi = INT_RANGES[base]
    return rng.choice([lo, hi, 0, rng.randint(lo, hi)])


def _dtype(base: str) -> np.dtype[Any]:
    return np.dtype({"bool": "bool", "char": "uint8", "byte": "uint8"}.get(base, base))


def random_values(rng: random.Random, store: Any, typename: str, big: bool) -> dict[str, Any]:
    """A random value tree for ``typename`` (plain dicts/lists/arrays) from ``store``'s
    fielddefs; ``big``: some sequences of 2000 elements."""
    out: dict[str, Any] = {}
    for name, desc in store.fielddefs[typename][1]:
        kind = desc[0]
        if kind == Nodetype.BASE:
            out[name] = _scalar(rng, desc[1][0])
        elif kind == Nodetype.NAME:
            out[name] = ("msg", desc[1], random_values(rng, store, desc[1], big))
        else:
            (subkind, subinfo), count = desc[1]
            n = count if kind == Nodetype.ARRAY else rng.choice([0, 1, 3, 2000 if big else 7])
            if subkind == Nodetype.NAME:
                n = min(n, 300)
                out[name] = ("seq", subinfo,
                             [random_values(rng, store, subinfo, False) for _ in range(n)])
            elif subinfo[0] == "string":
                out[name] = [rng.choice(TEXTS) for _ in range(n)]
            else:
                dt = _dtype(subinfo[0])
                if dt.kind == "f":
                    arr = np.array([rng.uniform(-1e3, 1e3) for _ in range(n)], dtype=dt)
                elif dt.kind == "b":
                    arr = np.array([rng.random() < 0.5 for _ in range(n)], dtype=dt)
                else:
                    info = np.iinfo(dt)
                    arr = np.random.default_rng(rng.randint(0, 2**32)).integers(
                        info.min, info.max, size=n, dtype=dt, endpoint=True
                    )
                out[name] = arr
    return out


def build_message(tree: dict[str, Any], typename: str, classes: dict[str, Any]) -> Any:
    """The message of value ``tree`` built from ``classes`` (type name -> class)."""
    kwargs: dict[str, Any] = {}
    for name, val in tree.items():
        if isinstance(val, tuple) and val[0] == "msg":
            kwargs[name] = build_message(val[2], val[1], classes)
        elif isinstance(val, tuple) and val[0] == "seq":
            kwargs[name] = [build_message(v, val[1], classes) for v in val[2]]
        elif isinstance(val, np.ndarray):
            kwargs[name] = val.copy()
        elif isinstance(val, list):
            kwargs[name] = list(val)
        else:
            kwargs[name] = val
    return classes[typename](**kwargs)
