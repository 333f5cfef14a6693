"""``posekit topic`` and ``node info`` verbs against a system running in another process.

One system per module (a Zenoh publisher of /odom, /chatter and /tf, and a subscriber of
/cmd_vel, in a separate Python process) and many verbs against it, run in-process on a Zenoh
context of their own. Oracles: the output formats of the Jazzy ros2cli sources (ros2topic's
list/type/find/echo/hz/bw/delay verbs and rosidl_runtime_py's ``message_to_yaml`` /
``message_to_csv``; ros2node's ``info``), PyYAML for flow style and for reading YAML back,
the publisher's own values and rates, and the CDR size from rosbags' serializer.
"""

from __future__ import annotations

import io
import json
import os
import sys
import textwrap
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml

from _support.ports import free_port
from _support.procs import Proc
from posekit.cli import node_cmd, topic_cmd
from posekit.cli.errors import CliError
from posekit.msgs.yaml_io import MessageFieldError
from posekit.runtime.context import Context

pytestmark = pytest.mark.slow

SYSTEM = """
import math, time
from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.std_msgs import String
from posekit.msgs.geometry_msgs import Twist
from posekit.msgs.tf2_msgs import TFMessage
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
ctx = Context(); ctx.init(transport="zenoh")
node = Node("system", namespace="/robot", context=ctx)
odom = node.create_publisher(Odometry, "/odom", 10)
chatter = node.create_publisher(String, "/chatter", 10)
tf = node.create_publisher(TFMessage, "/tf", 100)
node.create_subscription(Twist, "/cmd_vel", lambda m: None, 10)
ex = SingleThreadedExecutor(context=ctx); ex.add_node(node)
print("ready", flush=True)
i = 0
next_at = time.monotonic()
while True:
    now = time.time_ns()
    stamp_sec, stamp_ns = divmod(now - 50_000_000, 1_000_000_000)  # stamped 50 ms in the past
    m = Odometry()
    m.header.stamp.sec, m.header.stamp.nanosec = stamp_sec, stamp_ns
    m.header.frame_id, m.child_frame_id = "odom", "base_link"
    m.pose.pose.position.x = float(i % 10)
    m.pose.pose.orientation.w = 1.0
    odom.publish(m)
    t = TransformStamped()
    t.header.stamp.sec, t.header.stamp.nanosec = stamp_sec, stamp_ns
    t.header.frame_id, t.child_frame_id = "odom", "base_link"
    t.transform.translation.x = 0.5
    t.transform.rotation.w = 1.0
    tf.publish(TFMessage(transforms=[t]))
    if i % 2 == 0:
        chatter.publish(String(data=f"hello: {i // 2}"))
    i += 1
    next_at += 0.05  # odom and tf at 20 Hz, chatter at 10 Hz
    ex.spin_some(max(0.0, next_at - time.monotonic()))
"""


@pytest.fixture(scope="module")
def endpoint() -> Iterator[str]:
    where = f"tcp/127.0.0.1:{free_port()}"
    with pytest.MonkeyPatch.context() as mp:
        for var in ("ZENOH_SESSION_CONFIG_URI", "ZENOH_CONFIG_OVERRIDE", "ROS_DOMAIN_ID",
                    "POSEKIT_TRANSPORT"):
            mp.delenv(var, raising=False)
        mp.setenv("POSEKIT_ZENOH_ROUTER", where)
        yield where


@pytest.fixture(scope="module")
def system(endpoint: str) -> Iterator[Proc]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("ZENOH_", "ROS_DOMAIN"))}
    env.update(PYTHONUNBUFFERED="1")
    proc = Proc([sys.executable, "-c", textwrap.dedent(SYSTEM)], env)
    try:
        proc.wait_line(lambda s: s == "ready\n", 30, "the system to start")
        yield proc
    finally:
        proc.kill()


@pytest.fixture(scope="module")
def ctx(system: Proc) -> Iterator[Context]:
    context = Context()
    context.init(transport="zenoh")
    deadline = time.monotonic() + 20
    while "/odom" not in call(topic_cmd.main_list, [], context)[1]:
        assert time.monotonic() < deadline, "the system's topics never appeared"
        time.sleep(0.1)
    yield context
    context.try_shutdown()


