"""Real processes over real Zenoh sessions on loopback: runtime nodes and the posekit CLI.

Every test points its processes at a fresh free port through ``POSEKIT_ZENOH_ROUTER`` (the
variable the transport honours), so tests never meet each other or a user's router, and every
process is killed in a ``finally``. Waits are bounded and fail with the collected output.
"""

from __future__ import annotations

import json
import math
import re
import shutil
import signal
import subprocess
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from scipy.spatial.transform import Rotation

from _support.world import World
from posekit.msgs.registry import MESSAGE_CLASSES

pytestmark = pytest.mark.slow  # real processes, sessions or a browser

REPO = Path(__file__).resolve().parents[2]


# -- runtime processes (POSEKIT_TRANSPORT=zenoh, no transport named in the code) ---------------

SAMPLES = """
import dataclasses, typing
import numpy as np
from posekit.msgs.registry import MESSAGE_CLASSES

def elem_class(cls, name):
    hint = typing.get_type_hints(cls).get(name)
    args = typing.get_args(hint)
    return args[0] if args and dataclasses.is_dataclass(args[0]) else None

def sample(cls, seed):
    msg = cls()
    for i, f in enumerate(dataclasses.fields(msg)):
        v, k = getattr(msg, f.name), seed * 31 + i
        if dataclasses.is_dataclass(v):
            setattr(msg, f.name, sample(type(v), k))
        elif isinstance(v, np.ndarray):
            n = v.size or 3 + seed % 4
            setattr(msg, f.name, ((np.arange(n) * 7 + k) % 200).astype(v.dtype)
                    if v.dtype.kind in "iu" else (np.arange(n) + k / 8).astype(v.dtype))
        elif isinstance(v, list):
            e = elem_class(cls, f.name)
            setattr(msg, f.name, [sample(e, k + j) for j in range(2)] if e else [f"n{k}", "x"])
        elif isinstance(v, bool):
            setattr(msg, f.name, k % 2 == 1)
        elif isinstance(v, int):
            setattr(msg, f.name, k % 100 + 1)
        elif isinstance(v, float):
            setattr(msg, f.name, k / 4 + 0.125)
        elif isinstance(v, str):
            setattr(msg, f.name, f"{f.name}-{k}")
    return msg

def topic(name):
    return "/x/" + name.replace("/msg/", "_")
"""

PUBLISH_ALL = SAMPLES + """
import time
from posekit.runtime.context import Context
from posekit.runtime.node import Node
ctx = Context(); ctx.init()  # transport from POSEKIT_TRANSPORT
node = Node("every_type_talker", context=ctx)
print("transport", type(node.transport).__name__, flush=True)
pubs = [(node.create_publisher(cls, topic(name), 10), sample(cls, 1))
        for name, cls in sorted(MESSAGE_CLASSES.items())]
while True:
    for pub, msg in pubs:
        pub.publish(msg)
    time.sleep(0.1)
"""

RECEIVE_ALL = SAMPLES + """
import json, time
from posekit.cli.topic_cmd import message_to_ordered
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
ctx = Context(); ctx.init()
node = Node("every_type_listener", context=ctx)
got = {}
for name, cls in sorted(MESSAGE_CLASSES.items()):
    node.create_subscription(cls, topic(name),
                             lambda m, name=name: got.setdefault(name, m), 10)
ex = SingleThreadedExecutor(context=ctx); ex.add_node(node)
deadline = time.monotonic() + 25
while len(got) < len(MESSAGE_CLASSES) and time.monotonic() < deadline:
    ex.spin_some(0.1)
for name in sorted(MESSAGE_CLASSES):
    if name in got:
        m = got[name]
        print(json.dumps({"type": name, "cls": type(m).__name__,
                          "fields": message_to_ordered(m, None)}), flush=True)
print("done", len(got), flush=True)
"""


