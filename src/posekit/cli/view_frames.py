"""``posekit tf frames`` (view_frames) and ``posekit tf tree`` (what rqt_tf_tree shows).

view_frames listens for a few seconds, reads ``all_frames_as_yaml()`` and writes
``frames_<YYYY-MM-DD_HH.MM.SS>.gv`` and, through Graphviz's ``dot``, the ``.pdf``.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import time
from collections.abc import Sequence
from typing import Any, TextIO

from posekit.cli._session import add_sim_time_args, add_transport_option, transport_option

__all__ = ["generate_dot", "main", "main_tree", "parse_frames_yaml", "render_tree"]


def _scalar(text: str) -> float | str:
    text = text.strip()
    if len(text) >= 2 and text[0] == text[-1] == "'":
        return text[1:-1].replace("''", "'")
    try:
        return float(text)
    except ValueError:
        return text


def parse_frames_yaml(text: str) -> dict[str, dict[str, float | str]]:
    """Parse tf2's ``all_frames_as_yaml`` (a fixed two-level layout) like ``yaml.safe_load``."""
    frames: dict[str, dict[str, float | str]] = {}
    current: dict[str, float | str] | None = None
    for line in text.splitlines():
        if not line.strip() or line.strip() == "[]":
            continue
        if not line.startswith(" "):
            current = {}
            frames[line.rstrip().rstrip(":")] = current
        elif current is not None:
            key, _, value = line.strip().partition(":")
            current[key] = _scalar(value)
    return frames


def generate_dot(frames: dict[str, dict[str, float | str]], recorded_at: tuple[int, int]) -> str:
    """view_frames' dot text for parsed frames, recorded at ``(sec, nanosec)``."""
    if not frames:
        return 'digraph G { "No tf data received" }'
    out = ["digraph G {\n"]
    for child, data in frames.items():
        out.append(
            f'"{data["parent"]}" -> "{child}"[label=" Broadcaster: {data["broadcaster"]}'
            f'\\nAverage rate: {data["rate"]}\\nBuffer length: {data["buffer_length"]}'
            f'\\nMost recent transform: {data["most_recent_transform"]}'
            f'\\nOldest transform: {data["oldest_transform"]}\\n"];\n'
        )
    root = ""
    for data in frames.values():
        if data["parent"] not in frames:
            root = str(data["parent"])
    sec, nsec = recorded_at
    out.append(
        "edge [style=invis];\n"
        ' subgraph cluster_legend { style=bold; color=black; label ="view_frames Result";\n'
        f'"Recorded at time: {sec + nsec / 1e9}"[ shape=plaintext ] ;\n'
        f'}}->"{root}";\n}}'
    )
    return "".join(out)


def render_tree(frames: dict[str, dict[str, float | str]], now_s: float) -> str:
    """The frame tree as indented text: each frame with its parent link, rate and update age."""
    children: dict[str, list[str]] = {}
    for child, data in frames.items():
        children.setdefault(str(data["parent"]), []).append(child)
    roots = sorted(p for p in children if p not in frames)
    lines: list[str] = []

    def visit(frame: str, depth: int) -> None:
        data = frames.get(frame)
        if data is None:
            lines.append(f"{'  ' * depth}{frame}")
        else:
            newest = float(data["most_recent_transform"])
            age = "static" if newest == 0.0 else f"{max(0.0, now_s - newest):.3f} s ago"
            lines.append(f"{'  ' * depth}{frame}  [{data['broadcaster']}, "
                         f"{float(data['rate']):.1f} Hz, {age}]")
        for child in sorted(children.get(frame, [])):
            visit(child, depth + 1)

    for root in roots:
        visit(root, 0)
    return "\n".join(lines) + ("\n" if lines else "No tf data received\n")


def _collect(wait_s: float, context: Any, transport: str | None,
             use_sim_time: bool | None = None) -> tuple[str, Any]:
    """tf2's frames YAML after ``wait_s`` s of listening, and "now" on the tool's clock.

    The tool's clock shows the simulation's time when one publishes /clock (see
    ToolSession.follow_sim_time).
    """
    from posekit.cli._session import ToolSession
    from posekit.tf2 import Buffer

    with ToolSession("view_frames", context=context, transport=transport) as session:
        session.follow_sim_time(use_sim_time)
        buffer = Buffer()
        session.listen_tf(buffer)
        session.node.get_logger().info(f"Listening to tf data for {wait_s} seconds...")
        session.spin_for(wait_s)
        now = session.node.get_clock().now()
        return buffer.all_frames_as_yaml(), now


def main(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None) -> int:
    """view_frames: ``[-t/--wait-time S] [-o/--output NAME]``."""
    out = out or sys.stdout
    parser = argparse.ArgumentParser(prog="posekit tf frames")
    parser.add_argument("-t", "--wait-time", type=float, default=5.0)
    parser.add_argument("-o", "--output", default=None)
    add_transport_option(parser)
    add_sim_time_args(parser)
    ns = parser.parse_args(list(argv))
    yaml_text, now = _collect(ns.wait_time, context, transport_option(ns), ns.use_sim_time)
    name = ns.output or time.strftime("frames_%Y-%m-%d_%H.%M.%S")
    dot_text = generate_dot(parse_frames_yaml(yaml_text), now.seconds_nanoseconds())
    gv_path, pdf_path = f"{name}.gv", f"{name}.pdf"
    with open(gv_path, "w", encoding="utf-8") as f:
        f.write(dot_text)
    dot = shutil.which("dot")
    if dot is None:
        out.write(f"Wrote {gv_path}; Graphviz 'dot' was not found, so no {pdf_path} "
                  f"(install graphviz, then: dot -Tpdf {gv_path} -o {pdf_path})\n")
        return 0
    subprocess.run([dot, "-Tpdf", gv_path, "-o", pdf_path], check=True)
    out.write(f"Wrote {gv_path} and {pdf_path}\n")
    return 0


def main_tree(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None) -> int:
    """Print the frame tree after listening ``-t`` seconds (default 2)."""
    out = out or sys.stdout
    parser = argparse.ArgumentParser(prog="posekit tf tree")
    parser.add_argument("-t", "--wait-time", type=float, default=2.0)
    add_transport_option(parser)
    add_sim_time_args(parser)
    ns = parser.parse_args(list(argv))
    yaml_text, now = _collect(ns.wait_time, context, transport_option(ns), ns.use_sim_time)
    out.write(render_tree(parse_frames_yaml(yaml_text), now.nanoseconds / 1e9))
    return 0