def call(main: Any, argv: list[str], context: Context, **kw: Any) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    code = main(argv, context=context, out=out, err=err, **kw)
    return code, out.getvalue(), err.getvalue()


# -- list / type / find ------------------------------------------------------------------------

def test_list_verbose_sections_as_ros2(ctx: Context) -> None:
    code, out, _ = call(topic_cmd.main_list, ["-v"], ctx)
    assert code == 0
    published, subscribed = out.split("\n\n")[:2]
    assert published.splitlines()[0] == "Published topics:"
    assert " * /odom [nav_msgs/msg/Odometry] 1 publisher" in published.splitlines()
    assert " * /chatter [std_msgs/msg/String] 1 publisher" in published.splitlines()
    assert subscribed.splitlines() == ["Subscribed topics:",
                                       " * /cmd_vel [geometry_msgs/msg/Twist] 1 subscriber"]
    assert out.endswith("\n\n")  # ros2 prints each section with print(), after a final \n


def test_type_and_find(ctx: Context) -> None:
    assert call(topic_cmd.main_type, ["/odom"], ctx)[:2] == (0, "nav_msgs/msg/Odometry\n")
    assert call(topic_cmd.main_type, ["/nothing"], ctx)[:2] == (1, "")
    assert call(topic_cmd.main_find, ["std_msgs/msg/String"], ctx)[:2] == (0, "/chatter\n")
    assert call(topic_cmd.main_find, ["-c", "nav_msgs/msg/Odometry"], ctx)[:2] == (0, "1\n")
    assert call(topic_cmd.main_find, ["pkg/msg/None"], ctx)[:2] == (0, "")


# -- echo --------------------------------------------------------------------------------------

def echo(ctx: Context, *args: str) -> str:
    code, out, err = call(topic_cmd.main_echo, [*args], ctx, timeout_s=15)
    assert code == 0, err
    return out


def test_echo_field_scalar_and_message(ctx: Context) -> None:
    out = echo(ctx, "/odom", "--field", "pose.pose.position.x", "--once")
    value, sep = out.splitlines()
    assert sep == "---"
    assert float(value) in [float(i) for i in range(10)]
    out = echo(ctx, "/odom", "--field", "pose.pose.orientation", "--once")
    assert out == "x: 0.0\ny: 0.0\nz: 0.0\nw: 1.0\n---\n"


def test_echo_filter_over_m(ctx: Context) -> None:
    # as Jazzy: with --field, m is the selected field
    out = echo(ctx, "/odom", "--filter", "m == 7.0", "--field", "pose.pose.position.x",
               "--count", "2")
    assert out == "7.0\n---\n7.0\n---\n"
    out = echo(ctx, "/odom", "--filter", "m.pose.pose.position.x == 3.0", "--once")
    assert yaml.safe_load(out.split("---")[0])["pose"]["pose"]["position"]["x"] == 3.0
    out = echo(ctx, "/chatter", "--filter", "m.data.endswith('5')", "--once")
    assert yaml.safe_load(out.split("---")[0])["data"].endswith("5")


def test_echo_csv_no_arr_no_str(ctx: Context) -> None:
    line = echo(ctx, "/odom", "--csv", "--once").rstrip("\n")
    fields = line.split(",")
    # header(sec, nanosec, frame_id), child_frame_id, pose(7 + 36 covariance), twist(6 + 36)
    assert len(fields) == 3 + 1 + 7 + 36 + 6 + 36
    assert fields[2:4] == ["odom", "base_link"]
    assert fields[10] == "1.0"  # orientation.w, printed by str() as rosidl_runtime_py does
    line = echo(ctx, "/odom", "--csv", "--no-arr", "--no-str", "--once").rstrip("\n")
    assert line.split(",")[2:4] == ["<string length: <4>>", "<string length: <9>>"]
    assert line.count("<array type: double[36]>") == 2
    out = echo(ctx, "/odom", "--no-arr", "--once")
    data = yaml.safe_load(out.split("---")[0])
    assert data["pose"]["covariance"] == "<array type: double[36]>"
    assert data["child_frame_id"] == "base_link"