def test_publisher_and_subscriber_processes_exchange_every_message_type(world: World) -> None:
    ns: dict[str, Any] = {}
    exec(SAMPLES, ns)  # the same deterministic samples, built here independently
    from posekit.cli.topic_cmd import message_to_ordered

    talker = world.script(PUBLISH_ALL)
    assert talker.wait_line(lambda s: s.startswith("transport"), 20, "the talker") == (
        "transport ZenohTransport\n"
    )
    listener = world.script(RECEIVE_ALL)
    text = listener.finish(40, "the listener")
    received = {d["type"]: d for d in map(json.loads, text.splitlines()[:-1])}
    assert text.splitlines()[-1] == f"done {len(MESSAGE_CLASSES)}", listener.describe()
    for name, cls in MESSAGE_CLASSES.items():
        assert received[name]["cls"] == cls.__name__
        expected = json.loads(json.dumps(message_to_ordered(ns["sample"](cls, 1), None)))
        assert received[name]["fields"] == expected, name


TF_LISTENER = """
import sys, time
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.tf2_ros import TransformListener
from posekit.tf2 import Buffer
from posekit.time import Time
ctx = Context(); ctx.init()
node = Node("late_listener", context=ctx)
buf = Buffer()
TransformListener(buf, node)
ex = SingleThreadedExecutor(context=ctx); ex.add_node(node)
while True:
    ex.spin_some(0.2)
    if buf.can_transform("world", "laser", Time()):
        t = buf.lookup_transform("world", "laser", Time()).transform.translation
        print(f"world->laser {t.x:.3f} {t.y:.3f} {t.z:.3f}", flush=True)
    else:
        print("waiting", flush=True)
"""


def test_late_process_gets_tf_static_and_outlives_the_publisher(world: World) -> None:
    # zero configuration: the static publisher starts first and hosts the router itself
    static = world.cli("tf", "static", "--x", "0.2", "--z", "0.5", "--frame-id", "world",
                       "--child-frame-id", "laser")
    static.wait_stderr("Spinning until stopped", 20, "static publisher start-up")
    time.sleep(0.5)  # published well before the listener exists: only history can deliver it
    listener = world.script(TF_LISTENER)
    listener.wait_line(lambda s: s.startswith("world->laser"), 20, "the latched /tf_static")
    static.kill()  # SIGKILL, and the router it hosted dies with it
    assert static.popen.returncode == -signal.SIGKILL
    time.sleep(1.0)
    for _ in range(3):  # still running, still able to transform with the static frame
        line = listener.wait_line(lambda s: s.startswith(("world", "waiting")), 10, "a report")
        assert line == "world->laser 0.200 0.000 0.500\n"
    assert listener.popen.poll() is None


def _node_list(world: World) -> list[str]:
    proc = world.cli("node", "list")
    return proc.finish(30, "posekit node list").splitlines()


def test_node_list_follows_processes_and_rmw_zenoh_tokens(routed: World) -> None:
    import zenoh

    static = routed.cli("tf", "static", "--frame-id", "a", "--child-frame-id", "b")
    config = zenoh.Config()
    config.insert_json5("mode", '"peer"')
    config.insert_json5("connect/endpoints", json.dumps([routed.endpoint]))
    config.insert_json5("listen/endpoints", '["tcp/127.0.0.1:0"]')
    config.insert_json5("scouting/multicast/enabled", "false")
    ros = zenoh.open(config)
    zid = str(ros.info.zid())
    token = ros.liveliness().declare_token(f"@ros2_lv/0/{zid}/0/0/NN/%/%robot1/ros_talker")
    try:
        names: list[str] = []
        for _ in range(10):
            names = _node_list(routed)
            if len(names) == 2:
                break
        assert names[0] == "/robot1/ros_talker", names
        assert re.fullmatch(r"/static_transform_publisher_[0-9A-Za-z]{16}", names[1]), names
        static.kill()
        token.undeclare()
        for _ in range(10):
            names = _node_list(routed)
            if not names:
                break
        assert names == []
    finally:
        ros.close()


