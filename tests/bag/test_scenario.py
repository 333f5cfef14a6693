"""Recording the course's P-controller scenario, reading it back with rosbags and with
mcap + mcap-ros2-support, and replaying it into a tf2 Buffer."""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any

import numpy as np
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_typestore

import posekit.robot.scenarios  # noqa: F401 - registers the robot's scenarios
from posekit.bag import Player, attach_recorder, bag_info, read_messages, record_scenario
from posekit.launch.scenarios import start_scenario
from posekit.msgs.nav_msgs import Odometry
from posekit.runtime.context import Context
from posekit.runtime.node import Node
from posekit.runtime.sim_executor import SimulatedTimeExecutor
from posekit.tf2 import Buffer
from posekit.tf2_ros import TransformListener
from posekit.time import Time

SECONDS = 2.0


def _lookup_table(buffer: Buffer, frames: list[str], times_ns: list[int]) -> list[Any]:
    rows: list[Any] = []
    for frame in frames:
        for t in times_ns:
            try:
                tr = buffer.lookup_transform("odom", frame, Time(nanoseconds=t)).transform
            except Exception as exc:  # the same failure must happen in both runs
                rows.append(type(exc).__name__)
                continue
            rows.append((tr.translation.x, tr.translation.y, tr.translation.z,
                         tr.rotation.x, tr.rotation.y, tr.rotation.z, tr.rotation.w))
    return rows


def test_p_controller_run_recorded_read_back_and_replayed(tmp_path: Path,
                                                          same_message: Any) -> None:
    run = start_scenario("p_controller")
    executor = run.executor
    assert isinstance(executor, SimulatedTimeExecutor)
    live_node = Node("live_listener", context=run.context)
    live_buffer = Buffer()
    TransformListener(live_buffer, live_node)
    filtered: list[tuple[int, Odometry]] = []
    live_node.create_subscription(
        Odometry, "/odometry/filtered",
        lambda m: filtered.append((live_node.get_clock().now().nanoseconds, copy.deepcopy(m))),
        100,
    )
    executor.add_node(live_node)
    recorder = attach_recorder(run, tmp_path / "p")
    try:
        executor.run_for(SECONDS)
        counts = recorder.close()
        frames = sorted(f for f in live_buffer.get_all_frame_names() if f != "odom")
        times = list(range(100_000_000, int(SECONDS * 1e9) + 1, 73_000_000))
        live = _lookup_table(live_buffer, frames, times)
    finally:
        run.shutdown()
    assert {"/tf", "/tf_static", "/odometry/filtered", "/cmd_vel"} <= set(counts)
    assert "base_link" in frames
    assert sum(1 for row in live if not isinstance(row, str)) > len(times)  # real answers

    # 1. posekit's reader, rosbags with its own typestore, and mcap_ros2 (decoding from the
    #    schemas stored in the file) agree on every message.
    ours = list(read_messages(tmp_path / "p"))
    assert len(ours) == sum(counts.values())
    store = get_typestore(Stores.ROS2_JAZZY)
    with Reader(tmp_path / "p") as reader:
        by_rosbags = [(c.topic, t, store.deserialize_cdr(d, c.msgtype))
                      for c, t, d in reader.messages()]
    with next((tmp_path / "p").glob("*.mcap")).open("rb") as f:
        by_mcap = [(ch.topic, m.log_time, decoded) for _, ch, m, decoded in
                   make_reader(f, decoder_factories=[DecoderFactory()]).iter_decoded_messages()]
    assert len(by_rosbags) == len(by_mcap) == len(ours)

    def key(item: tuple[str, int, Any]) -> tuple[int, str]:
        return (item[1], item[0])

    # The same (topic, time) sequence from all three readers.
    ours_sorted = sorted(((m.topic, m.timestamp_ns, m) for m in ours), key=key)
    stamps = [(topic, t) for topic, t, _ in ours_sorted]
    assert [(topic, t) for topic, t, _ in sorted(by_rosbags, key=key)] == stamps
    assert [(topic, t) for topic, t, _ in sorted(by_mcap, key=key)] == stamps
    by_topic: dict[str, list[Any]] = {}
    for topic, _, m in ours_sorted:
        by_topic.setdefault(topic, []).append(m.decode())
    for source in (by_rosbags, by_mcap):
        per_topic: dict[str, list[Any]] = {}
        for topic, _, decoded in source:
            per_topic.setdefault(topic, []).append(decoded)
        for topic, messages in by_topic.items():
            for mine, theirs in zip(messages, per_topic[topic], strict=True):
                same_message(mine, theirs)
    # ... and they equal what a live subscriber received, with the receive times.
    recorded_filtered = [(m.timestamp_ns, m.decode()) for m in ours
                         if m.topic == "/odometry/filtered"]
    assert [t for t, _ in recorded_filtered] == [t for t, _ in filtered]
    for (_, live_msg), (_, rec_msg) in zip(filtered, recorded_filtered, strict=True):
        same_message(live_msg, rec_msg)

    # 2. Replayed into a Buffer, every lookup gives the live run's answer.
    ctx = Context()
    ctx.init(transport="inprocess")
    try:
        replay = SimulatedTimeExecutor(context=ctx)
        node = Node("replay_listener", context=ctx)
        buffer = Buffer()
        TransformListener(buffer, node)
        replay.add_node(node)
        Player(tmp_path / "p", context=ctx).run_simulated(replay)
        replayed = _lookup_table(buffer, frames, times)
    finally:
        ctx.try_shutdown()
    assert len(replayed) == len(live)
    for a, b in zip(live, replayed, strict=True):
        if isinstance(a, str):
            assert a == b
        else:
            np.testing.assert_array_equal(np.array(b), np.array(a))


def test_record_scenario_helper(tmp_path: Path) -> None:
    counts = record_scenario("empty_world", tmp_path / "e", duration=0.5,
                             topics=["/tf", "/odometry/wheels"], version=8)
    info = bag_info(tmp_path / "e")
    assert info.version == 8
    assert {t.name: t.message_count for t in info.topics} == counts
    assert set(counts) == {"/tf", "/odometry/wheels"}
    assert counts["/tf"] > 0
    assert info.end_ns <= 500_000_000
