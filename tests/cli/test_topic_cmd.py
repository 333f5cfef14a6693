"""posekit topic: YAML dumps against PyYAML, VALUES parsing, hz statistics, verbs in-process."""

from __future__ import annotations

import dataclasses
import io
import math
import sys
import threading
import time
from typing import Any

import numpy as np
import pytest
import yaml
from hypothesis import given
from hypothesis import strategies as st

from posekit.cli import topic_cmd
from posekit.cli.main import main as posekit_main
from posekit.cli.topic_cmd import (
    MessageFieldError,
    hz_report,
    message_to_ordered,
    message_to_yaml,
    ros_repr,
    set_message_fields,
    yaml_scalar,
)
from posekit.msgs import yaml_io
from posekit.msgs.geometry_msgs import TransformStamped, Twist, Vector3
from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.registry import MESSAGE_CLASSES
from posekit.msgs.sensor_msgs import Image, JointState
from posekit.msgs.std_msgs import String
from posekit.msgs.tf2_msgs import TFMessage
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node


class _RosDumper(yaml.SafeDumper):
    """What rosidl_runtime_py.message_to_yaml does: ordered mappings, block style."""


_RosDumper.add_representer(
    dict, lambda d, data: d.represent_mapping("tag:yaml.org,2002:map", data.items())
)


def pyyaml_dump(data: Any) -> str:
    return str(yaml.dump(data, Dumper=_RosDumper, allow_unicode=True, width=sys.maxsize,
                         default_flow_style=False))


def filled(cls: type, seed: int) -> Any:
    """A message with every field set to a non-default value derived from ``seed``."""
    rng = np.random.default_rng(seed)
    msg = cls()
    for f in dataclasses.fields(msg):
        value = getattr(msg, f.name)
        if dataclasses.is_dataclass(value):
            setattr(msg, f.name, filled(type(value), seed + 1))
        elif isinstance(value, np.ndarray):
            n = value.size or 3
            setattr(msg, f.name, (rng.integers(0, 200, n)).astype(value.dtype)
                    if value.dtype.kind in "iu" else rng.normal(size=n).astype(value.dtype))
        elif isinstance(value, list):
            elem = yaml_io._list_element_class(cls, f.name)
            setattr(msg, f.name, [filled(elem, seed + i) for i in range(2)] if elem
                    else ["a", "1.5"])
        elif isinstance(value, bool):
            setattr(msg, f.name, True)
        elif isinstance(value, int):
            setattr(msg, f.name, int(rng.integers(0, 100)))
        elif isinstance(value, float):
            setattr(msg, f.name, float(rng.normal()))
        elif isinstance(value, str):
            setattr(msg, f.name, f"{f.name}_{seed}")
    return msg


@pytest.mark.parametrize("type_name", sorted(MESSAGE_CLASSES))
def test_every_message_dumps_like_pyyaml(type_name: str) -> None:
    cls = MESSAGE_CLASSES[type_name]
    for msg in (cls(), filled(cls, 3)):
        text = message_to_yaml(msg)
        assert text == pyyaml_dump(message_to_ordered(msg))
        # and the dump reads back to the same values
        assert yaml.safe_load(text) == message_to_ordered(msg)


def test_tf_message_dump_is_ros2_topic_echo_layout() -> None:
    t = TransformStamped(child_frame_id="base_link")
    t.header.frame_id = "odom"
    t.header.stamp.sec, t.header.stamp.nanosec = 1, 2
    t.transform.translation = Vector3(x=1.0, y=2.0, z=3.0)
    expected = (
        "transforms:\n- header:\n    stamp:\n      sec: 1\n      nanosec: 2\n"
        "    frame_id: odom\n  child_frame_id: base_link\n  transform:\n    translation:\n"
        "      x: 1.0\n      y: 2.0\n      z: 3.0\n    rotation:\n      x: 0.0\n      y: 0.0\n"
        "      z: 0.0\n      w: 1.0\n"
    )
    assert message_to_yaml(TFMessage([t])) == expected
    assert message_to_yaml(TFMessage()) == "transforms: []\n"


