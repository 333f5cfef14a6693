"""bag_info / format_info against the recorded content, and clear errors for bad bags."""

from __future__ import annotations

import shutil
import time
from pathlib import Path
from typing import Any

import pytest
from mcap.reader import make_reader

from posekit.bag import (
    BagError,
    BagFormatError,
    BagNotFoundError,
    bag_info,
    format_info,
    read_messages,
)
from posekit.bag.info import format_size
from posekit.runtime.qos import DurabilityPolicy


def test_info_matches_what_was_recorded(recorded: Any, kit: Any) -> None:
    info = bag_info(recorded.path)
    mcap_path = next(recorded.path.glob("*.mcap"))
    assert info.version == 9
    assert info.storage_identifier == "mcap"
    assert info.files == [mcap_path.name]
    assert info.bag_size == mcap_path.stat().st_size
    assert info.start_ns == kit.START_NS
    assert info.end_ns == kit.START_NS + 1_000_000_000
    assert info.message_count == sum(recorded.counts.values())
    assert {t.name: t.message_count for t in info.topics} == recorded.counts
    assert info.topic("/tf").msgtype == "tf2_msgs/msg/TFMessage"
    assert info.chunk_compression == "zstd"
    static = info.topic("/tf_static").offered_qos
    assert [q.durability for q in static] == [DurabilityPolicy.TRANSIENT_LOCAL] * 2
    # mcap's own statistics agree on the count.
    with mcap_path.open("rb") as f:
        summary = make_reader(f).get_summary()
    assert summary is not None
    assert summary.statistics is not None
    assert summary.statistics.message_count == info.message_count
    with pytest.raises(KeyError, match="/nope"):
        info.topic("/nope")


def test_format_looks_like_ros2_bag_info(recorded: Any, kit: Any) -> None:
    info = bag_info(recorded.path)
    text = format_info(info)
    lines = text.splitlines()
    assert lines[0] == ""
    assert lines[1] == f"Files:             {info.files[0]}"
    assert lines[2] == f"Bag size:          {format_size(info.bag_size)}"
    assert lines[3] == "Storage id:        mcap"
    assert lines[4] == "ROS Distro:        jazzy"
    assert lines[5] == "Duration:          1.000000000s"
    # ros2 bag info: std::put_time(localtime, "%b %e %Y") and "%H:%M:%S", then the fraction.
    start = time.strftime("%b %e %Y %H:%M:%S", time.localtime(1000))
    end = time.strftime("%b %e %Y %H:%M:%S", time.localtime(1001))
    assert lines[6] == f"Start:             {start}.250000000 (1000.250000000)"
    assert lines[7] == f"End:               {end}.250000000 (1001.250000000)"
    assert lines[8] == f"Messages:          {info.message_count}"
    assert lines[9] == (
        "Topic information: Topic: /camera/image | Type: sensor_msgs/msg/Image | Count: 5 | "
        "Serialization Format: cdr"
    )
    assert all(line.startswith(" " * 19 + "Topic: ") for line in lines[10:-2])
    assert len(lines) == 9 + len(info.topics) + 2
    # Jazzy's service section (format_bag_metadata.cpp): no services recorded
    assert lines[-2:] == ["Service:           0", "Service information: "]
    verbose = format_info(info, verbose=True)
    assert "Version:           9" in verbose
    assert "Compression:       zstd (storage chunks)" in verbose
    assert "keep_last(1), reliable, transient_local" in verbose


@pytest.mark.parametrize(
    ("size", "text"),
    [(0, "0 B"), (1023, "1023 B"), (1024, "1.0 KiB"), (1536, "1.5 KiB"),
     (5 * 1024**2 + 1, "5.0 MiB"), (3 * 1024**4, "3.0 TiB")],
)
def test_size_format(size: int, text: str) -> None:
    assert format_size(size) == text


def _copy(recorded: Any, tmp_path: Path, name: str) -> tuple[Path, Path]:
    target = tmp_path / name
    shutil.copytree(recorded.path, target)
    return target, next(target.glob("*.mcap"))


def test_missing_and_not_a_bag(tmp_path: Path) -> None:
    with pytest.raises(BagNotFoundError, match="does not exist"):
        bag_info(tmp_path / "nope")
    (tmp_path / "plain").mkdir()
    with pytest.raises(BagNotFoundError, match="no metadata"):
        bag_info(tmp_path / "plain")
    (tmp_path / "file.mcap").write_bytes(b"x")
    with pytest.raises(BagFormatError, match="is a file"):
        bag_info(tmp_path / "file.mcap")
    with pytest.raises(BagNotFoundError):
        list(read_messages(tmp_path / "nope"))


def test_truncated_and_empty_storage(recorded: Any, tmp_path: Path) -> None:
    bag, mcap_file = _copy(recorded, tmp_path, "trunc")
    data = mcap_file.read_bytes()
    mcap_file.write_bytes(data[: len(data) // 2])
    with pytest.raises(BagFormatError, match=r"trunc.*end magic"):
        bag_info(bag)
    with pytest.raises(BagFormatError):
        list(read_messages(bag))
    mcap_file.write_bytes(b"")
    with pytest.raises(BagFormatError, match="empty"):
        bag_info(bag)


def test_damaged_chunk_is_reported_while_reading(recorded: Any, tmp_path: Path) -> None:
    bag, mcap_file = _copy(recorded, tmp_path, "flip")
    with mcap_file.open("rb") as f:
        summary = make_reader(f).get_summary()
    assert summary is not None
    chunk = summary.chunk_indexes[0]
    data = bytearray(mcap_file.read_bytes())
    # The compressed stream starts after the chunk record's fixed fields and "zstd".
    start = chunk.chunk_start_offset + 9 + 8 + 8 + 8 + 4 + 4 + len("zstd") + 8
    data[start:start + 8] = bytes(b ^ 0xFF for b in data[start:start + 8])
    mcap_file.write_bytes(bytes(data))
    bag_info(bag)  # the summary is intact, so info works ...
    with pytest.raises(BagFormatError, match=r"cannot read bag .*ZstdError"):
        list(read_messages(bag))  # ... and reading the chunk names the problem


def test_damaged_summary_and_missing_file(recorded: Any, tmp_path: Path) -> None:
    bag, mcap_file = _copy(recorded, tmp_path, "summary")
    data = bytearray(mcap_file.read_bytes())
    data[-300:-200] = bytes(b ^ 0xFF for b in data[-300:-200])
    mcap_file.write_bytes(bytes(data))
    with pytest.raises(BagFormatError, match="cannot open bag"):
        bag_info(bag)
    bag2, mcap2 = _copy(recorded, tmp_path, "gone")
    mcap2.unlink()
    with pytest.raises(BagFormatError, match="missing"):
        bag_info(bag2)


@pytest.mark.parametrize(
    ("text", "reason"),
    [
        ("rosbag2_bagfile_information: [unclosed", "not valid YAML"),
        ("something_else: 1\n", "rosbag2_bagfile_information"),
        ("rosbag2_bagfile_information:\n  version: 9\n", "cannot open bag"),
    ],
)
def test_bad_metadata(recorded: Any, tmp_path: Path, text: str, reason: str) -> None:
    bag, _ = _copy(recorded, tmp_path, "meta")
    (bag / "metadata.yaml").write_text(text)
    with pytest.raises(BagFormatError, match=reason):
        bag_info(bag)
    with pytest.raises(BagError):
        list(read_messages(bag))