# -- CLI end to end ---------------------------------------------------------------------------

SPEC_BLOCK = """\
- Translation: [1.000, -2.500, 0.123]
- Rotation: in Quaternion [0.103, 0.043, 0.992, 0.065]
- Rotation: in RPY (radian) [0.100, -0.200, 3.000]
- Rotation: in RPY (degree) [5.730, -11.459, 171.887]
- Matrix:
 -0.970 -0.121  0.210  1.000
  0.138 -0.988  0.071 -2.500
  0.199  0.098  0.975  0.123
  0.000  0.000  0.000  1.000
"""


def test_tf_static_then_tf_echo_prints_the_tf2_echo_block(routed: World) -> None:
    routed.cli("tf", "static", "--x", "1", "--y", "-2.5", "--z", "0.123456", "--roll", "0.1",
               "--pitch", "-0.2", "--yaw", "3.0", "--frame-id", "a", "--child-frame-id", "b")
    echo = routed.cli("tf", "echo", "a", "b", "--count", "1")
    out = echo.finish(30, "posekit tf echo")
    # static transforms are looked up at time 0: tf2_echo prints "At time 0.0"
    assert out == "At time 0.0\n" + SPEC_BLOCK, echo.describe()
    # docs/specs/tf2.md's block is tf2's output; check it against scipy as well (rounded to 3
    # places)
    R = Rotation.from_euler("xyz", [0.1, -0.2, 3.0])
    q = R.as_quat()
    assert f"[{q[0]:.3f}, {q[1]:.3f}, {q[2]:.3f}, {q[3]:.3f}]" in out
    assert f"{R.as_matrix()[0, 0]:6.3f}" in out


BROADCASTER = """
import math, time
from posekit.msgs.geometry_msgs import TransformStamped
from posekit.runtime.context import Context
from posekit.runtime.node import Node
from posekit.tf2_ros import TransformBroadcaster
ctx = Context(); ctx.init()
node = Node("odom_broadcaster", context=ctx)
br = TransformBroadcaster(node)
print("ready", flush=True)
while True:
    t = TransformStamped(child_frame_id="base_link")
    t.header.frame_id = "odom"
    t.header.stamp = node.get_clock().now().to_msg()
    t.transform.translation.x, t.transform.translation.y = 1.5, -0.25
    t.transform.rotation.z, t.transform.rotation.w = math.sin(0.25), math.cos(0.25)
    br.sendTransform(t)
    time.sleep(0.05)
"""


@pytest.fixture
def tf_world(routed: World) -> World:
    static = routed.cli("tf", "static", "--x", "0.5", "--frame-id", "map",
                        "--child-frame-id", "odom")
    static.wait_stderr("Spinning until stopped", 20, "static publisher start-up")
    routed.script(BROADCASTER).wait_line(lambda s: s == "ready\n", 20, "the broadcaster")
    return routed