def test_echo_flow_style_is_pyyaml_flow(ctx: Context) -> None:
    out = echo(ctx, "/chatter", "--flow-style", "--once")
    body, sep = out.split("\n", 1)
    assert sep == "---\n"
    assert yaml.safe_load(body)["data"].startswith("hello: ")
    assert body == yaml.dump(yaml.safe_load(body), default_flow_style=True,
                             width=sys.maxsize, sort_keys=False).rstrip("\n")
    assert body.startswith("{data: 'hello: ")  # ': ' forces quoting, as PyYAML does


def test_echo_raw_is_the_cdr_serialization(ctx: Context) -> None:
    from rosbags.typesys import Stores, get_typestore

    out = echo(ctx, "/chatter", "--raw", "--once")
    raw = eval(out.split("\n")[0])
    store = get_typestore(Stores.ROS2_JAZZY)
    msg = store.deserialize_cdr(raw, "std_msgs/msg/String")
    assert msg.data.startswith("hello: ")
    assert bytes(store.serialize_cdr(msg, "std_msgs/msg/String")) == raw


def test_echo_qos_override_and_explicit_type(ctx: Context) -> None:
    out = echo(ctx, "/chatter", "std_msgs/msg/String", "--qos-reliability", "best_effort",
               "--qos-depth", "1", "--once")
    assert out.startswith("data: 'hello: ")


def test_echo_include_message_info(ctx: Context) -> None:
    """rclpy's MessageInfo from rmw_zenoh's attachment, printed as ros2 prints it."""
    before = time.time_ns()
    out = echo(ctx, "/chatter", "-i", "--count", "2")
    blocks = out.split("---\n")
    info_text = blocks[0]
    assert info_text.splitlines()[0].startswith("publication_sequence_number: ")
    keys = [line.split(":")[0] for line in info_text.splitlines()]
    assert keys == sorted(keys) == ["publication_sequence_number", "received_timestamp",
                                    "reception_sequence_number", "source_timestamp"]
    first, second = yaml.safe_load(blocks[0]), yaml.safe_load(blocks[2])
    assert second["publication_sequence_number"] == first["publication_sequence_number"] + 1
    assert before - 5 * 10**9 < first["source_timestamp"] <= first["received_timestamp"]
    assert first["received_timestamp"] < time.time_ns()
    assert yaml.safe_load(blocks[1])["data"].startswith("hello: ")
    line = echo(ctx, "/chatter", "-i", "--csv", "--once").rstrip("\n")
    source, received, seq, reception, data = line.split(",", 4)
    assert int(source) <= int(received)
    assert int(seq) > 0
    assert reception == "0"
    assert data.startswith("hello: ")


def test_echo_timeout_ends_quietly_like_ros2(ctx: Context) -> None:
    out, err = io.StringIO(), io.StringIO()
    start = time.monotonic()
    code = topic_cmd.main_echo(["/never", "std_msgs/msg/String", "--timeout", "0.5"],
                               context=ctx, out=out, err=err)
    assert code == 0
    assert out.getvalue() == ""
    assert time.monotonic() - start < 5


def test_echo_user_mistakes_are_cli_errors(ctx: Context) -> None:
    with pytest.raises(MessageFieldError, match=r"Invalid field 'pose\.nope'"):
        call(topic_cmd.main_echo, ["/odom", "--field", "pose.nope"], ctx, timeout_s=15)
    with pytest.raises(CliError, match="invalid --filter expression"):
        call(topic_cmd.main_echo, ["/odom", "--filter", "m.("], ctx)
    with pytest.raises(CliError, match="The passed message type 'nope/msg/X' is invalid"):
        call(topic_cmd.main_echo, ["/odom", "nope/msg/X"], ctx)


# -- hz / bw / delay ---------------------------------------------------------------------------

