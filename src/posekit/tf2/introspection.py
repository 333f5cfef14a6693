"""tf2's text dumps of the frame tree, byte for byte (ROS 2).

* :func:`frames_as_string` - ``allFramesAsString``;
* :func:`frames_as_yaml` - ``allFramesAsYAML`` (what ``Buffer.all_frames_as_yaml`` returns and
  the ``tf2_frames`` service serves);
* :func:`frames_as_dot_core` - ``BufferCore::_allFramesAsDot``;
* :func:`view_frames_dot` - the graph tf2_tools' ``view_frames`` writes (its ``generate_dot``
  applied to the YAML dump), used by ``Buffer.to_dot``.

The functions read the core's tables (names by id, caches by id, authorities by id); the
caller holds the buffer lock.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from posekit.tf2.time_cache import display_time

__all__ = ["frames_as_dot_core", "frames_as_string", "frames_as_yaml", "view_frames_dot"]

_NO_AUTHORITY = "no recorded authority"


def _duration_s(ns: int) -> float:
    """tf2 ``durationToSec``: whole and fractional seconds scaled separately (C truncation)."""
    nsec = ns % 1_000_000_000 if ns >= 0 else -((-ns) % 1_000_000_000)
    return float((ns - nsec) // 1_000_000_000) + 1e-9 * float(nsec)


def _rate(cache: Any) -> float:
    span = cache.latest_stamp() - cache.oldest_stamp()
    return (len(cache) * 1e9) / float(span if span > 100_000 else 100_000)


def frames_as_string(names: Sequence[str], caches: Sequence[Any]) -> str:
    """``Frame <child> exists with parent <parent>.`` per frame with a cache, in id order."""
    lines = []
    for fid in range(1, len(caches)):
        cache = caches[fid]
        if cache is None:
            continue
        parent = cache.latest_time_and_parent()[1] if len(cache) else 0
        lines.append(f"Frame {names[fid]} exists with parent {names[parent]}.\n")
    return "".join(lines)


def _yaml_entries(
    names: Sequence[str], caches: Sequence[Any], authority: dict[int, str]
) -> list[tuple[str, str, str, Any]]:
    out = []
    for fid in range(1, len(caches)):
        cache = caches[fid]
        if cache is None or not len(cache):
            continue
        parent = cache.latest_time_and_parent()[1]
        out.append((names[fid], names[parent], authority.get(fid, _NO_AUTHORITY), cache))
    return out


def frames_as_yaml(
    names: Sequence[str], caches: Sequence[Any], authority: dict[int, str], current_time_ns: int = 0
) -> str:
    """tf2 ``allFramesAsYAML(current_time)``: ``[]`` when no frame was ever registered."""
    parts = ["[]"] if len(caches) == 1 else []
    for child, parent, auth, cache in _yaml_entries(names, caches, authority):
        newest = cache.latest_stamp()
        oldest = cache.oldest_stamp()
        parts.append(
            f"{child}: \n"
            f"  parent: '{parent}'\n"
            f"  broadcaster: '{auth}'\n"
            f"  rate: {_rate(cache):.3f}\n"
            f"  most_recent_transform: {display_time(newest)}\n"
            f"  oldest_transform: {display_time(oldest)}\n"
        )
        if current_time_ns != 0:
            parts.append(f"  transform_delay: {_duration_s(current_time_ns - newest):.3f}\n")
        parts.append(f"  buffer_length: {_duration_s(newest - oldest):.3f}\n")
    return "".join(parts)


def frames_as_dot_core(
    names: Sequence[str], caches: Sequence[Any], authority: dict[int, str], current_time_ns: int = 0
) -> str:
    """tf2 ``_allFramesAsDot(current_time)`` (the core's own dot text, with tf2's typo)."""
    parts = ["digraph G {\n"]
    if len(caches) == 1:
        parts.append('"no tf data recieved"')
    for child, parent, auth, cache in _yaml_entries(names, caches, authority):
        newest = cache.latest_stamp()
        oldest = cache.oldest_stamp()
        parts.append(
            f'"{parent}" -> "{child}"[label="Broadcaster: {auth}\\n'
            f"Average rate: {_rate(cache):.3f} Hz\\n"
            f"Most recent transform: {display_time(newest)} "
        )
        if current_time_ns != 0:
            parts.append(f"( {_duration_s(current_time_ns - newest):.3f} sec old)")
        parts.append(f'\\nBuffer length: {_duration_s(newest - oldest):.3f} sec\\n"];\n')
    legend = ' subgraph cluster_legend { style=bold; color=black; label ="view_frames Result";\n'
    recorded = (
        f'"Recorded at time: {display_time(current_time_ns)}"[ shape=plaintext ] ;\n '
        if current_time_ns != 0
        else ""
    )
    for fid in range(1, len(caches)):
        cache = caches[fid]
        if cache is None:
            if current_time_ns != 0:
                parts.append(f'edge [style=invis];\n{legend}{recorded}}}->"{names[fid]}";\n')
            continue
        if not len(cache):  # parent NO_PARENT
            parts.append(f'edge [style=invis];\n{legend}{recorded}}}->"{names[fid]}";\n')
    parts.append("}")
    return "".join(parts)


def _yaml_scalar(text: str) -> str:
    """``str()`` of what ``yaml.safe_load`` makes of one of our numeric fields."""
    return str(float(text))


def view_frames_dot(yaml_text: str, recorded_time: tuple[int, int]) -> str:
    """tf2_tools ``view_frames.generate_dot(yaml.safe_load(yaml_text), (sec, nsec))``.

    Returns ``digraph G { "No tf data received" }`` for ``[]`` and ``""`` when the YAML is
    empty (view_frames then crashes inside a swallowed exception and leaves an empty file).
    """
    if yaml_text.strip() == "[]":
        return 'digraph G { "No tf data received" }'
    if not yaml_text:
        return ""
    frames: dict[str, dict[str, str]] = {}
    current: dict[str, str] = {}
    for line in yaml_text.splitlines():
        if not line.startswith("  "):
            current = {}
            frames[line[:-2] if line.endswith(": ") else line.rstrip(":")] = current
            continue
        key, _, value = line.strip().partition(": ")
        current[key] = value[1:-1] if value.startswith("'") else _yaml_scalar(value)
    dot = ["digraph G {\n"]
    root = None
    for child, fields in frames.items():
        dot.append(
            f'"{fields["parent"]}" -> "{child}"[label=" '
            f"Broadcaster: {fields['broadcaster']}\\n"
            f"Average rate: {fields['rate']}\\n"
            f"Buffer length: {fields['buffer_length']}\\n"
            f"Most recent transform: {fields['most_recent_transform']}\\n"
            f"Oldest transform: {fields['oldest_transform']}\\n"
            '"];\n'
        )
        if fields["parent"] not in frames:
            root = fields["parent"]
    if root is None:  # every parent is also a child (a loop): view_frames would crash here
        root = next(iter(frames.values()))["parent"]
    dot.append("edge [style=invis];\n")
    dot.append(' subgraph cluster_legend { style=bold; color=black; label ="view_frames Result";\n')
    dot.append(
        f'"Recorded at time: {recorded_time[0] + recorded_time[1] / 1e9}"[ shape=plaintext ] ;\n'
    )
    dot.append(f'}}->"{root}";\n}}')
    return "".join(dot)
