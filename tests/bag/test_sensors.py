"""Sensor topics in bags: the simulated LiDAR's ``sensor_msgs/LaserScan`` on ``/scan`` and a
``sensor_msgs/PointCloud2`` recorded, read back by independent readers and replayed.

Oracles: what a live subscriber of the same run received (the scan), the cloud as built
with :func:`posekit.msgs.point_cloud2.create_cloud` from known points; rosbags' stock ROS 2
Jazzy typestore (its own deserializer, not posekit's) and ``mcap`` + ``mcap-ros2-support``
(which decodes with the schema text stored in the file, as Foxglove does) must give the same
values; floats compared bit for bit. The replayed messages must equal the recorded ones.
"""

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
from posekit.bag import Player, attach_recorder, bag_info, read_messages
from posekit.launch.scenarios import start_scenario
from posekit.msgs.point_cloud2 import create_cloud, read_points
from posekit.msgs.sensor_msgs import LaserScan, PointCloud2
from posekit.msgs.std_msgs import Header
from posekit.runtime.context import Context
from posekit.runtime.node import Node
from posekit.runtime.sim_executor import SimulatedTimeExecutor

ROS = get_typestore(Stores.ROS2_JAZZY)
CLOUD_TOPIC = "/cloud"


def _cloud(k: int) -> PointCloud2:
    """Eight points with x, y, z (float32) and intensity (float32): a known layout."""
    points = np.zeros(8, dtype=[("x", "<f4"), ("y", "<f4"), ("z", "<f4"),
                                ("intensity", "<f4")])
    points["x"] = np.arange(8, dtype=np.float32) * 0.5 + k
    points["y"] = -np.arange(8, dtype=np.float32)
    points["z"] = np.float32(0.25)
    points["intensity"] = np.linspace(0, 1, 8, dtype=np.float32)
    header = Header(frame_id="oak_rgb_camera_optical_frame")
    return create_cloud(header, points)


def _record(tmp_path: Path) -> tuple[Path, list[Any], list[Any]]:
    """0.5 s of /scan in aruco_box_world plus a 10 Hz /cloud, recorded; returns the bag and
    what live subscribers received."""
    run = start_scenario("empty_world", {"world_simulation.world": "aruco_box_world"})
    executor = run.executor
    assert isinstance(executor, SimulatedTimeExecutor)
    live = Node("live", context=run.context)
    scans: list[Any] = []
    live.create_subscription(LaserScan, "/scan", lambda m: scans.append(copy.deepcopy(m)), 100)
    clouds: list[Any] = []
    cloud_pub = live.create_publisher(PointCloud2, CLOUD_TOPIC, 10)

    def publish_cloud() -> None:
        msg = _cloud(len(clouds))
        msg.header.stamp = live.get_clock().now().to_msg()
        cloud_pub.publish(msg)
        clouds.append(copy.deepcopy(msg))

    live.create_timer(0.1, publish_cloud)
    executor.add_node(live)
    recorder = attach_recorder(run, tmp_path / "sensors", ["/scan", CLOUD_TOPIC])
    try:
        executor.run_for(0.5)
        recorder.close()
    finally:
        run.shutdown()
    return tmp_path / "sensors", scans, clouds


def _same(expected: Any, actual: Any, path: str = "msg") -> None:
    """Field-by-field equality across posekit, rosbags and mcap_ros2 objects (arrays bit for
    bit; a float equal, or equal to its float32 rounding: a live in-process subscriber gets
    the publisher's Python float, a reader of the CDR the float32 the field holds)."""
    import dataclasses

    if dataclasses.is_dataclass(expected):
        for f in dataclasses.fields(expected):
            _same(getattr(expected, f.name), getattr(actual, f.name), f"{path}.{f.name}")
        return
    if isinstance(expected, np.ndarray):
        got = np.asarray(actual if not isinstance(actual, bytes | bytearray)
                         else np.frombuffer(actual, np.uint8))
        assert got.dtype.kind == expected.dtype.kind or expected.dtype == np.uint8, path
        np.testing.assert_array_equal(got.astype(expected.dtype).view(np.uint8),
                                      expected.view(np.uint8), err_msg=path)
        return
    if isinstance(expected, list):
        assert len(actual) == len(expected), path
        for i, (e, a) in enumerate(zip(expected, actual, strict=True)):
            _same(e, a, f"{path}[{i}]")
        return
    if isinstance(expected, float):  # a float32 field keeps the float32 rounding exactly
        assert actual in (expected, float(np.float32(expected))), f"{path}: {actual!r}"
        return
    assert actual == expected, f"{path}: {actual!r} != {expected!r}"