CURATED = ["", "a", "1", "1.5", "1e5", "yes", "No", "null", "~", "a: b", "a:b", "a #b", "#a",
           "-a", "- a", "-", "?", ":", "? a", "'q'", '"', "a'b", " lead", "trail ", "---x",
           "...", "2020-01-01", "0x1F", "1_000", ".inf", "-.Inf", ".nan", "<<", "=",
           "tab\there", "é", "\x01", "a,b", "[a]", "{a}", "@x", "%x", "&x", "*x", "!x", "|x",
           ">x", "`x", "a:", "1:20", "+1", "08", "0b101", ".5", "True", "on", "OFF", "y"]


@pytest.mark.parametrize("text", CURATED)
def test_scalar_quoting_matches_pyyaml(text: str) -> None:
    assert pyyaml_dump({"k": text}) == f"k: {yaml_scalar(text)}\n"


@given(st.text(alphabet=st.characters(min_codepoint=0x20, max_codepoint=0x7E), max_size=12))
def test_printable_strings_quote_like_pyyaml(text: str) -> None:
    assert pyyaml_dump({"k": text}) == f"k: {yaml_scalar(text)}\n"


@given(st.floats(allow_nan=True, allow_infinity=True))
def test_floats_print_like_pyyaml(value: float) -> None:
    assert pyyaml_dump({"k": value}) == f"k: {yaml_scalar(value)}\n"


def test_truncation_to_128_like_ros2_topic_echo() -> None:
    img = Image(encoding="x" * 200, data=np.arange(300, dtype=np.uint8).astype(np.uint8))
    data = yaml.safe_load(message_to_yaml(img))
    assert data["encoding"] == "x" * 128 + "..."
    assert data["data"][:128] == list(range(128))
    assert data["data"][128] == "..."
    assert len(data["data"]) == 129
    full = yaml.safe_load(message_to_yaml(img, truncate_length=None))
    assert len(full["data"]) == 300


def test_ros_repr_matches_rclpy_format() -> None:
    assert ros_repr(String(data="hi")) == "std_msgs.msg.String(data='hi')"
    assert ros_repr(Twist()) == (
        "geometry_msgs.msg.Twist(linear=geometry_msgs.msg.Vector3(x=0.0, y=0.0, z=0.0), "
        "angular=geometry_msgs.msg.Vector3(x=0.0, y=0.0, z=0.0))"
    )
    js = JointState(name=["j"], position=np.array([1.5]))
    assert "name=['j'], position=[1.5], velocity=[], effort=[]" in ros_repr(js)
    assert "covariance=array([0., 0.," in ros_repr(Odometry())  # fixed-size: numpy, as rclpy


@pytest.mark.slow
def test_a_type_posekit_has_no_class_for_is_built_and_printed_as_rclpy() -> None:
    """Oracle: the real rclpy's repr of the same NavSatFix (its status defaults to -2)."""
    from _support.ros2 import run_ros2_script

    values = ("{latitude: 1.5, status: {service: 1}, "
              "position_covariance: [1, 2, 3, 4, 5, 6, 7, 8, 9]}")
    ref = run_ros2_script(
        "from sensor_msgs.msg import NavSatFix, NavSatStatus\n"
        "print(repr(NavSatFix(latitude=1.5, status=NavSatStatus(service=1), "
        "position_covariance=[float(i) for i in range(1, 10)])))\n", domain_id=0)
    assert ref.returncode == 0, ref.stderr
    msg = yaml_io.default_message("sensor_msgs/msg/NavSatFix")
    set_message_fields(msg, yaml_io.parse_values(values))
    assert ros_repr(msg) == ref.stdout.strip()
    # echo shows the fields, not the constants rosbags' class carries as dataclass fields
    assert list(message_to_ordered(msg)["status"]) == ["status", "service"]


def test_set_message_fields_converts_like_ros2cli() -> None:
    msg = TFMessage()
    set_message_fields(msg, yaml.safe_load(
        "{transforms: [{header: {frame_id: a}, child_frame_id: b, "
        "transform: {translation: {x: 1, y: 2}, rotation: {w: 1}}}]}"
    ))
    t = msg.transforms[0]
    assert isinstance(t, TransformStamped)
    assert (t.header.frame_id, t.child_frame_id) == ("a", "b")
    assert t.transform.translation.x == 1.0
    assert isinstance(t.transform.translation.x, float)
    odom = Odometry()
    set_message_fields(odom, {"pose": {"covariance": list(range(36))}, "child_frame_id": 5})
    assert odom.pose.covariance.dtype == np.float64
    assert odom.pose.covariance[35] == 35.0
    assert odom.child_frame_id == "5"  # str(5), as rosidl_runtime_py does
    before = time.time()
    set_message_fields(odom, {"header": "auto"})
    assert abs(odom.header.stamp.sec + odom.header.stamp.nanosec * 1e-9 - before) < 5
    t2 = TransformStamped()
    set_message_fields(t2, {"header": {"stamp": "now", "frame_id": "m"}})
    assert t2.header.stamp.sec >= int(before)
    assert t2.header.frame_id == "m"