def test_topic_echo_tf_and_tf_frames_and_topic_tools(tf_world: World) -> None:
    # start the listeners together: each needs a second or two to start and discover
    echo = tf_world.cli("topic", "echo", "/tf", "--once")
    frames = tf_world.cli("tf", "frames", "-t", "2", "-o", "tree")
    hz = tf_world.cli("topic", "hz", "/tf", "--count", "1")

    blocks = echo.finish(30, "posekit topic echo /tf").split("---\n")
    assert len(blocks) == 2, echo.describe()
    assert blocks[1] == ""
    msg = yaml.safe_load(blocks[0])  # PyYAML reads the dump back
    (t,) = msg["transforms"]
    assert (t["header"]["frame_id"], t["child_frame_id"]) == ("odom", "base_link")
    assert t["transform"]["translation"] == {"x": 1.5, "y": -0.25, "z": 0.0}
    assert t["transform"]["rotation"]["w"] == math.cos(0.25)
    assert abs(t["header"]["stamp"]["sec"] - time.time()) < 60

    report = hz.finish(30, "posekit topic hz").splitlines()
    match = re.fullmatch(r"average rate: (\d+\.\d{3})", report[0])
    assert match, hz.describe()
    assert 2.0 < float(match.group(1)) < 60.0  # nominal 20 Hz; loose on a loaded machine
    assert re.fullmatch(r"\tmin: \d+\.\d{3}s max: \d+\.\d{3}s std dev: \d+\.\d{5}s window: \d+",
                        report[1])

    listed: list[str] = []
    for _ in range(8):  # a graph snapshot may predate the newest token reaching the router
        listed = tf_world.cli("topic", "list", "-t").finish(30, "topic list").splitlines()
        if "/tf [tf2_msgs/msg/TFMessage]" in listed and len(listed) >= 2:
            break
    assert "/tf [tf2_msgs/msg/TFMessage]" in listed
    assert "/tf_static [tf2_msgs/msg/TFMessage]" in listed

    out = frames.finish(40, "posekit tf frames")
    gv = tf_world.tmp / "tree.gv"
    text = gv.read_text()
    edges = set(re.findall(r'^"([^"]+)" -> "([^"]+)"\[label=', text, re.MULTILINE))
    assert edges == {("map", "odom"), ("odom", "base_link")}, text
    assert re.search(r'Broadcaster: [^\\]+\\nAverage rate: ', text)
    assert text.endswith('}->"map";\n}')  # the legend hangs off the root
    dot = shutil.which("dot")
    if dot is None:
        assert "Graphviz 'dot' was not found" in out
        assert not (tf_world.tmp / "tree.pdf").exists()
    else:
        assert (tf_world.tmp / "tree.pdf").read_bytes().startswith(b"%PDF")
        plain = subprocess.run([dot, "-Tplain", str(gv)], capture_output=True, text=True,
                               check=True).stdout
        plain_edges = {tuple(line.split()[1:3]) for line in plain.splitlines()
                       if line.startswith("edge")}
        assert {("map", "odom"), ("odom", "base_link")} <= plain_edges


def test_topic_pub_reaches_topic_echo_in_another_process(routed: World) -> None:
    echo = routed.cli("topic", "echo", "/chatter", "std_msgs/msg/String", "--count", "2")
    pub = routed.cli("topic", "pub", "/chatter", "std_msgs/msg/String", "{data: 'hello: world'}",
                     "--times", "2", "-r", "10")
    printed = pub.finish(30, "posekit topic pub")
    assert printed.startswith(
        ("Waiting for at least 1 matching subscription(s)...\n", "publisher: beginning loop\n")
    )
    assert "publishing #2: std_msgs.msg.String(data='hello: world')\n" in printed
    assert echo.finish(20, "posekit topic echo") == "data: 'hello: world'\n---\n" * 2


def test_array_helper_sanity() -> None:
    # the sample builder used across processes yields non-default values for every class
    ns: dict[str, Any] = {}
    exec(SAMPLES, ns)
    for cls in MESSAGE_CLASSES.values():
        sample, default = ns["sample"](cls, 1), cls()
        if any(not isinstance(getattr(default, f), np.ndarray) or getattr(default, f).size
               for f in cls.__dataclass_fields__ if not f.startswith("_")):
            assert sample != default, cls


# -- parameters and services between processes ---------------------------------------------

