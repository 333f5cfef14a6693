"""Byte-exact dumps: frames as string, YAML, core dot and view_frames dot (docs/specs/tf2.md 8,
11.3)."""

from __future__ import annotations

import math

from posekit.msgs.geometry_msgs import TransformStamped
from posekit.tf2 import BufferCore
from posekit.time import Time

S = 1_000_000_000


def ts(parent: str, child: str, sec: float) -> TransformStamped:
    m = TransformStamped()
    m.header.frame_id = parent
    m.child_frame_id = child
    m.header.stamp.sec, m.header.stamp.nanosec = divmod(round(sec * S), S)
    return m


def tree() -> BufferCore:
    b = BufferCore()
    b.set_transform_static(ts("world", "map", 0), "static_pub")
    b.set_transform(ts("map", "odom", 1), "odom_node")
    b.set_transform(ts("map", "odom", 2), "odom_node")
    b.set_transform(ts("map", "odom", 3.5), "odom_node")
    return b


def test_empty_buffer_texts() -> None:
    b = BufferCore()
    assert b.all_frames_as_yaml() == "[]"
    assert b.all_frames_as_string() == ""
    assert b._allFramesAsDot() == 'digraph G {\n"no tf data recieved"}'
    assert b.to_dot(Time(seconds=1)) == 'digraph G { "No tf data received" }'


def test_yaml_exact() -> None:
    assert tree().all_frames_as_yaml() == (
        "map: \n"
        "  parent: 'world'\n"
        "  broadcaster: 'static_pub'\n"
        "  rate: 10000.000\n"
        "  most_recent_transform: 0.000000\n"
        "  oldest_transform: 0.000000\n"
        "  buffer_length: 0.000\n"
        "odom: \n"
        "  parent: 'map'\n"
        "  broadcaster: 'odom_node'\n"
        "  rate: 1.200\n"  # 3 samples / 2.5 s
        "  most_recent_transform: 3.500000\n"
        "  oldest_transform: 1.000000\n"
        "  buffer_length: 2.500\n"
    )


def test_yaml_transform_delay_only_with_current_time() -> None:
    text = tree().all_frames_as_yaml(Time(seconds=5))
    assert "  transform_delay: 1.500\n  buffer_length: 2.500\n" in text
    assert "  transform_delay: 5.000\n" in text  # static frame: now - 0


def test_yaml_single_sample_rate_uses_100us_floor() -> None:
    b = BufferCore()
    b.set_transform(ts("a", "b", 1), "n")
    b.set_transform(ts("a", "b", 1.00005), "n")  # 50 us apart: rate = 2 / 100 us
    assert "  rate: 20000.000\n" in b.all_frames_as_yaml()


def test_yaml_and_string_after_clear() -> None:
    b = BufferCore()
    b.set_transform(ts("a", "b", 1), "n")
    b.clear()
    assert b.all_frames_as_yaml() == ""
    assert b.all_frames_as_string() == "Frame b exists with parent NO_PARENT.\n"
    assert b._allFramesAsDot() == (
        "digraph G {\nedge [style=invis];\n subgraph cluster_legend { style=bold; color=black; "
        'label ="view_frames Result";\n}->"b";\n}'
    )
    assert b.to_dot(Time(seconds=1)) == ""


def test_no_recorded_authority_is_impossible_via_api_but_string_lists_roots_out() -> None:
    assert tree().all_frames_as_string() == (
        "Frame map exists with parent world.\nFrame odom exists with parent map.\n"
    )


def test_core_dot_exact() -> None:
    assert tree()._allFramesAsDot() == (
        "digraph G {\n"
        '"world" -> "map"[label="Broadcaster: static_pub\\nAverage rate: 10000.000 Hz\\n'
        'Most recent transform: 0.000000 \\nBuffer length: 0.000 sec\\n"];\n'
        '"map" -> "odom"[label="Broadcaster: odom_node\\nAverage rate: 1.200 Hz\\n'
        'Most recent transform: 3.500000 \\nBuffer length: 2.500 sec\\n"];\n'
        "}"
    )


def test_core_dot_with_time_marks_age_and_roots() -> None:
    text = tree()._allFramesAsDot(Time(seconds=4))
    assert "Most recent transform: 3.500000 ( 0.500 sec old)\\nBuffer length" in text
    assert text.endswith(
        "edge [style=invis];\n subgraph cluster_legend { style=bold; color=black; "
        'label ="view_frames Result";\n"Recorded at time: 4.000000"[ shape=plaintext ] ;\n '
        '}->"world";\n}'
    )


def test_view_frames_dot_exact() -> None:
    assert tree().to_dot(Time(seconds=12, nanoseconds=500_000_000)) == (
        "digraph G {\n"
        '"world" -> "map"[label=" Broadcaster: static_pub\\nAverage rate: 10000.0\\n'
        "Buffer length: 0.0\\nMost recent transform: 0.0\\nOldest transform: 0.0\\n"
        '"];\n'
        '"map" -> "odom"[label=" Broadcaster: odom_node\\nAverage rate: 1.2\\n'
        "Buffer length: 2.5\\nMost recent transform: 3.5\\nOldest transform: 1.0\\n"
        '"];\n'
        "edge [style=invis];\n"
        ' subgraph cluster_legend { style=bold; color=black; label ="view_frames Result";\n'
        '"Recorded at time: 12.5"[ shape=plaintext ] ;\n'
        '}->"world";\n}'
    )


def test_view_frames_legend_goes_to_last_root_only() -> None:
    b = tree()
    b.set_transform_static(ts("other_root", "x", 0), "n")
    assert tree().to_dot(Time(seconds=1)).endswith('}->"world";\n}')
    assert b.to_dot(Time(seconds=1)).endswith('}->"other_root";\n}')


def test_yaml_parses_with_pyyaml_like_lecture_code() -> None:
    yaml = __import__("pytest").importorskip("yaml")
    data = yaml.safe_load(tree().all_frames_as_yaml())
    assert data["odom"]["parent"] == "map"
    assert math.isclose(data["odom"]["most_recent_transform"], 3.5)