def test_hz_filter_and_wall_time(ctx: Context) -> None:
    code, out, _ = call(topic_cmd.main_hz, ["/odom", "--count", "1"], ctx, timeout_s=20)
    first, second = out.splitlines()[:2]
    assert code == 0
    assert 15 < float(first.split(": ")[1]) < 25, out  # published at 20 Hz
    assert second.startswith("\tmin: ")
    assert "window: " in second
    # only x == 0.0 (one message in ten): 2 Hz
    code, out, _ = call(topic_cmd.main_hz, ["/odom", "--filter", "m.pose.pose.position.x == 0.0",
                                            "--wall-time", "--count", "1"], ctx, timeout_s=20)
    assert code == 0
    assert 1.6 < float(out.splitlines()[0].split(": ")[1]) < 2.4, out


def test_hz_ends_cleanly_when_nothing_arrives(ctx: Context) -> None:
    with pytest.raises(CliError, match=r"did not appear within 0.5 s"):
        call(topic_cmd.main_hz, ["/never", "--timeout", "0.5"], ctx)
    # the filter rejects everything: messages arrive, but none is measured
    with pytest.raises(CliError, match=r"no message measured on \[/odom\] within 1 s"):
        call(topic_cmd.main_hz, ["/odom", "--filter", "False", "--timeout", "1"], ctx)


def test_bw_reports_cdr_sizes(ctx: Context) -> None:
    from posekit.msgs.cdr import to_cdr
    from posekit.msgs.std_msgs import String

    code, out, _ = call(topic_cmd.main_bw, ["/chatter", "--count", "1"], ctx, timeout_s=20)
    lines = out.splitlines()
    assert code == 0
    assert lines[0] == "Subscribed to [/chatter]"
    rate, _rest = lines[1].split(" B/s from ")
    assert 150 < float(rate) < 450  # 10 Hz x ~28 bytes
    sizes = {len(to_cdr(String(data=f"hello: {n}"))) for n in (1, 10, 100)}
    mean = lines[2].split("mean: ")[1].split(" B")[0]
    assert min(sizes) <= int(mean) <= max(sizes)


def test_delay_from_header_stamp(ctx: Context) -> None:
    code, out, _ = call(topic_cmd.main_delay, ["/odom", "--count", "1"], ctx, timeout_s=20)
    first = out.splitlines()[0]
    assert code == 0
    assert first.startswith("average delay: "), out
    assert 0.045 < float(first.split(": ")[1]) < 1.0  # stamped 50 ms before publishing
    with pytest.raises(CliError, match="have no header"):
        call(topic_cmd.main_delay, ["/chatter", "--count", "1"], ctx, timeout_s=20)


# -- node info ---------------------------------------------------------------------------------

def test_tf_monitor_all_frames_and_chain(ctx: Context) -> None:
    from posekit.cli import tf_monitor

    out, err = io.StringIO(), io.StringIO()
    assert tf_monitor.main(["--period", "1.5", "--count", "1"], context=ctx, out=out,
                           err=err) == 0
    lines = out.getvalue().splitlines()
    assert lines[:5] == ["Gathering data on all frames for 10 seconds...", "", "", "",
                         "RESULTS: for all Frames"]
    assert lines[5:7] == ["", "Frames:"]
    frame = lines[7].split(", ")
    assert frame[:2] == ["Frame: base_link", "published by <no authority available>"]
    assert 0.045 < float(frame[2].removeprefix("Average Delay: ")) < 1.0  # stamped 50 ms back
    node = lines[8].split(" ")
    assert node[:4] == ["Node:", "<no", "authority", "available>"]
    assert 14 < float(node[4]) < 26  # /tf at 20 Hz
    assert err.getvalue() == "\nAll Broadcasters:\n"  # tf2_monitor writes it to stderr
    out = io.StringIO()
    assert tf_monitor.main(["odom", "base_link", "--period", "1", "--count", "1"], context=ctx,
                           out=out, err=err, timeout_s=10) == 0
    lines = out.getvalue().splitlines()
    assert lines[0] == "Gathering data on odom -> base_link for 10 seconds..."
    assert lines[4:6] == ["RESULTS: for odom to base_link", "Chain is: odom -> base_link"]
    assert lines[6].startswith("Net delay     avg = ")