def test_scan_and_cloud_recorded_and_read_back_independently(tmp_path: Path) -> None:
    bag, scans, clouds = _record(tmp_path)
    assert len(scans) == 5  # 10 Hz for 0.5 s
    assert len(clouds) == 5
    assert scans[0].ranges.size == 3000
    assert np.isfinite(scans[0].ranges).any()  # the world's boxes are seen
    with Reader(bag) as reader:
        types = {c.topic: c.msgtype for c in reader.connections}
        assert types == {"/scan": "sensor_msgs/msg/LaserScan",
                         CLOUD_TOPIC: "sensor_msgs/msg/PointCloud2"}
        got: dict[str, list[Any]] = {"/scan": [], CLOUD_TOPIC: []}
        for conn, _, data in reader.messages():
            got[conn.topic].append(ROS.deserialize_cdr(bytes(data), conn.msgtype))
    for expected, actual in zip(scans, got["/scan"], strict=True):
        _same(expected, actual)
    for expected, actual in zip(clouds, got[CLOUD_TOPIC], strict=True):
        _same(expected, actual)
    # The schema text stored in the MCAP file decodes the same values (Foxglove's way).
    (mcap_file,) = sorted(bag.glob("*.mcap"))
    decoded: dict[str, list[Any]] = {"/scan": [], CLOUD_TOPIC: []}
    with mcap_file.open("rb") as f:
        for _, channel, _, msg in make_reader(
                f, decoder_factories=[DecoderFactory()]).iter_decoded_messages():
            decoded[channel.topic].append(msg)
    for expected, actual in zip(scans, decoded["/scan"], strict=True):
        np.testing.assert_array_equal(np.asarray(actual.ranges, np.float32), expected.ranges)
        assert actual.header.frame_id == expected.header.frame_id
        assert actual.angle_increment == float(np.float32(expected.angle_increment))
    for expected, actual in zip(clouds, decoded[CLOUD_TOPIC], strict=True):
        assert [f.name for f in actual.fields] == ["x", "y", "z", "intensity"]
        assert bytes(actual.data) == expected.data.tobytes()
    assert bag_info(bag).topic("/scan").message_count == 5


def test_scan_and_cloud_replayed_unchanged(tmp_path: Path) -> None:
    bag, _, clouds = _record(tmp_path)
    recorded = {m.topic: [] for m in read_messages(bag)}  # type: dict[str, list[Any]]
    for m in read_messages(bag):
        recorded[m.topic].append(m.decode())
    context = Context()
    context.init(transport="inprocess")
    try:
        listener = Node("listener", context=context)
        got: dict[str, list[Any]] = {"/scan": [], CLOUD_TOPIC: []}
        listener.create_subscription(LaserScan, "/scan", got["/scan"].append, 100)
        listener.create_subscription(PointCloud2, CLOUD_TOPIC, got[CLOUD_TOPIC].append, 100)
        executor = SimulatedTimeExecutor(context=context)
        executor.add_node(listener)
        with Player(bag, context=context) as player:
            executor.add_node(player.node)
            player.run_simulated(executor)
        executor.run_for(0.01)
    finally:
        context.try_shutdown()
    for topic in ("/scan", CLOUD_TOPIC):
        assert len(got[topic]) == len(recorded[topic]) == 5
        for expected, actual in zip(recorded[topic], got[topic], strict=True):
            _same(expected, actual)
    points = read_points(got[CLOUD_TOPIC][0])
    np.testing.assert_array_equal(points["x"], np.arange(8, dtype=np.float32) * 0.5)
    assert clouds[0].header.frame_id == got[CLOUD_TOPIC][0].header.frame_id
