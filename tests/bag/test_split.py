"""rosbag2 Jazzy's file layout: ``<name>_<i>.mcap``, splitting by size and by duration, topic
selection by regex and exclusion, merged metadata.yaml.

Oracles: rosbags' reader with a fresh ROS 2 Jazzy typestore (not posekit's decoder), the
``mcap`` package with ``mcap-ros2-support`` reading each storage file on its own, PyYAML for
metadata.yaml, and rosbag2's rules (a new file before a message once the current file holds
more than ``max_bagfile_size`` bytes or the message is more than ``max_bagfile_duration``
after the file's first one) applied to the timestamps read back.
"""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_typestore

from posekit.bag import BagOptionError, Recorder, bag_info, format_info
from posekit.msgs.std_msgs import String
from posekit.runtime.context import Context
from posekit.runtime.node import Node
from posekit.runtime.sim_executor import SimulatedTimeExecutor

SEC = 1_000_000_000


def record_run(path: Path, seconds: float, topics: list[str] | None = None,
               payload: int = 10, **options: object) -> list[tuple[str, str]]:
    """/words and /other_words at 10 Hz, /_hidden and /skip_me too, in sim time from 100 s."""
    context = Context()
    context.init(transport="inprocess")
    sent: list[tuple[str, str]] = []
    try:
        executor = SimulatedTimeExecutor(context=context, start_time=100.0)
        node = Node("speaker", context=context)
        pubs = {name: node.create_publisher(String, name, 100)
                for name in ("/words", "/other_words", "/_hidden", "/skip_me")}
        counter = iter(range(10_000))

        def tick() -> None:
            k = next(counter)
            for name, pub in pubs.items():
                text = f"{name}-{k}-" + "x" * payload
                pub.publish(String(data=text))
                sent.append((name, text))

        node.create_timer(0.1, tick)
        executor.add_node(node)
        recorder = Recorder(path, topics, context=context, **options)  # type: ignore[arg-type]
        executor.add_node(recorder.node)
        executor.run_for(seconds)
        recorder.close()
    finally:
        context.try_shutdown()
    return sent


def per_file(path: Path) -> dict[str, list[tuple[str, int, str]]]:
    """Every storage file read on its own by the mcap reader: (topic, log time, data)."""
    out: dict[str, list[tuple[str, int, str]]] = {}
    for file in sorted(path.glob("*.mcap"), key=lambda p: int(p.stem.rsplit("_", 1)[1])):
        with file.open("rb") as f:
            reader = make_reader(f, decoder_factories=[DecoderFactory()])
            out[file.name] = [(ch.topic, m.log_time, decoded.data)
                              for _, ch, m, decoded in reader.iter_decoded_messages()]
    return out


def rosbags_messages(path: Path) -> list[tuple[str, int, str]]:
    store = get_typestore(Stores.ROS2_JAZZY)
    with Reader(path) as reader:
        return [(c.topic, t, getattr(store.deserialize_cdr(raw, c.msgtype), "data", ""))
                for c, t, raw in reader.messages()]


def test_single_file_is_named_like_rosbag2(tmp_path: Path) -> None:
    sent = record_run(tmp_path / "run1", 0.55, ["/words"])
    assert sorted(p.name for p in (tmp_path / "run1").iterdir()) == [
        "metadata.yaml", "run1_0.mcap"]
    meta = yaml.safe_load((tmp_path / "run1" / "metadata.yaml").read_text())[
        "rosbag2_bagfile_information"]
    assert meta["relative_file_paths"] == ["run1_0.mcap"]
    assert meta["ros_distro"] == "jazzy"
    assert [f["path"] for f in meta["files"]] == ["run1_0.mcap"]
    words = [t for n, t in sent if n == "/words"]
    assert [d for _, _, d in rosbags_messages(tmp_path / "run1")] == words
    text = format_info(bag_info(tmp_path / "run1"))
    assert "Files:             run1_0.mcap\n" in text
    assert "ROS Distro:        jazzy\n" in text


def test_split_by_duration_follows_rosbag2s_rule(tmp_path: Path) -> None:
    sent = record_run(tmp_path / "d", 3.55, ["/words"], max_bag_duration=1.0)
    files = per_file(tmp_path / "d")
    assert list(files) == [f"d_{i}.mcap" for i in range(len(files))]
    assert len(files) == 4  # 36 messages 0.1 s apart, a new file after more than 1 s
    firsts = [msgs[0][1] for msgs in files.values()]
    for msgs in files.values():
        assert all(t - msgs[0][1] <= SEC for _, t, _ in msgs)
    for (msgs, nxt) in zip(list(files.values())[:-1], firsts[1:], strict=True):
        assert nxt - msgs[0][1] > SEC  # the message that started the next file
    everything = [m for msgs in files.values() for m in msgs]
    assert everything == rosbags_messages(tmp_path / "d")  # rosbags reads across the files
    assert [d for _, _, d in everything] == [t for n, t in sent if n == "/words"]
    meta = yaml.safe_load((tmp_path / "d" / "metadata.yaml").read_text())[
        "rosbag2_bagfile_information"]
    assert meta["relative_file_paths"] == list(files)
    assert [f["message_count"] for f in meta["files"]] == [len(m) for m in files.values()]
    assert meta["message_count"] == len(everything)
    assert meta["starting_time"]["nanoseconds_since_epoch"] == everything[0][1]
    assert meta["duration"]["nanoseconds"] == everything[-1][1] - everything[0][1]
    assert meta["topics_with_message_count"][0]["message_count"] == len(everything)
    info = bag_info(tmp_path / "d")
    assert info.files == list(files)
    assert info.bag_size == sum((tmp_path / "d" / f).stat().st_size for f in files)