def test_chain_as_vector_follows_tf2() -> None:
    """Expected chains worked by hand through tf2's walkToTopParent (Jazzy buffer_core.cpp),
    including its pruning, which drops the common parent in some cases."""
    from posekit.cli.tf_monitor import chain_as_vector

    #        map
    #       /   \
    #    odom   world_marker
    #     |
    #    base -- laser
    parents = {"odom": "map", "base": "odom", "laser": "base", "world_marker": "map"}
    assert chain_as_vector(parents, "base", "map") == ["map", "odom", "base"]
    assert chain_as_vector(parents, "map", "laser") == ["laser", "base", "odom"]
    assert chain_as_vector(parents, "laser", "world_marker") == ["odom", "base", "laser"]
    assert chain_as_vector(parents, "odom", "laser") == ["laser", "base", "odom"]
    assert chain_as_vector(parents, "laser", "odom") == ["laser", "base", "odom"]


def test_node_info_sections_as_ros2(ctx: Context) -> None:
    code, out, _ = call(node_cmd.main_info, ["/robot/system"], ctx)
    assert code == 0
    assert out == (
        "/robot/system\n"
        "  Subscribers:\n"
        "    /cmd_vel: geometry_msgs/msg/Twist\n"
        "  Publishers:\n"
        "    /chatter: std_msgs/msg/String\n"
        "    /odom: nav_msgs/msg/Odometry\n"
        "    /parameter_events: rcl_interfaces/msg/ParameterEvent\n"
        "    /rosout: rcl_interfaces/msg/Log\n"
        "    /tf: tf2_msgs/msg/TFMessage\n"
        "  Service Servers:\n"  # every node's parameter services, as rclpy's
        "    /robot/system/describe_parameters: rcl_interfaces/srv/DescribeParameters\n"
        "    /robot/system/get_parameter_types: rcl_interfaces/srv/GetParameterTypes\n"
        "    /robot/system/get_parameters: rcl_interfaces/srv/GetParameters\n"
        "    /robot/system/get_type_description: "
        "type_description_interfaces/srv/GetTypeDescription\n"
        "    /robot/system/list_parameters: rcl_interfaces/srv/ListParameters\n"
        "    /robot/system/set_parameters: rcl_interfaces/srv/SetParameters\n"
        "    /robot/system/set_parameters_atomically: "
        "rcl_interfaces/srv/SetParametersAtomically\n"
        "  Service Clients:\n\n"
        "  Action Servers:\n\n"
        "  Action Clients:\n\n"
    )
    with pytest.raises(CliError, match="Unable to find node '/nobody'"):
        call(node_cmd.main_info, ["/nobody"], ctx)


def test_node_info_services_and_actions_from_rmw_zenoh_tokens(ctx: Context,
                                                             endpoint: str) -> None:
    import zenoh

    config = zenoh.Config()
    config.insert_json5("mode", json.dumps("peer"))
    config.insert_json5("connect/endpoints", json.dumps([endpoint]))
    config.insert_json5("listen/endpoints", json.dumps(["tcp/127.0.0.1:0"]))
    config.insert_json5("scouting/multicast/enabled", "false")
    ros = zenoh.open(config)
    zid = str(ros.info.zid())
    qos = "::,10:,:,:,,"
    h = "RIHS01_" + "0" * 64
    keys = [  # rmw_zenoh's token layout; types as its liveliness tokens carry them
        f"@ros2_lv/0/{zid}/0/0/NN/%/%/fib_server",
        f"@ros2_lv/0/{zid}/0/1/SS/%/%/fib_server/%add_two_ints/"
        f"example_interfaces::srv::dds_::AddTwoInts_/{h}/{qos}",
        f"@ros2_lv/0/{zid}/0/2/SS/%/%/fib_server/%fibonacci%_action%send_goal/"
        f"example_interfaces::action::dds_::Fibonacci_SendGoal_/{h}/{qos}",
        f"@ros2_lv/0/{zid}/0/3/SC/%/%/fib_server/%other/"
        f"std_srvs::srv::dds_::Trigger_/{h}/{qos}",
    ]
    tokens = [ros.liveliness().declare_token(k) for k in keys]
    try:
        deadline = time.monotonic() + 10
        while True:
            try:
                code, out, _ = call(node_cmd.main_info, ["/fib_server"], ctx)
                assert code == 0
                break
            except CliError:
                assert time.monotonic() < deadline
                time.sleep(0.1)
        assert out == (
            "/fib_server\n  Subscribers:\n\n  Publishers:\n\n"
            "  Service Servers:\n    /add_two_ints: example_interfaces/srv/AddTwoInts\n"
            "  Service Clients:\n    /other: std_srvs/srv/Trigger\n"
            "  Action Servers:\n    /fibonacci: example_interfaces/action/Fibonacci\n"
            "  Action Clients:\n\n"
        )
        _code, out, _ = call(node_cmd.main_info, ["/fib_server", "--include-hidden"], ctx)
        assert ("    /fibonacci/_action/send_goal: example_interfaces/action/Fibonacci_SendGoal"
                in out.splitlines())
    finally:
        for token in tokens:
            token.undeclare()
        ros.close()