CMD_VEL_OBSERVER = """
import math
from posekit.msgs.geometry_msgs import TwistStamped
from posekit.msgs.nav_msgs import Odometry
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
ctx = Context(); ctx.init()
node = Node("cmd_vel_observer", context=ctx)
pose = []
def on_odom(m):
    pose[:] = [m.pose.pose.position.x, m.pose.pose.position.y]
def on_cmd(m):
    if pose:
        rho = math.hypot(5.0 - pose[0], 5.0 - pose[1])
        print(f"v={m.twist.linear.x:.4f} rho={rho:.4f}", flush=True)
node.create_subscription(Odometry, "/odometry/filtered", on_odom, 10)
node.create_subscription(TwistStamped, "/cmd_vel", on_cmd, 10)
ex = SingleThreadedExecutor(context=ctx); ex.add_node(node)
ex.spin()
"""


def _v_rho(line: str) -> tuple[float, float] | None:
    match = re.fullmatch(r"v=(\S+) rho=(\S+)\n", line)
    return (float(match[1]), float(match[2])) if match else None


@pytest.mark.slow
def test_param_set_retunes_the_running_p_controller(world: World) -> None:
    """The lecture's tip over real processes: ``posekit launch p_controller --zenoh
    --realtime`` drives to (5, 5) at the 0.5 m/s clamp; ``posekit param set /p_controller
    k_rho 0.02`` from another process makes the next commands v = 0.02 * rho (under the
    clamp), seen by a third process on /cmd_vel."""
    launch = world.cli("launch", "p_controller", "--zenoh", "--realtime")
    observer = world.script(CMD_VEL_OBSERVER)
    line = observer.wait_line(lambda s: (vr := _v_rho(s)) is not None and vr[0] == 0.5, 60,
                              "the controller driving at the 0.5 m/s clamp")
    assert launch.popen.poll() is None, line
    listed = world.cli("param", "list", "/p_controller").finish(30, "posekit param list")
    assert "  k_rho\n" in listed
    assert "  goal_tolerance\n" in listed
    got = world.cli("param", "get", "/p_controller", "k_rho").finish(30, "posekit param get")
    assert got == "Double value is: 0.4\n"
    setter = world.cli("param", "set", "/p_controller", "k_rho", "0.02")
    assert setter.finish(30, "posekit param set") == "Set parameter successful\n"
    observer.wait_line(
        lambda s: (vr := _v_rho(s)) is not None and abs(vr[0] - 0.02 * vr[1]) < 0.005, 30,
        "commands following the new gain (v = 0.02 * rho)",
    )
    refused = world.cli("param", "set", "/p_controller", "k_rho", "1")
    assert refused.finish(30, "posekit param set") == ""
    assert refused.err == [
        "Setting parameter failed: Wrong parameter type, expected 'Type.DOUBLE' "
        "got 'Type.INTEGER'\n"
    ]
    got = world.cli("param", "get", "/p_controller", "k_rho").finish(30, "posekit param get")
    assert got == "Double value is: 0.02\n"


@pytest.mark.slow
def test_service_call_between_processes(routed: World) -> None:
    server = routed.script("""
from posekit.msgs.std_srvs import SetBool
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
ctx = Context(); ctx.init()
node = Node("flag_server", context=ctx)
def on_request(request, response):
    response.success = not request.data
    response.message = f"flipped {request.data}"
    return response
node.create_service(SetBool, "flip", on_request)
ex = SingleThreadedExecutor(context=ctx); ex.add_node(node)
print("serving", flush=True)
ex.spin()
""")
    server.wait_line(lambda s: s == "serving\n", 30, "the server")
    caller = routed.cli("service", "call", "/flip", "std_srvs/srv/SetBool", "{data: true}",
                        "--timeout", "20")
    printed = caller.finish(40, "posekit service call")
    assert printed.endswith(
        "requester: making request: std_srvs.srv.SetBool_Request(data=True)\n\n"
        "response:\nstd_srvs.srv.SetBool_Response(success=False, message='flipped True')\n\n"
    )
    listed = routed.cli("service", "list", "-t").finish(30, "posekit service list")
    assert "/flip [std_srvs/srv/SetBool]\n" in listed
    assert "/flag_server/get_parameters [rcl_interfaces/srv/GetParameters]\n" in listed