@pytest.mark.parametrize(("values", "match"), [
    ({"nope": 1}, "no field 'nope'"),
    ({"linear": {"x": "fast"}}, "linear.x"),
    ({"linear": 3}, "linear: expected a mapping"),
    ([1, 2], "expected a mapping"),
])
def test_set_message_fields_errors_name_the_field(values: Any, match: str) -> None:
    with pytest.raises(MessageFieldError, match=match):
        set_message_fields(Twist(), values)
    with pytest.raises(MessageFieldError, match="expected 36 values"):
        set_message_fields(Odometry(), {"pose": {"covariance": [1.0, 2.0]}})


def test_hz_report_statistics() -> None:
    # Jazzy's ros2topic hz prints the number of inter-arrival times in the window (n)
    deltas = [100_000_000, 110_000_000, 90_000_000, 100_000_000]
    arr = np.array(deltas) * 1e-9
    text = hz_report(deltas)
    assert text == (
        f"average rate: {1 / arr.mean():.3f}\n"
        f"\tmin: {arr.min():.3f}s max: {arr.max():.3f}s std dev: {arr.std():.5f}s window: 4\n"
    )
    assert text.startswith("average rate: 10.000\n\tmin: 0.090s max: 0.110s std dev: 0.00707s")


# -- verbs on the in-process transport (same code paths as over Zenoh) ---------------------


@pytest.fixture
def ctx() -> Any:
    context = Context()
    context.init(transport="inprocess")
    yield context
    context.try_shutdown()


def test_list_and_info(ctx: Context) -> None:
    node = Node("talker", context=ctx)
    node.create_publisher(Twist, "/cmd_vel", 10)
    node.create_publisher(String, "/_hidden/x", 10)
    out = io.StringIO()
    assert topic_cmd.main(["list", "-t"], context=ctx, out=out) == 0
    # every node (the tool's too) has /parameter_events and /rosout, as in ROS 2
    assert out.getvalue() == (
        "/cmd_vel [geometry_msgs/msg/Twist]\n"
        "/parameter_events [rcl_interfaces/msg/ParameterEvent]\n"
        "/rosout [rcl_interfaces/msg/Log]\n"
    )
    out = io.StringIO()
    topic_cmd.main(["list", "--include-hidden-topics", "-c"], context=ctx, out=out)
    assert out.getvalue() == "4\n"
    out = io.StringIO()
    assert topic_cmd.main(["info", "cmd_vel"], context=ctx, out=out) == 0
    assert out.getvalue() == (
        "Type: geometry_msgs/msg/Twist\nPublisher count: 1\nSubscription count: 0\n"
    )
    err = io.StringIO()
    assert topic_cmd.main(["info", "/nothing"], context=ctx, out=out, err=err) == 1
    assert err.getvalue() == "Unknown topic '/nothing'\n"


def test_pub_once_reaches_a_subscriber_and_prints_like_ros2(ctx: Context) -> None:
    node = Node("listener", context=ctx)
    got: list[Twist] = []
    node.create_subscription(Twist, "/cmd_vel", got.append, 10)
    executor = SingleThreadedExecutor(context=ctx)
    executor.add_node(node)
    out = io.StringIO()
    code = topic_cmd.main(["pub", "/cmd_vel", "geometry_msgs/msg/Twist",
                           "{linear: {x: 0.5}, angular: {z: -1}}", "--once"], context=ctx, out=out)
    assert code == 0
    executor.spin_some(0.1)
    assert len(got) == 1
    assert got[0].linear.x == 0.5
    assert got[0].angular.z == -1.0
    assert out.getvalue() == (
        "publisher: beginning loop\n"
        "publishing #1: geometry_msgs.msg.Twist(linear=geometry_msgs.msg.Vector3(x=0.5, "
        "y=0.0, z=0.0), angular=geometry_msgs.msg.Vector3(x=0.0, y=0.0, z=-1.0))\n\n"
    )
    err = io.StringIO()
    assert topic_cmd.main(["pub", "/cmd_vel", "geometry_msgs/msg/Twist", "{linear: {q: 1}}"],
                          context=ctx, out=out, err=err) == 1
    assert "Failed to populate field" in err.getvalue()
    assert "q" in err.getvalue()
    assert topic_cmd.main(["pub", "/x", "nope_msgs/msg/Nope", "{}"], context=ctx, out=out,
                          err=err) == 1
    assert "nope_msgs/msg/Nope" in err.getvalue()