# -- bag record against the running system ------------------------------------------------------

def test_bag_record_regex_and_duration_split(ctx: Context, tmp_path: Path) -> None:
    """Records the other process's topics over Zenoh; read back by rosbags and by mcap."""
    from mcap.reader import make_reader
    from rosbags.rosbag2 import Reader
    from rosbags.typesys import Stores, get_typestore

    from posekit.cli.bag_cmd import record

    out = tmp_path / "live"
    assert record(["-o", str(out), "-e", "^/(odom|chatter)$", "--exclude-regex", "chat",
                   "-d", "1", "--duration", "2.6"], context=ctx) == 0
    files = sorted(p.name for p in out.glob("*.mcap"))
    assert files == [f"live_{i}.mcap" for i in range(len(files))]
    assert len(files) >= 2  # receive stamps over ~2.6 s, a new file after each second
    store = get_typestore(Stores.ROS2_JAZZY)
    with Reader(out) as reader:
        assert [c.topic for c in reader.connections][:1] == ["/odom"]
        assert {c.topic for c in reader.connections} == {"/odom"}
        xs = [store.deserialize_cdr(raw, c.msgtype).pose.pose.position.x
              for c, _, raw in reader.messages()]
    assert len(xs) > 20  # 20 Hz
    assert set(xs) <= {float(i) for i in range(10)}
    total = 0
    for name in files:
        with (out / name).open("rb") as f:
            summary = make_reader(f).get_summary()
        assert summary is not None
        assert summary.statistics is not None
        total += summary.statistics.message_count
    assert total == len(xs)


def test_the_command_line_itself(system: Proc, endpoint: str) -> None:
    """The ``posekit`` entry point in its own process (argument parsing to exit code)."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("ZENOH_", "ROS_DOMAIN"))}
    env.update(POSEKIT_ZENOH_ROUTER=endpoint, PYTHONUNBUFFERED="1")
    env.pop("POSEKIT_TRANSPORT", None)
    for _ in range(3):  # a fresh process's first graph snapshot can still miss a node
        info = Proc([sys.executable, "-m", "posekit.cli.main", "node", "info",
                     "/robot/system"], env)
        out = info.finish(60, "posekit node info")
        if info.popen.returncode == 0:
            break
        assert "".join(info.err) == "posekit node info: error: Unable to find node " \
            "'/robot/system'\n", info.describe()
    assert out.startswith(
        "/robot/system\n  Subscribers:\n    /cmd_vel: geometry_msgs/msg/Twist\n")
    echo = Proc([sys.executable, "-m", "posekit.cli.main", "topic", "echo", "/chatter",
                 "--once", "--field", "data"], env)
    out = echo.finish(60, "posekit topic echo --once")
    assert echo.popen.returncode == 0
    assert out.startswith("hello: ")
    assert out.endswith("\n---\n")
