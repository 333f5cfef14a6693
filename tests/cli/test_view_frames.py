"""view_frames' dot text (docs/specs/tf2.md §11.3) and the terminal tree, from a real Buffer."""

import pytest

from posekit.cli.main import main as posekit_main
from posekit.cli.view_frames import generate_dot, parse_frames_yaml, render_tree
from posekit.msgs.geometry_msgs import TransformStamped
from posekit.tf2 import Buffer


def _tf(parent: str, child: str, sec: int, static: bool, buffer: Buffer) -> None:
    t = TransformStamped()
    t.header.frame_id = parent
    t.header.stamp.sec = sec
    t.child_frame_id = child
    if static:
        buffer.set_transform_static(t, "static_pub")
    else:
        buffer.set_transform(t, "odom_pub")


def test_dot_from_buffer_yaml_matches_view_frames_format() -> None:
    buffer = Buffer()
    _tf("map", "odom", 0, True, buffer)
    _tf("odom", "base_link", 10, False, buffer)
    _tf("odom", "base_link", 12, False, buffer)
    frames = parse_frames_yaml(buffer.all_frames_as_yaml())
    assert frames["base_link"]["rate"] == 1.0  # 2 samples over 2 s
    assert frames["odom"]["rate"] == 10000.0
    dot = generate_dot(frames, (5, 500_000_000))
    expected = (
        "digraph G {\n"
        '"map" -> "odom"[label=" Broadcaster: static_pub\\nAverage rate: 10000.0'
        "\\nBuffer length: 0.0\\nMost recent transform: 0.0\\nOldest transform: 0.0\\n\"];\n"
        '"odom" -> "base_link"[label=" Broadcaster: odom_pub\\nAverage rate: 1.0'
        "\\nBuffer length: 2.0\\nMost recent transform: 12.0\\nOldest transform: 10.0\\n\"];\n"
        "edge [style=invis];\n"
        ' subgraph cluster_legend { style=bold; color=black; label ="view_frames Result";\n'
        '"Recorded at time: 5.5"[ shape=plaintext ] ;\n'
        '}->"map";\n}'
    )
    assert dot == expected


def test_empty_dot() -> None:
    assert generate_dot(parse_frames_yaml(Buffer().all_frames_as_yaml()), (0, 0)) == (
        'digraph G { "No tf data received" }'
    )


def test_tree_lists_children_under_parents() -> None:
    buffer = Buffer()
    _tf("map", "odom", 0, True, buffer)
    _tf("odom", "base_link", 10, False, buffer)
    text = render_tree(parse_frames_yaml(buffer.all_frames_as_yaml()), now_s=11.0)
    assert text.splitlines() == [
        "map",
        "  odom  [static_pub, 10000.0 Hz, static]",
        "    base_link  [odom_pub, 10000.0 Hz, 1.000 s ago]",
    ]


def test_unknown_command_is_a_clear_error(capsys: pytest.CaptureFixture[str]) -> None:
    assert posekit_main(["nonsense"]) == 2
    assert "unknown command 'nonsense'" in capsys.readouterr().err
