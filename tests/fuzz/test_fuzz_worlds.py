"""Bounded, seeded fuzzer: world files (the simulator's input) with mutated structure, values
and bytes.

Oracle: the loader's contract in posekit.worlds: every input either loads into a World
whose cameras respect the documented limits, or raises WorldError (a ValueError naming the
world and the field); nothing else, and no input takes memory proportional to its numbers.
"""

from __future__ import annotations

import copy
import json
import math
import random
from pathlib import Path
from typing import Any

from posekit.worlds import (
    MAX_CAMERA_PIXELS,
    MAX_CAMERA_RATE_HZ,
    WORLDS,
    World,
    WorldError,
    load_world,
)

ODD_VALUES: list[Any] = [None, True, -1, 0, 1e308, -1e308, math.nan, math.inf, 2**70, "",
                         "x" * 1000, [], {}, [1] * 7, {"x": 1}, 100_000, 10**9, -0.0]


def _paths(obj: Any, prefix: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    out = [prefix]
    if isinstance(obj, dict):
        for k, v in obj.items():
            out += _paths(v, (*prefix, k))
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            out += _paths(v, (*prefix, i))
    return out


def _mutate(rng: random.Random, data: dict[str, Any]) -> Any:
    data = copy.deepcopy(data)
    for _ in range(rng.randint(1, 3)):
        path = rng.choice(_paths(data)[1:])
        parent = data
        for key in path[:-1]:
            parent = parent[key]
        action = rng.randrange(3)
        if action == 0 and isinstance(parent, dict):
            del parent[path[-1]]
        elif action == 1 and isinstance(parent, list):
            parent.append(copy.deepcopy(parent[path[-1]]))  # duplicates
        else:
            parent[path[-1]] = copy.deepcopy(rng.choice(ODD_VALUES))
    return data


def _check(world: World) -> None:
    for cam in world.cameras:
        assert cam.width * cam.height <= MAX_CAMERA_PIXELS
        assert 0 < cam.rate_hz <= MAX_CAMERA_RATE_HZ


def test_mutated_world_data_loads_or_raises_world_error() -> None:
    rng = random.Random(31)
    seeds = [w.to_dict() for w in WORLDS.values()]
    loaded = refused = 0
    for i in range(1500):
        data = _mutate(rng, seeds[i % len(seeds)])
        try:
            world = World.from_dict(data, source=f"fuzz {i}")
        except WorldError:
            refused += 1
            continue
        _check(world)
        loaded += 1
    assert loaded > 0
    assert refused > 0


def test_mutated_world_file_bytes_load_or_raise_world_error(tmp_path: Path) -> None:
    rng = random.Random(32)
    text = json.dumps(WORLDS["aruco_box_camera_world"].to_dict()).encode()
    refused = 0
    for i in range(300):
        buf = bytearray(text)
        for _ in range(rng.randint(1, 5)):
            buf[rng.randrange(len(buf))] = rng.randrange(256)
        path = tmp_path / f"w{i}.{'json' if i % 2 else 'yaml'}"
        path.write_bytes(bytes(buf[: rng.randint(1, len(buf))]))
        try:
            _check(load_world(path))
        except WorldError:
            refused += 1
    assert refused > 0