def test_split_by_size_and_every_file_has_every_topic(tmp_path: Path) -> None:
    record_run(tmp_path / "s", 2.05, ["/words", "/other_words"], payload=2000,
               max_bag_size=12_000, compression=None)
    files = per_file(tmp_path / "s")
    assert len(files) >= 3
    sizes = [(tmp_path / "s" / name).stat().st_size for name in files]
    # a file is only closed once it held more than the limit; the last one may hold less
    assert all(size > 12_000 for size in sizes[:-1])
    for name in files:
        with (tmp_path / "s" / name).open("rb") as f:
            summary = make_reader(f).get_summary()
        assert summary is not None
        assert {c.topic for c in summary.channels.values()} == {"/words", "/other_words"}
    assert [m for msgs in files.values() for m in msgs] == rosbags_messages(tmp_path / "s")


def test_regex_and_exclusions_select_like_rosbag2(tmp_path: Path) -> None:
    record_run(tmp_path / "r", 0.35, None, regex="words$", exclude_regex="^/other")
    assert {t for t, _, _ in rosbags_messages(tmp_path / "r")} == {"/words"}
    record_run(tmp_path / "all", 0.35, None, exclude=["/clock", "/skip_me"])
    # every node also publishes /rosout and /parameter_events, recorded by --all as by ros2
    assert {t for t, _, _ in rosbags_messages(tmp_path / "all")} - {
        "/rosout", "/parameter_events"} == {"/words", "/other_words"}
    record_run(tmp_path / "hidden", 0.35, None, regex="^/_", include_hidden=True)
    assert {t for t, _, _ in rosbags_messages(tmp_path / "hidden")} == {"/_hidden"}
    record_run(tmp_path / "both", 0.35, ["/skip_me"], regex="^/other")
    assert {t for t, _, _ in rosbags_messages(tmp_path / "both")} == {
        "/skip_me", "/other_words"}


def test_compression_modes_read_back(tmp_path: Path) -> None:
    sent = record_run(tmp_path / "m", 0.35, ["/words"], compression="message")
    assert [d for _, _, d in rosbags_messages(tmp_path / "m")] == [
        t for n, t in sent if n == "/words"]
    sent = record_run(tmp_path / "f", 0.35, ["/words"], compression="file")
    assert [p.name for p in sorted((tmp_path / "f").glob("f_0*"))] == ["f_0.mcap.zstd"]
    assert [d for _, _, d in rosbags_messages(tmp_path / "f")] == [
        t for n, t in sent if n == "/words"]
    meta = yaml.safe_load((tmp_path / "f" / "metadata.yaml").read_text())[
        "rosbag2_bagfile_information"]
    assert (meta["compression_mode"], meta["compression_format"]) == ("file", "zstd")


def test_bad_options(tmp_path: Path) -> None:
    with pytest.raises(BagOptionError, match="regular expression"):
        Recorder(tmp_path / "x", None, regex="(")
    with pytest.raises(BagOptionError, match=">= 0"):
        Recorder(tmp_path / "y", ["/a"], max_bag_size=-1)
    assert not (tmp_path / "x").exists()


def test_convert_merges_splits_and_selects(tmp_path: Path,
                                           capsys: pytest.CaptureFixture[str]) -> None:
    """``posekit bag convert`` with ros2 bag convert's options file."""
    from posekit.cli.main import main

    record_run(tmp_path / "a", 1.05, ["/words"])
    record_run(tmp_path / "b", 1.05, ["/other_words", "/skip_me"])
    options = tmp_path / "out.yaml"
    options.write_text(yaml.safe_dump({"output_bags": [
        {"uri": str(tmp_path / "merged"), "storage_id": "mcap", "all_topics": True,
         "exclude_topics": ["/skip_me"], "max_bagfile_duration": 0.5},
        {"uri": str(tmp_path / "other"), "regex": "other", "compression_mode": "file",
         "compression_format": "zstd"},
    ]}))
    assert main(["bag", "convert", "-i", str(tmp_path / "a"), "-i", str(tmp_path / "b"),
                 "mcap", "-o", str(options)]) == 0
    assert "wrote 20 messages" in capsys.readouterr().err
    merged = rosbags_messages(tmp_path / "merged")
    inputs = sorted(rosbags_messages(tmp_path / "a") + [
        m for m in rosbags_messages(tmp_path / "b") if m[0] != "/skip_me"],
        key=lambda m: m[1])
    assert sorted(merged) == sorted(inputs)
    assert [t for _, t, _ in merged] == sorted(t for _, t, _ in merged)
    files = per_file(tmp_path / "merged")
    assert len(files) == 2  # 1 s of messages, a new file after more than 0.5 s
    assert [m for msgs in files.values() for m in msgs] == merged
    other = rosbags_messages(tmp_path / "other")
    assert {t for t, _, _ in other} == {"/other_words"}
    assert (tmp_path / "other" / "other_0.mcap.zstd").is_file()
    options.write_text("output_bags:\n- uri: x\n  bogus: 1\n")
    assert main(["bag", "convert", "-i", str(tmp_path / "a"), "-o", str(options)]) == 1
    assert capsys.readouterr().err == (
        "posekit bag convert: error: unknown output bag option(s) ['bogus']\n")