def test_echo_learns_type_and_prints_messages(ctx: Context) -> None:
    node = Node("talker", context=ctx)
    pub = node.create_publisher(String, "/chatter", 10)
    out = io.StringIO()
    result: list[int] = []
    thread = threading.Thread(target=lambda: result.append(topic_cmd.main(
        ["echo", "/chatter", "--count", "2"], context=ctx, out=out, err=io.StringIO())))
    thread.start()
    deadline = time.monotonic() + 10
    i = 0
    while thread.is_alive() and time.monotonic() < deadline:
        pub.publish(String(data=f"m{i}"))
        i += 1
        time.sleep(0.02)
    thread.join(1)
    assert result == [0], "echo did not exit after --count 2"
    blocks = out.getvalue().split("---\n")
    assert blocks[2] == ""
    assert len(blocks) == 3
    assert [yaml.safe_load(b)["data"] for b in blocks[:2]] == [
        f"m{int(yaml.safe_load(blocks[0])['data'][1:])}",
        f"m{int(yaml.safe_load(blocks[0])['data'][1:]) + 1}",
    ]


def test_hz_reports_the_publish_rate(ctx: Context) -> None:
    node = Node("talker", context=ctx)
    pub = node.create_publisher(String, "/fast", 10)
    out = io.StringIO()
    thread = threading.Thread(target=topic_cmd.main, args=(["hz", "/fast", "--count", "1"],),
                              kwargs={"context": ctx, "out": out, "err": io.StringIO()})
    thread.start()
    deadline = time.monotonic() + 10
    while thread.is_alive() and time.monotonic() < deadline:
        pub.publish(String())
        time.sleep(0.01)
    thread.join(1)
    first, second = out.getvalue().splitlines()[:2]
    rate = float(first.split(": ")[1])
    assert first.startswith("average rate: ")
    assert 10 < rate < 150
    assert second.startswith("\tmin: ")
    assert "window: " in second
    assert math.isfinite(float(second.split("std dev: ")[1].split("s")[0]))


def test_dispatcher_routes_topic_and_node(capsys: pytest.CaptureFixture[str]) -> None:
    assert posekit_main(["topic"]) == 0  # as `ros2 topic`: the verbs, on stdout
    listing = capsys.readouterr().out
    for verb in ("list", "info", "type", "find", "echo", "hz", "bw", "delay", "pub"):
        assert f"\n  {verb} " in listing
    assert posekit_main(["topic", "bogus"]) == 2
    assert "posekit topic: error: unknown verb 'bogus'" in capsys.readouterr().err
    assert posekit_main(["nosuch"]) == 2
    assert "posekit: error: unknown command 'nosuch'" in capsys.readouterr().err
    assert posekit_main(["--help"]) == 0
    text = capsys.readouterr().out
    for verb in ("topic list", "topic echo", "topic hz", "topic pub", "node list", "router"):
        assert verb in text


@pytest.mark.parametrize("rate", ["nan", "inf", "0", "-5"])
def test_pub_refuses_a_rate_that_is_no_positive_finite_number(ctx: Context, rate: str) -> None:
    """One line on stderr and exit 2, no timer created (rclpy would raise on NaN/inf)."""
    err = io.StringIO()
    code = topic_cmd.main(["pub", "/cmd_vel", "geometry_msgs/msg/Twist", "{}", f"--rate={rate}"],
                          context=ctx, out=io.StringIO(), err=err)
    assert code == 2
    assert err.getvalue().count("\n") == 1
    assert "rate must be a positive finite number" in err.getvalue()
