"""posekit's dds transport against a real ROS 2 Jazzy (rclpy on rmw_fastrtps_cpp), over loopback.

Oracles: the real rclpy from ``.venv-ros2`` (its own rendering of each message, its
``get_node_names()``, its publishers with BEST_EFFORT QoS or another type), and for
``/tf_static`` a late-joining reader written with plain ``cyclonedds`` that defines
``tf2_msgs/TFMessage`` itself and never imports posekit. Every process gets its own
``ROS_DOMAIN_ID``; every wait is bounded.
"""

from __future__ import annotations

import hashlib
import json
import sys
import textwrap
import time
from pathlib import Path
from typing import Any

import pytest

from _support.dds import dds_context, dds_domain, posekit_env, spin_until
from _support.procs import Proc
from _support.ros2 import ROS_MSG_HELPERS, ros2_env, ros2_python
from posekit.cli.topic_cmd import message_to_ordered, set_message_fields
from posekit.msgs.registry import get_message_class
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.logging import LogRecord
from posekit.runtime.node import Node, NodeNameNonExistentError
from posekit.runtime.qos import QoSProfile, ReliabilityPolicy

pytestmark = pytest.mark.slow

HEADER = {"stamp": {"sec": 1712345678, "nanosec": 987654321}, "frame_id": "odom"}
QUAT = {"x": 0.0, "y": 0.0, "z": 0.3826834323650898, "w": 0.9238795325112867}
POSE = {"position": {"x": 1.5, "y": -2.25, "z": 0.125}, "orientation": QUAT}
TWIST = {"linear": {"x": 0.5, "y": -0.125, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": -0.75}}
COV = [i * 0.5 - 3.0 for i in range(36)]
COV9 = [0.01 * (i + 1) for i in range(9)]
VEC = {"x": 0.25, "y": -9.81, "z": 1e-3}

#: One fully specified message per type both sides have: name -> (type, values).
SPEC: dict[str, tuple[str, dict[str, Any]]] = {
    "string": ("std_msgs/msg/String", {"data": "héllo wörld ✓ \t 42"}),
    "transform": ("geometry_msgs/msg/TransformStamped", {
        "header": HEADER, "child_frame_id": "base_link",
        "transform": {"translation": {"x": 1.5, "y": -2.25, "z": 0.125}, "rotation": QUAT}}),
    "twist": ("geometry_msgs/msg/TwistStamped", {"header": HEADER, "twist": TWIST}),
    "pose": ("geometry_msgs/msg/PoseStamped", {"header": HEADER, "pose": POSE}),
    "odometry": ("nav_msgs/msg/Odometry", {
        "header": HEADER, "child_frame_id": "base_link",
        "pose": {"pose": POSE, "covariance": COV},
        "twist": {"twist": TWIST, "covariance": COV[::-1]}}),
    "image": ("sensor_msgs/msg/Image", {
        "header": HEADER, "height": 4, "width": 3, "encoding": "rgb8", "is_bigendian": 0,
        "step": 9, "data": [(i * 37) % 256 for i in range(36)]}),
    "camera_info": ("sensor_msgs/msg/CameraInfo", {
        "header": HEADER, "height": 480, "width": 640, "distortion_model": "plumb_bob",
        "d": [0.1, -0.2, 0.001, 0.002, 0.0],
        "k": [525.0, 0.0, 319.5, 0.0, 525.0, 239.5, 0.0, 0.0, 1.0],
        "r": [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
        "p": [525.0, 0.0, 319.5, 0.0, 0.0, 525.0, 239.5, 0.0, 0.0, 0.0, 1.0, 0.0],
        "binning_x": 1, "binning_y": 2,
        "roi": {"x_offset": 1, "y_offset": 2, "height": 3, "width": 4, "do_rectify": True}}),
    "imu": ("sensor_msgs/msg/Imu", {
        "header": HEADER, "orientation": QUAT, "orientation_covariance": COV9,
        "angular_velocity": VEC, "angular_velocity_covariance": COV9[::-1],
        "linear_acceleration": VEC, "linear_acceleration_covariance": COV9}),
    "joint_state": ("sensor_msgs/msg/JointState", {
        "header": HEADER, "name": ["fl_wheel_joint", "fr_wheel_joint"],
        "position": [1.0, -2.5], "velocity": [0.5, -0.5], "effort": []}),
    "clock": ("rosgraph_msgs/msg/Clock", {"clock": {"sec": 42, "nanosec": 7}}),
}
BIG_W, BIG_H = 1280, 720

REFERENCE = ROS_MSG_HELPERS + textwrap.dedent("""
    import hashlib, json, sys, time
    import rclpy
    from sensor_msgs.msg import Image
    from std_msgs.msg import String

    SPEC = json.loads(sys.argv[1])
    W, H = int(sys.argv[2]), int(sys.argv[3])
    rclpy.init()
    node = rclpy.create_node("ros_interop")
    received, expected, pubs = {}, {}, []
    for name, (ros_type, values) in SPEC.items():
        cls = msg_class(ros_type)
        msg = make(cls, values)
        expected[name] = to_plain(msg)
        pubs.append((node.create_publisher(cls, f"/interop/{name}/from_ros", 10), msg))
        node.create_subscription(
            cls, f"/interop/{name}/from_pk",
            lambda m, name=name: received.setdefault(name, to_plain(m)), 10)
    big = Image(height=H, width=W, encoding="rgb8", step=3 * W)
    big.data = hashlib.shake_128(b"posekit big image").digest(3 * W * H)
    big_pub = node.create_publisher(Image, "/interop/big/from_ros", 2)
    node.create_subscription(Image, "/interop/big/from_pk", lambda m: received.setdefault(
        "big", [m.height, m.width, m.encoding, hashlib.sha256(bytes(m.data)).hexdigest()]), 2)
    done = []
    node.create_subscription(String, "/interop/done", lambda m: done.append(m.data), 10)
    names, graph = [], {}
    deadline, next_pub = time.monotonic() + 45, 0.0
    while time.monotonic() < deadline and not (
            done and graph and len(received) == len(SPEC) + 1):
        rclpy.spin_once(node, timeout_sec=0.05)
        if time.monotonic() >= next_pub:
            for pub, msg in pubs:
                pub.publish(msg)
            big_pub.publish(big)
            next_pub = time.monotonic() + 0.3
            names = node.get_node_names_and_namespaces()
            if ["posekit_interop", "/"] in [list(n) for n in names]:
                pubs_of = node.get_publisher_names_and_types_by_node("posekit_interop", "/")
                subs_of = node.get_subscriber_names_and_types_by_node("posekit_interop", "/")
                info = node.get_publishers_info_by_topic("/interop/odometry/from_pk")
                graph = {"pubs": sorted([n, t] for n, ts in pubs_of for t in ts),
                         "subs": sorted([n, t] for n, ts in subs_of for t in ts),
                         "odom_pub": [[i.node_name, i.node_namespace, i.topic_type,
                                       i.qos_profile.reliability.name] for i in info]}
    print(json.dumps({"received": received, "expected": expected, "nodes": names,
                      "graph": graph, "done": done}), flush=True)
    node.destroy_node()
    rclpy.shutdown()
""")


def _start_reference(domain_id: int, source: str, *args: str) -> Proc:
    return Proc([str(ros2_python()), "-c", source, *args], env=ros2_env(domain_id))


def _last_json(proc: Proc) -> Any:
    for line in reversed(proc.out):
        if line.startswith("{"):
            return json.loads(line)
    raise AssertionError(f"no JSON from the reference process\n{proc.describe()}")


def test_every_shared_type_both_ways_with_a_large_image_and_the_graph(
        monkeypatch: pytest.MonkeyPatch) -> None:
    domain = dds_domain(monkeypatch)
    context = dds_context()
    proc = _start_reference(domain, REFERENCE, json.dumps(SPEC), str(BIG_W), str(BIG_H))
    try:
        node = Node("posekit_interop", context=context)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        got: dict[str, Any] = {}
        outgoing = []
        for name, (ros_type, values) in SPEC.items():
            cls = get_message_class(ros_type)
            msg = cls()
            set_message_fields(msg, values)
            outgoing.append((node.create_publisher(cls, f"/interop/{name}/from_pk", 10), msg))
            node.create_subscription(
                cls, f"/interop/{name}/from_ros",
                lambda m, name=name: got.setdefault(name, message_to_ordered(m, None)), 10)
        image_cls = get_message_class("sensor_msgs/msg/Image")
        big = image_cls(height=BIG_H, width=BIG_W, encoding="rgb8", step=3 * BIG_W,
                        data=hashlib.shake_128(b"posekit big image").digest(3 * BIG_W * BIG_H))
        big_pub = node.create_publisher(image_cls, "/interop/big/from_pk", 2)
        node.create_subscription(image_cls, "/interop/big/from_ros", lambda m: got.setdefault(
            "big", [m.height, m.width, m.encoding,
                    hashlib.sha256(bytes(m.data)).hexdigest()]), 2)
        string_cls = get_message_class("std_msgs/msg/String")
        done_pub = node.create_publisher(string_cls, "/interop/done", 10)
        seen_nodes: set[str] = set()
        ours: dict[str, list[tuple[str, list[str]]]] = {}
        next_pub = [0.0]

        def publish_all() -> None:
            if time.monotonic() < next_pub[0]:
                return
            next_pub[0] = time.monotonic() + 0.3
            for pub, msg in outgoing:
                pub.publish(msg)
            big_pub.publish(big)
            seen_nodes.update(node.transport.get_node_names())  # type: ignore[attr-defined]
            try:  # the real node's endpoints, by node (its discovery info matched to GIDs)
                pubs_of = node.get_publisher_names_and_types_by_node("ros_interop", "/")
                subs_of = node.get_subscriber_names_and_types_by_node("ros_interop", "/")
            except NodeNameNonExistentError:
                pass  # not discovered yet, or gone once done
            else:  # the fullest view (discovery fills it in; the end takes it apart)
                if len(pubs_of) + len(subs_of) > sum(map(len, ours.values())):
                    ours.update(pubs=pubs_of, subs=subs_of)
            if len(got) == len(SPEC) + 1 and "/ros_interop" in seen_nodes:
                done_pub.publish(string_cls(data="done"))

        assert spin_until(executor, lambda: proc.popen.poll() is not None, 50, publish_all), \
            f"reference did not finish\ngot {sorted(got)}\n{proc.describe()}"
        result = _last_json(proc)
    finally:
        proc.kill()
        context.try_shutdown()

    expected = result["expected"]
    # real rclpy -> posekit, field for field against rclpy's own rendering of what it sent
    assert sorted(got) == sorted([*SPEC, "big"]), f"posekit missed {set(SPEC) - set(got)}"
    for name in SPEC:
        assert got[name] == expected[name], name
    # posekit -> real rclpy
    assert sorted(result["received"]) == sorted([*SPEC, "big"]), proc.describe()
    for name in SPEC:
        assert result["received"][name] == expected[name], name
    # a 1280x720 rgb8 image arrives whole both ways (2.7 MB, fragmented on the wire)
    digest = hashlib.sha256(hashlib.shake_128(b"posekit big image").digest(
        3 * BIG_W * BIG_H)).hexdigest()
    assert got["big"] == [BIG_H, BIG_W, "rgb8", digest]
    assert result["received"]["big"] == [BIG_H, BIG_W, "rgb8", digest]
    # the graph both ways: each side lists the other's node, the real one with the posekit
    # node's publishers and subscriptions (ros_discovery_info's GIDs matched to endpoints)
    assert ["posekit_interop", "/"] in result["nodes"]
    assert "/ros_interop" in seen_nodes
    graph = result["graph"]
    for name, (ros_type, _values) in SPEC.items():
        assert [f"/interop/{name}/from_pk", ros_type] in graph["pubs"], name
        assert [f"/interop/{name}/from_ros", ros_type] in graph["subs"], name
    assert ["/interop/done", "std_msgs/msg/String"] in graph["pubs"]
    assert graph["odom_pub"] == [["posekit_interop", "/", "nav_msgs/msg/Odometry", "RELIABLE"]]
    # and posekit's node lists the real node's topics by node, as rclpy does its own
    assert ours, "the real node was never found by name"
    assert dict(ours["pubs"]) == {
        **{f"/interop/{name}/from_ros": [ros_type] for name, (ros_type, _) in SPEC.items()},
        "/interop/big/from_ros": ["sensor_msgs/msg/Image"],
        "/parameter_events": ["rcl_interfaces/msg/ParameterEvent"],
        "/rosout": ["rcl_interfaces/msg/Log"]}
    assert dict(ours["subs"]) == {
        **{f"/interop/{name}/from_pk": [ros_type] for name, (ros_type, _) in SPEC.items()},
        "/interop/big/from_pk": ["sensor_msgs/msg/Image"],
        "/interop/done": ["std_msgs/msg/String"]}


BAD_PEERS = textwrap.dedent("""
    import sys, time
    import rclpy
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from std_msgs.msg import Int32, String
    rclpy.init()
    node = rclpy.create_node("bad_peers")
    best_effort = node.create_publisher(
        String, "/qos_probe", QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT))
    other_type = node.create_publisher(Int32, "/type_probe", 5)
    alive = node.create_publisher(String, "/alive", 5)
    node.create_subscription(String, "/be_from_pk", lambda m: None, 5)  # RELIABLE
    deadline = time.monotonic() + float(sys.argv[1])
    i = 0
    while time.monotonic() < deadline:
        best_effort.publish(String(data=f"be {i}"))
        other_type.publish(Int32(data=i))
        alive.publish(String(data=f"alive {i}"))
        i += 1
        rclpy.spin_once(node, timeout_sec=0.1)
    rclpy.shutdown()
""")


def test_incompatible_qos_and_another_type_each_log_one_reason_and_the_node_runs_on(
        monkeypatch: pytest.MonkeyPatch, logs: list[LogRecord]) -> None:
    domain = dds_domain(monkeypatch)
    context = dds_context()
    proc = _start_reference(domain, BAD_PEERS, "25")
    try:
        node = Node("posekit_strict", context=context)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        string_cls = get_message_class("std_msgs/msg/String")
        wrong: list[Any] = []
        alive: list[str] = []
        node.create_subscription(string_cls, "/qos_probe", wrong.append, QoSProfile(depth=5))
        node.create_subscription(string_cls, "/type_probe", wrong.append, 5)
        node.create_subscription(string_cls, "/alive", lambda m: alive.append(m.data), 5)
        node.create_publisher(string_cls, "/be_from_pk", QoSProfile(
            depth=5, reliability=ReliabilityPolicy.BEST_EFFORT))

        def warnings(word: str) -> list[str]:
            return [r.message for r in logs if r.name == "posekit_strict" and word in r.message]

        assert spin_until(executor, lambda: bool(
            warnings("offering incompatible QoS") and warnings("requesting incompatible QoS")
            and warnings("also has endpoints of type")
            and len(alive) >= 3), 25), f"{[r.message for r in logs]}\n{proc.describe()}"
        spin_until(executor, lambda: False, 1.0)  # more samples from the same peers
    finally:
        proc.kill()
        context.try_shutdown()
    qos_warnings = warnings("offering incompatible QoS")
    assert len(qos_warnings) == 1, qos_warnings
    assert "'/qos_probe'" in qos_warnings[0]
    assert "RELIABILITY" in qos_warnings[0]
    # and the other way round: posekit's BEST_EFFORT publisher, a real RELIABLE subscription
    offer_warnings = warnings("requesting incompatible QoS")
    assert len(offer_warnings) == 1, offer_warnings
    assert "'/be_from_pk'" in offer_warnings[0]
    assert "RELIABILITY" in offer_warnings[0]
    type_warnings = warnings("also has endpoints of type")
    assert len(type_warnings) == 1, type_warnings
    assert "std_msgs/msg/Int32" in type_warnings[0]
    assert "'/type_probe'" in type_warnings[0]
    assert wrong == []  # neither pairing delivers anything, as between real ROS 2 nodes
    assert alive  # and the node kept receiving what it can


INDEPENDENT_TF_READER = textwrap.dedent('''
    """Reads /tf_static as a late joiner with plain cyclonedds; TFMessage defined here."""
    import json, sys, time
    from dataclasses import dataclass
    from cyclonedds.domain import Domain, DomainParticipant
    from cyclonedds.idl import IdlStruct
    from cyclonedds.idl.types import int32, uint32, float64, sequence
    from cyclonedds.qos import Policy, Qos
    from cyclonedds.sub import DataReader
    from cyclonedds.topic import Topic

    @dataclass
    class Time(IdlStruct, typename="builtin_interfaces::msg::dds_::Time_"):
        sec: int32
        nanosec: uint32

    @dataclass
    class Header(IdlStruct, typename="std_msgs::msg::dds_::Header_"):
        stamp: Time
        frame_id: str

    @dataclass
    class Vector3(IdlStruct, typename="geometry_msgs::msg::dds_::Vector3_"):
        x: float64
        y: float64
        z: float64

    @dataclass
    class Quaternion(IdlStruct, typename="geometry_msgs::msg::dds_::Quaternion_"):
        x: float64
        y: float64
        z: float64
        w: float64

    @dataclass
    class Transform(IdlStruct, typename="geometry_msgs::msg::dds_::Transform_"):
        translation: Vector3
        rotation: Quaternion

    @dataclass
    class TransformStamped(IdlStruct, typename="geometry_msgs::msg::dds_::TransformStamped_"):
        header: Header
        child_frame_id: str
        transform: Transform

    @dataclass
    class TFMessage(IdlStruct, typename="tf2_msgs::msg::dds_::TFMessage_"):
        transforms: sequence[TransformStamped]

    domain_id = int(sys.argv[1])
    config = ('<CycloneDDS><Domain><General><Interfaces><NetworkInterface address="127.0.0.1"/>'
              '</Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery>'
              '<ParticipantIndex>auto</ParticipantIndex><Peers><Peer address="localhost"/>'
              '</Peers></Discovery></Domain></CycloneDDS>')
    domain = Domain(domain_id, config)
    participant = DomainParticipant(domain_id)
    topic = Topic(participant, "rt/tf_static", TFMessage)
    reader = DataReader(participant, topic, Qos(
        Policy.Reliability.Reliable(0), Policy.Durability.TransientLocal,
        Policy.History.KeepLast(1)))
    out = []
    deadline = time.monotonic() + 20
    while not out and time.monotonic() < deadline:
        for sample in reader.take(N=10):
            out += [[t.header.frame_id, t.child_frame_id, t.transform.translation.x,
                     t.transform.translation.y, t.transform.rotation.z, t.transform.rotation.w,
                     t.header.stamp.sec] for t in sample.transforms]
        time.sleep(0.05)
    print(json.dumps(out), flush=True)
''')


def test_late_independent_reader_gets_tf_static_from_posekit(
        monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    from posekit.msgs.geometry_msgs import TransformStamped
    from posekit.tf2_ros import StaticTransformBroadcaster

    domain = dds_domain(monkeypatch)
    context = dds_context()
    try:
        node = Node("static_publisher", context=context)
        transforms = []
        for child, x in (("camera", 0.1), ("lidar", -0.2)):
            t = TransformStamped()
            t.header.frame_id, t.child_frame_id = "base_link", child
            t.header.stamp.sec = 77
            t.transform.translation.x, t.transform.translation.y = x, 2 * x
            t.transform.rotation.z, t.transform.rotation.w = 0.6, 0.8
            transforms.append(t)
        StaticTransformBroadcaster(node).sendTransform(transforms)
        script = tmp_path / "tf_reader.py"
        script.write_text(INDEPENDENT_TF_READER)
        # The reader joins after the transforms were sent (transient local hands them over).
        reader = Proc([sys.executable, "-I", str(script), str(domain)],
                      env=posekit_env(domain))
        out = reader.finish(30, "the independent /tf_static reader")
    finally:
        context.try_shutdown()
    rows = json.loads(out.strip().splitlines()[-1])
    assert sorted(rows) == [
        ["base_link", "camera", 0.1, 0.2, 0.6, 0.8, 77],
        ["base_link", "lidar", -0.2, -0.4, 0.6, 0.8, 77],
    ], reader.describe()


REAL_SERVICES = textwrap.dedent("""
    import sys, time
    import rclpy
    from std_srvs.srv import SetBool
    rclpy.init()
    node = rclpy.create_node("real_services")
    node.create_service(SetBool, "/real_flip", lambda req, resp: resp)
    client = node.create_client(SetBool, "/posekit_flip")
    print("ready", flush=True)
    deadline = time.monotonic() + float(sys.argv[1])
    future = None
    while time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.05)
        if future is None and client.service_is_ready():
            print("sees the posekit server", flush=True)
            future = client.call_async(SetBool.Request(data=True))
        elif future is not None and future.done():
            print("answered", flush=True)
            future = None
""")


def test_fast_dds_services_are_refused_with_a_reason_not_misread(
        monkeypatch: pytest.MonkeyPatch, logs: list[LogRecord]) -> None:
    """rmw_fastrtps's service format is not rmw_cyclonedds's: neither side is misread.

    posekit's server never hands a Fast DDS request to its callback, posekit's client never
    counts a Fast DDS server as available (and says why once).

    Oracle: the real rclpy on Fast DDS (its server and client are found on the graph).
    """
    from posekit.msgs.std_srvs import SetBool

    domain = dds_domain(monkeypatch)
    real = Proc([str(ros2_python()), "-c", REAL_SERVICES, "25"], env=ros2_env(domain))
    context = dds_context()
    try:
        node = Node("posekit_services", context=context)
        called: list[Any] = []
        node.create_service(SetBool, "/posekit_flip",
                            lambda req, resp: called.append(req) or resp)
        client = node.create_client(SetBool, "/real_flip")
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        real.wait_line(lambda line: line.startswith("ready"), 60, "the real node")
        assert spin_until(executor, lambda: node.count_services("/real_flip") == 1, 20)
        real.wait_line(lambda line: "sees the posekit server" in line, 20, "the real client")
        # the real server is on the graph but never counted as available
        assert not spin_until(executor, client.service_is_ready, 2.0)
        # its requests (no header) never reach the callback: Cyclone discards a payload
        # shorter than the header-carrying type, posekit one from a writer without clientid
        assert not spin_until(executor, lambda: bool(called), 2.0)
    finally:
        real.kill()
        context.try_shutdown()
    assert called == []
    assert not any("answered" in line for line in real.out)
    assert any("a server cannot be called" in r.message and "'/real_flip'" in r.message
               for r in logs)
