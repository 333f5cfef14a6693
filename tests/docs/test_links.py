"""Links in README.md and docs/*.md lead somewhere: a relative link names a file or directory
of the repository, and a ``#fragment`` names a heading of its target document.

Oracle: the heading ids GitHub gives Markdown headings, written out here: the heading text
in lower case, every character that is not a letter, digit, ``_``, ``-`` or space removed
(so an en dash in "20:00–20:10" goes, and "20:00–20:10" becomes ``20002010``), spaces
turned into ``-``; a repeated id gets ``-1``, ``-2``... in order. Headings and links inside
fenced code blocks do not count.
"""

from __future__ import annotations

import re
from collections import Counter
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
DOCS = sorted([REPO / "README.md", *(REPO / "docs").glob("*.md")])
_FENCE = re.compile(r"^```.*?^```", re.S | re.M)
_HEADING = re.compile(r"^#{1,6} +(.+?) *$", re.M)
_LINK = re.compile(r"\]\((?P<target>[^)\s#]*)(?:#(?P<fragment>[^)\s]+))?\)")


def heading_id(text: str) -> str:
    """GitHub's id for a heading's text (before numbering repeats)."""
    return re.sub(r"[^\w\- ]", "", text.strip().lower()).replace(" ", "-")


def heading_ids(markdown: str) -> set[str]:
    ids: set[str] = set()
    seen: Counter[str] = Counter()
    for match in _HEADING.finditer(_FENCE.sub("", markdown)):
        base = heading_id(match[1])
        ids.add(base if not seen[base] else f"{base}-{seen[base]}")
        seen[base] += 1
    return ids


def test_heading_ids_follow_the_rule() -> None:
    text = "# A/B, and (2026-11-25, 20:00–20:10 UTC)\n## Same\n## Same\n```\n# not a heading\n```\n"
    assert heading_ids(text) == {"ab-and-2026-11-25-20002010-utc", "same", "same-1"}


@pytest.mark.parametrize("doc", DOCS, ids=lambda d: d.name)
def test_relative_links_and_fragments_resolve(doc: Path) -> None:
    text = doc.read_text(encoding="utf-8")
    broken = []
    for match in _LINK.finditer(_FENCE.sub("", text)):
        target, fragment = match["target"], match["fragment"]
        if re.match(r"[a-z]+:", target):  # http:, https:, mailto:
            continue
        path = (doc.parent / target).resolve() if target else doc
        if not path.exists():
            broken.append(f"{target} (no such file)")
            continue
        if fragment and path.suffix == ".md" and fragment not in heading_ids(
                path.read_text(encoding="utf-8")):
            broken.append(f"{target}#{fragment} (no such heading)")
    assert not broken, f"{doc.name}: " + "; ".join(broken)
