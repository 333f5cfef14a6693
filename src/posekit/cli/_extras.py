"""Optional dependencies, checked before a command starts.

A missing one is ONE line naming the extra that installs it (``pip install 'posekit[plot]'``),
never a traceback at the end of a run. Nothing is imported to check
(``importlib.util.find_spec``).
"""

from __future__ import annotations

import importlib.util
from collections.abc import Iterable

__all__ = ["EXTRA_MODULES", "missing_extra", "require"]

#: The import names each extra of pyproject.toml provides (those a command needs at run time).
EXTRA_MODULES: dict[str, tuple[str, ...]] = {
    "plot": ("matplotlib",),
    "viewer": ("aiohttp", "cv2"),
    "vision": ("cv2",),
    "zenoh": ("zenoh", "rosbags"),
    "dds": ("cyclonedds", "rosbags"),
    "bag": ("rosbags", "mcap"),
    "foxglove": ("foxglove", "rosbags"),
}


def _installed(module: str) -> bool:
    try:
        return importlib.util.find_spec(module) is not None
    except (ImportError, ValueError):
        return False


def missing_extra(extra: str) -> list[str]:
    """The modules of ``extra`` that are not installed (empty: the extra is complete)."""
    return [m for m in EXTRA_MODULES.get(extra, ()) if not _installed(m)]


def require(command: str, needs: Iterable[tuple[str, str]]) -> str | None:
    """The first problem as one line, or None.

    ``needs``: ``(what, extra)`` pairs, e.g. ``("--plot", "plot")``; ``what`` names the option
    or the command that needs the extra.
    """
    for what, extra in needs:
        missing = missing_extra(extra)
        if missing:
            return (f"{command}: {what} needs {', '.join(missing)}, which is not installed: "
                    f"pip install 'posekit[{extra}]'")
    return None
