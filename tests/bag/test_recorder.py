"""Recorder: what lands in the bag, checked with two independent readers.

Every message the talkers published is compared with (1) rosbags' own reader and a fresh
ROS 2 Jazzy typestore (not posekit's decoder) and (2) the ``mcap`` package with
``mcap-ros2-support``, which decodes from the schema text stored in the file, so it also
proves the message definitions are complete. Metadata is parsed with PyYAML.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_typestore

from posekit.bag import (
    BagExistsError,
    BagOptionError,
    Recorder,
    read_messages,
)
from posekit.msgs.std_msgs import String
from posekit.runtime.context import Context
from posekit.runtime.node import Node
from posekit.runtime.qos import DurabilityPolicy, QoSProfile
from posekit.runtime.sim_executor import SimulatedTimeExecutor

START_NS = 1_000_250_000_000  # conftest.START_NS: the talkers' start time


@pytest.fixture
def record_talkers(kit: Any) -> Any:
    return kit.record

# /rosout and /parameter_events: every node (the recorder's too) publishes its log lines and
# parameter changes there, as in ROS 2.
TOPICS = ["/camera/image", "/chatter", "/imu", "/odom", "/tf", "/tf_static"]
ALL_TOPICS = sorted([*TOPICS, "/parameter_events", "/rosout"])
#: The talkers' topics whose every published message is compared.
SENT_TOPICS = ["/camera/image", "/chatter", "/imu", "/odom", "/tf"]


def _mcap_file(path: Path) -> Path:
    files = sorted(path.glob("*.mcap"))
    assert len(files) == 1, files
    return files[0]


def test_every_message_read_back_by_rosbags_with_its_receive_time(recorded: Any,
                                                                  same_message: Any) -> None:
    store = get_typestore(Stores.ROS2_JAZZY)
    got: dict[str, list[tuple[int, Any]]] = {}
    with Reader(recorded.path) as reader:
        assert sorted(c.topic for c in reader.connections) == ALL_TOPICS
        for conn, timestamp, data in reader.messages():
            got.setdefault(conn.topic, []).append(
                (timestamp, store.deserialize_cdr(data, conn.msgtype))
            )
    sent = recorded.talkers.sent
    for topic in SENT_TOPICS:
        expected = [(t, m) for top, t, m in sent if top == topic]
        assert len(got[topic]) == len(expected) > 0, topic
        for (t_exp, m_exp), (t_got, m_got) in zip(expected, got[topic], strict=True):
            assert t_got == t_exp  # receive time == publish time in a stepped run
            same_message(m_exp, m_got)
    # 20 Hz /tf for 1 s starting 50 ms after START: exact sim times, no drift.
    assert [t for t, _ in got["/tf"]] == [START_NS + k * 50_000_000 for k in range(1, 21)]
    # Both static broadcasters' latched messages, received when the recorder subscribed.
    statics = got["/tf_static"]
    assert [t for t, _ in statics] == [START_NS, START_NS]
    children = sorted(m.transforms[0].child_frame_id for _, m in statics)
    assert children == ["camera", "laser"]
    assert recorded.counts == {topic: len(got[topic]) for topic in ALL_TOPICS}
    events = [m for _, m in got["/parameter_events"]]
    assert all(m.__msgtype__ == "rcl_interfaces/msg/ParameterEvent" for m in events)


def test_every_message_read_back_by_mcap_ros2_from_the_stored_schemas(
    recorded: Any, same_message: Any
) -> None:
    path = _mcap_file(recorded.path)
    decoded: dict[str, list[tuple[int, int, Any]]] = {}
    with path.open("rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        summary = reader.get_summary()
        assert summary is not None
        schemas = {s.name: s for s in summary.schemas.values()}
        for _, channel, message, ros_msg in reader.iter_decoded_messages():
            decoded.setdefault(channel.topic, []).append(
                (message.log_time, message.publish_time, ros_msg)
            )
        header = reader.get_header()
    assert header.profile == "ros2"
    assert {s.encoding for s in schemas.values()} == {"ros2msg"}
    # The TFMessage schema carries its dependencies so foreign tools can decode it.
    tf_schema = schemas["tf2_msgs/msg/TFMessage"].data.decode()
    for dep in ("MSG: geometry_msgs/TransformStamped", "MSG: std_msgs/Header",
                "MSG: builtin_interfaces/Time", "MSG: geometry_msgs/Quaternion"):
        assert dep in tf_schema
    sent = recorded.talkers.sent
    for topic in SENT_TOPICS:
        expected = [(t, m) for top, t, m in sent if top == topic]
        assert len(decoded[topic]) == len(expected), topic
        for (t_exp, m_exp), (log_t, pub_t, m_got) in zip(expected, decoded[topic], strict=True):
            assert log_t == t_exp
            assert pub_t == t_exp
            same_message(m_exp, m_got)
    assert len(decoded["/tf_static"]) == 2


def test_chunks_are_zstd_and_channels_carry_offered_qos(recorded: Any) -> None:
    with _mcap_file(recorded.path).open("rb") as f:
        summary = make_reader(f).get_summary()
    assert summary is not None
    assert summary.chunk_indexes
    assert {c.compression for c in summary.chunk_indexes} == {"zstd"}
    by_topic = {c.topic: c for c in summary.channels.values()}
    assert set(by_topic) == set(ALL_TOPICS)
    static_qos = yaml.safe_load(by_topic["/tf_static"].metadata["offered_qos_profiles"])
    assert static_qos[0]["durability"] == "transient_local"
    assert all(c.message_encoding == "cdr" for c in by_topic.values())


def test_uncompressed_option_writes_plain_chunks(ctx: Context, tmp_path: Path,
                                                record_talkers: Any) -> None:
    rec = record_talkers(ctx, tmp_path / "raw", seconds=0.3, compression=None)
    with _mcap_file(rec.path).open("rb") as f:
        summary = make_reader(f).get_summary()
    assert summary is not None
    assert {c.compression for c in summary.chunk_indexes} == {""}


def _metadata(path: Path) -> dict[str, Any]:
    data = yaml.safe_load((path / "metadata.yaml").read_text())
    info: dict[str, Any] = data["rosbag2_bagfile_information"]
    return info


def _topic_meta(info: dict[str, Any], name: str) -> dict[str, Any]:
    for entry in info["topics_with_message_count"]:
        if entry["topic_metadata"]["name"] == name:
            meta: dict[str, Any] = entry["topic_metadata"]
            return meta
    raise KeyError(name)


def test_metadata_version_9_structured_qos(recorded: Any) -> None:
    info = _metadata(recorded.path)
    assert info["version"] == 9
    assert info["storage_identifier"] == "mcap"
    assert info["relative_file_paths"] == [_mcap_file(recorded.path).name]
    assert info["starting_time"]["nanoseconds_since_epoch"] == START_NS
    assert info["duration"]["nanoseconds"] == 1_000_000_000  # last message at START + 1 s
    assert info["message_count"] == sum(recorded.counts.values())
    static = _topic_meta(info, "/tf_static")
    qos = static["offered_qos_profiles"]
    assert isinstance(qos, list)
    assert len(qos) == 2
    assert {q["durability"] for q in qos} == {"transient_local"}
    assert {q["reliability"] for q in qos} == {"reliable"}
    assert {q["history"] for q in qos} == {"keep_last"}
    assert {q["depth"] for q in qos} == {1}
    assert qos[0]["deadline"] == {"sec": 9223372036, "nsec": 854775807}
    imu = _topic_meta(info, "/imu")["offered_qos_profiles"]
    assert imu[0]["reliability"] == "best_effort"
    assert imu[0]["depth"] == 5
    tf = _topic_meta(info, "/tf")
    assert tf["offered_qos_profiles"][0]["depth"] == 100  # tf2_ros DynamicBroadcasterQoS
    assert tf["type"] == "tf2_msgs/msg/TFMessage"
    assert tf["type_description_hash"].startswith("RIHS01_")
    assert tf["serialization_format"] == "cdr"


def test_metadata_version_8_qos_is_a_yaml_string_with_numeric_policies(
    ctx: Context, tmp_path: Path, record_talkers: Any
) -> None:
    rec = record_talkers(ctx, tmp_path / "v8", seconds=0.2, version=8)
    info = _metadata(rec.path)
    assert info["version"] == 8
    static = _topic_meta(info, "/tf_static")
    assert isinstance(static["offered_qos_profiles"], str)
    qos = yaml.safe_load(static["offered_qos_profiles"])
    assert {q["durability"] for q in qos} == {1}  # RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL
    assert {q["reliability"] for q in qos} == {1}  # RELIABLE
    imu = yaml.safe_load(_topic_meta(info, "/imu")["offered_qos_profiles"])
    assert imu[0]["reliability"] == 2  # BEST_EFFORT
    # The same messages whatever the version: rosbags reads both.
    with Reader(rec.path) as reader:
        assert reader.message_count == sum(rec.counts.values())


def test_explicit_topics_only(ctx: Context, tmp_path: Path, record_talkers: Any) -> None:
    rec = record_talkers(ctx, tmp_path / "some", seconds=0.3, topics=["tf", "/chatter"])
    assert sorted(rec.counts) == ["/chatter", "/tf"]
    assert {m.topic for m in read_messages(rec.path)} == {"/chatter", "/tf"}


def test_header_stamps_option(ctx: Context, tmp_path: Path) -> None:
    """stamp="header": /tf stored at header.stamp (here published 10 ms in the past)."""
    executor = SimulatedTimeExecutor(context=ctx, start_time=5.0)
    node = Node("stamper", context=ctx)
    executor.add_node(node)
    pub = node.create_publisher(String, "plain", 10)

    from posekit.msgs.geometry_msgs import TransformStamped
    from posekit.msgs.tf2_msgs import TFMessage

    tf_pub = node.create_publisher(TFMessage, "/tf", 10)

    def tick() -> None:
        t = TransformStamped()
        now = node.get_clock().now().nanoseconds - 10_000_000
        t.header.stamp.sec, t.header.stamp.nanosec = divmod(now, 1_000_000_000)
        t.header.frame_id, t.child_frame_id = "a", "b"
        tf_pub.publish(TFMessage(transforms=[t]))
        pub.publish(String(data="x"))

    node.create_timer(0.5, tick)
    from posekit.bag import attach_recorder

    rec = attach_recorder(executor, tmp_path / "h", stamp="header")
    executor.run_for(1.0)
    rec.close()
    stamps = {
        (m.topic, m.timestamp_ns) for m in read_messages(tmp_path / "h")
        if m.topic not in ("/parameter_events", "/rosout")  # no header: receive times
    }
    assert stamps == {
        ("/tf", 5_490_000_000), ("/tf", 5_990_000_000),
        ("/plain", 5_500_000_000), ("/plain", 6_000_000_000),  # no header: receive time
    }
    assert _metadata(tmp_path / "h")["custom_data"]["timestamps"] == "header"


def test_all_topics_discovers_late_topics_skips_hidden_clock_and_foreign_types(
    ctx: Context, tmp_path: Path, logs: list[Any]
) -> None:
    executor = SimulatedTimeExecutor(context=ctx)  # publishes /clock at every step
    node = Node("late", context=ctx)
    executor.add_node(node)
    rec = Recorder(tmp_path / "all", context=ctx)
    executor.add_node(rec.node)
    early = node.create_publisher(String, "early", 10)
    hidden = node.create_publisher(String, "_hidden/x", 10)

    class NotAMessage:
        pass

    node.create_publisher(NotAMessage, "custom", 10)
    late_pub: list[Any] = []

    def tick() -> None:
        early.publish(String(data="e"))
        hidden.publish(String(data="h"))
        if node.get_clock().now().nanoseconds >= 500_000_000 and not late_pub:
            late_pub.append(node.create_publisher(String, "late", 10))
        for p in late_pub:
            p.publish(String(data="l"))

    node.create_timer(0.1, tick)
    executor.run_for(1.0)
    counts = rec.close()
    assert set(counts) == {"/early", "/late", "/parameter_events", "/rosout"}
    # /early is discovered on the first graph check (after the node existed); /late within
    # one discovery period (0.1 s) of appearing at 0.5 s, so it misses at most one message.
    assert counts["/early"] == 10
    assert counts["/late"] in (4, 5)
    assert any("not recording '/custom'" in r.message for r in logs)


def test_existing_output_and_bad_options_are_rejected(ctx: Context, tmp_path: Path) -> None:
    (tmp_path / "taken").mkdir()
    with pytest.raises(BagExistsError, match="exists already"):
        Recorder(tmp_path / "taken", context=ctx)
    with pytest.raises(BagOptionError, match="choose 8 or 9"):
        Recorder(tmp_path / "v7", context=ctx, version=7)
    with pytest.raises(BagOptionError, match="compression"):
        Recorder(tmp_path / "lz", context=ctx, compression="lz4")
    with pytest.raises(BagOptionError, match="stamp"):
        Recorder(tmp_path / "st", context=ctx, stamp="publish")
    assert not (tmp_path / "v7").exists()
    assert not (tmp_path / "lz").exists()


def test_transient_local_subscription_only_when_every_publisher_latches(
    ctx: Context, tmp_path: Path
) -> None:
    """A late recorder still gets latched /tf_static, and a volatile publisher on a topic
    does not make the recorder request transient local (which would not match it)."""
    node = Node("mixed", context=ctx)
    latched = node.create_publisher(
        String, "mixed", QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    )
    latched.publish(String(data="before"))
    volatile = node.create_publisher(String, "mixed", 10)
    executor = SimulatedTimeExecutor(context=ctx)
    executor.add_node(node)
    rec = Recorder(tmp_path / "m", ["mixed"], context=ctx)
    executor.add_node(rec.node)
    volatile.publish(String(data="after"))
    executor.run_for(0.1)
    rec.close()
    got = [m.decode().data for m in read_messages(tmp_path / "m")]
    assert got == ["after"]  # volatile subscription: the latched history is not replayed
    info = _metadata(tmp_path / "m")
    assert {q["durability"] for q in _topic_meta(info, "/mixed")["offered_qos_profiles"]} == {
        "transient_local", "volatile"
    }


def test_close_is_idempotent_and_stops_recording(ctx: Context, tmp_path: Path) -> None:
    executor = SimulatedTimeExecutor(context=ctx)
    node = Node("talk", context=ctx)
    pub = node.create_publisher(String, "words", 10)
    executor.add_node(node)
    rec = Recorder(tmp_path / "c", ["words"], context=ctx)
    executor.add_node(rec.node)
    pub.publish(String(data="one"))
    executor.run_for(0.1)
    assert rec.close() == {"/words": 1}
    before = (tmp_path / "c" / "metadata.yaml").read_text()
    pub.publish(String(data="two"))
    executor.run_for(0.1)
    assert rec.close() == {"/words": 1}
    assert rec.closed
    assert rec.discover() == []
    assert (tmp_path / "c" / "metadata.yaml").read_text() == before
    assert [m.decode().data for m in read_messages(tmp_path / "c")] == ["one"]


def test_context_shutdown_finishes_an_attached_bag(tmp_path: Path) -> None:
    from posekit.bag import attach_recorder

    context = Context()
    context.init(transport="inprocess")
    executor = SimulatedTimeExecutor(context=context)
    node = Node("talk", context=context)
    pub = node.create_publisher(String, "words", 10)
    executor.add_node(node)
    rec = attach_recorder(context, tmp_path / "auto", ["words"])
    executor.add_node(rec.node)  # a bare context: the caller spins the recorder node
    pub.publish(String(data="kept"))
    executor.run_for(0.1)
    assert not (tmp_path / "auto" / "metadata.yaml").exists()  # still recording
    context.shutdown()
    assert rec.closed
    assert [m.decode().data for m in read_messages(tmp_path / "auto")] == ["kept"]
    with pytest.raises(BagOptionError, match="LaunchRun, an Executor or a Context"):
        attach_recorder(object(), tmp_path / "never")
