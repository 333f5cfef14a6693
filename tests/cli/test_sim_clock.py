"""One sim clock across processes, over real Zenoh on loopback: a running scenario owns
/clock; a node in another process started with ``--ros-args -p use_sim_time:=true`` follows
it; a second simulation is refused with one line; a stray /clock publisher changes nothing;
``posekit topic pub ... "{header: auto}"`` stamps commands with sim time and the robot stops
within the documented timeout once the commands stop (a wall-clock stamped stream is
rejected with one warning).

Oracles: the simulator's ground truth (true velocity, stamped with sim time), the documented
bound (last valid command stamp + cmd_vel_timeout 0.5 s + braking |v| / 1.0 m/s²) and the
wall clock (sim times are far below it).
"""

from __future__ import annotations

import json
import re
import time
from collections.abc import Callable
from typing import Any

import pytest

from _support.procs import Proc
from _support.world import World

pytestmark = pytest.mark.slow

NS = 1_000_000_000
#: Sim times are seconds since the simulation started; wall-clock stamps are ~1.8e9 s.
SIM_TIME_CEILING_NS = 100_000 * NS

FOLLOWER = """
import json, sys, time
from posekit import rclpy
from posekit.rclpy.node import Node

rclpy.init()  # sys.argv: --ros-args -p use_sim_time:=true
node = Node("sim_follower")
assert node.get_parameter("use_sim_time").value is True

def tick():
    print(json.dumps({"now": node.get_clock().now().nanoseconds}), flush=True)

node.create_timer(0.5, tick)
rclpy.spin(node)
"""

OBSERVER = """
import json
import re
from posekit import rclpy
from posekit.rclpy.node import Node
from posekit.msgs.geometry_msgs import TwistStamped
from posekit.msgs.nav_msgs import Odometry

rclpy.init()
node = Node("cmd_observer")
clock = node.get_clock()

def ns(stamp):
    return stamp.sec * 1_000_000_000 + stamp.nanosec

def on_cmd(msg):
    print(json.dumps({"cmd": ns(msg.header.stamp), "now": clock.now().nanoseconds,
                      "x": msg.twist.linear.x}), flush=True)

def on_odom(msg):
    print(json.dumps({"odom": ns(msg.header.stamp), "v": msg.twist.twist.linear.x}),
          flush=True)

node.create_subscription(TwistStamped, "/cmd_vel", on_cmd, 10)
node.create_subscription(Odometry, "/ground_truth/odom", on_odom, 10)
rclpy.spin(node)
"""


def _records(proc: Proc, key: str) -> list[dict[str, Any]]:
    out = []
    for line in list(proc.out):
        if line.startswith("{"):
            record = json.loads(line)
            if key in record:
                out.append(record)
    return out


def _wait_for(condition: Callable[[], bool], timeout: float, what: str, *procs: Proc) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out after {timeout} s waiting for {what}\n"
                                 + "\n".join(p.describe() for p in procs))
        time.sleep(0.1)


def _simulation(routed: World) -> Proc:
    sim = routed.cli("launch", "empty_world", "--realtime", "--zenoh")
    sim.wait_stderr("world 'empty_world'", 30, "the simulation to start")
    return sim


def test_nodes_elsewhere_follow_the_one_simulation_clock(routed: World) -> None:
    sim = _simulation(routed)
    follower = routed.script(FOLLOWER, "--ros-args", "-p", "use_sim_time:=true")
    _wait_for(lambda: len(_records(follower, "now")) >= 4, 30, "4 sim-time ticks", follower)
    ticks = [r["now"] for r in _records(follower, "now")]
    assert all(0 < t < SIM_TIME_CEILING_NS for t in ticks), ticks
    assert ticks == sorted(ticks)
    assert len(set(ticks)) == len(ticks)

    # A second simulation on the same network is refused before it shows any node.
    second = routed.cli("launch", "empty_world", "--zenoh", "--until-sim-time", "1")
    second.finish(60, "the second launch")
    assert second.popen.returncode == 2
    err = "".join(second.err).strip()
    assert err.count("\n") == 0, err
    assert "another clock source already publishes /clock (/posekit_sim_clock)" in err

    # A stray /clock publisher: reported once by the simulation and by the follower, and
    # the follower keeps following the simulation's time.
    stray = routed.cli("topic", "pub", "/clock", "rosgraph_msgs/msg/Clock",
                       "{clock: {sec: 1000}}", "-r", "20")
    sim.wait_stderr("Ignoring a second /clock publisher", 20, "the simulation's report")
    follower.wait_stderr("Ignoring /clock from a second source", 20, "the follower's warning")
    before = len(_records(follower, "now"))
    _wait_for(lambda: len(_records(follower, "now")) >= before + 4, 30, "more ticks",
              follower, stray)
    ticks = [r["now"] for r in _records(follower, "now")]
    assert all(0 < t < SIM_TIME_CEILING_NS for t in ticks), ticks
    assert ticks == sorted(ticks)
    assert sum("second /clock publisher" in line for line in sim.err) == 1
    assert sum("second source" in line for line in follower.err) == 1
    assert sim.popen.poll() is None


def test_cli_commands_are_stamped_in_sim_time_and_the_robot_stops(routed: World) -> None:
    sim = _simulation(routed)
    observer = routed.script(OBSERVER, "--ros-args", "-p", "use_sim_time:=true")
    _wait_for(lambda: len(_records(observer, "odom")) >= 5, 30, "ground truth", observer)

    pub = routed.cli("topic", "pub", "/cmd_vel", "geometry_msgs/msg/TwistStamped",
                     "{header: auto, twist: {linear: {x: 0.3}}}", "-r", "10", "-t", "20")
    pub.finish(60, "topic pub")
    assert pub.popen.returncode == 0, pub.describe()
    commands = _records(observer, "cmd")
    assert len(commands) == 20
    t_last = max(c["cmd"] for c in commands)
    for c in commands:  # sim-time stamps, close to the sim time at reception
        assert 0 < c["cmd"] < SIM_TIME_CEILING_NS, (c, pub.describe()[:1500])
        assert abs(c["now"] - c["cmd"]) < NS // 2, c
    # Documented bound: timeout 0.5 s + braking 0.3 m/s / 1 m/s², plus one 50 ms output.
    stop_by = t_last + NS // 2 + 3 * NS // 10 + NS // 20
    _wait_for(lambda: any(r["odom"] > stop_by + NS for r in _records(observer, "odom")),
              30, "ground truth after the stop bound", observer)
    odom = _records(observer, "odom")
    assert max(r["v"] for r in odom if r["odom"] <= t_last) > 0.25  # it drove
    after = [r["v"] for r in odom if r["odom"] >= stop_by]
    assert after
    assert all(v == 0.0 for v in after), after
    assert not any("Rejected cmd_vel" in line for line in sim.err)

    # The same stream on the wall clock is ahead of the simulation: rejected, one warning.
    wall = routed.cli("topic", "pub", "/cmd_vel", "geometry_msgs/msg/TwistStamped",
                      "{header: auto, twist: {linear: {x: 0.3}}}", "-r", "10", "-t", "10",
                      "--wall-time")
    wall.finish(60, "topic pub --wall-time")
    wall_cmds = _records(observer, "cmd")[20:]
    assert len(wall_cmds) == 10
    assert all(c["cmd"] > SIM_TIME_CEILING_NS for c in wall_cmds)
    t_wall_end = max(c["now"] for c in wall_cmds)
    _wait_for(lambda: any(r["odom"] > t_wall_end + NS for r in _records(observer, "odom")),
              30, "ground truth after the wall-clock stream", observer)
    assert all(r["v"] == 0.0 for r in _records(observer, "odom") if r["odom"] >= stop_by)
    warnings = [line for line in sim.err if "stamped in the future" in line]
    assert len(warnings) == 1, warnings
    assert "use_sim_time" in warnings[0]


def test_tools_detect_sim_time_for_frame_ages_and_rates(routed: World) -> None:
    _simulation(routed)
    tree = routed.cli("tf", "tree", "-t", "1.5")
    text = tree.finish(60, "tf tree")
    ages = [float(age) for age in re.findall(r"([0-9.]+) s ago", text)]
    assert ages, text  # dynamic frames (odom -> base_link, the wheels) were listed
    assert max(ages) < 2.0, text  # sim-time ages, not "1.8e9 s ago"
    wall_tree = routed.cli("tf", "tree", "-t", "1.5", "--wall-time")
    wall_ages = [float(a) for a in re.findall(r"([0-9.]+) s ago",
                                              wall_tree.finish(60, "tf tree --wall-time"))]
    assert wall_ages
    assert min(wall_ages) > 1e9  # the stamps are sim time: the wall clock is far ahead
    hz = routed.cli("topic", "hz", "/imu/data", "--count", "2")
    rates = [float(r) for r in re.findall(r"average rate: ([0-9.]+)", hz.finish(60, "hz"))]
    assert len(rates) == 2
    assert all(15.0 < r < 35.0 for r in rates), rates  # 25 Hz per simulated second


def test_a_launch_with_no_clock_publishes_no_clock(routed: World) -> None:
    # Oracle: the graph another process sees. The same launch without --no-clock lists
    # /clock (test_nodes_elsewhere_follow_the_one_simulation_clock follows it).
    sim = routed.cli("launch", "empty_world", "--realtime", "--zenoh", "--no-clock")
    sim.wait_stderr("world 'empty_world'", 30, "the simulation to start")
    listing = routed.cli("topic", "list").finish(60, "topic list").split()
    assert "/imu/data" in listing, listing  # the simulation's topics are visible
    assert "/clock" not in listing, listing
    assert sim.popen.poll() is None


def test_param_list_answers_for_every_node_while_a_simulation_runs(routed: World) -> None:
    # Oracle: the graph another process sees. The clock node is a node there, but it serves
    # no parameters (no executor spins it), so param list neither waits on it nor names it.
    _simulation(routed)
    nodes = routed.cli("node", "list").finish(60, "node list").split()
    assert "/posekit_sim_clock" in nodes
    assert "/world_simulation" in nodes
    services = routed.cli("service", "list").finish(60, "service list").split()
    assert "/world_simulation/list_parameters" in services
    assert not [s for s in services if s.startswith("/posekit_sim_clock/")], services
    params = routed.cli("param", "list")
    text = params.finish(60, "param list")
    assert params.popen.returncode == 0, params.describe()
    headers = [line[:-1] for line in text.splitlines() if not line.startswith(" ")]
    assert headers == sorted(set(nodes) - {"/posekit_sim_clock"}), params.describe()
    assert "  use_sim_time" in text.splitlines()


TICKER = """
import json
from posekit.rclpy.node import Node


class Ticker(Node):
    def __init__(self):
        super().__init__("ticker")
        self.create_timer(0.5, self.tick)

    def tick(self):
        print(json.dumps({"now": self.get_clock().now().nanoseconds}), flush=True)
"""

OWN_LAUNCH = """
from pathlib import Path
from posekit.launch import LaunchDescription, Node
{imports}

def generate_launch_description():
    return LaunchDescription([{world}Node(f"{{Path(__file__).with_name('ticker.py')}}:Ticker")])
"""


def _own_launch(routed: World, name: str, *, world: bool = False) -> str:
    (routed.tmp / "ticker.py").write_text(TICKER)
    path = routed.tmp / name
    path.write_text(OWN_LAUNCH.format(
        imports="from posekit.demos.scenarios import include_scenario" if world else "",
        world='*include_scenario("empty_world"), ' if world else ""))
    return str(path)


def test_a_launch_of_nodes_follows_the_running_simulation_clock(routed: World) -> None:
    # Oracle: the follower's clock (sim time, far below the wall clock, increasing) and the
    # graph (one /clock publisher: the simulation's).
    sim = _simulation(routed)
    nodes = routed.cli("launch", _own_launch(routed, "nodes.launch.py"), "--realtime",
                       "--zenoh")
    nodes.wait_stderr("its nodes follow the running simulation's /clock", 30,
                      "the launch to follow the simulation")
    _wait_for(lambda: len(_records(nodes, "now")) >= 4, 30, "4 sim-time ticks", nodes, sim)
    ticks = [r["now"] for r in _records(nodes, "now")]
    assert all(0 < t < SIM_TIME_CEILING_NS for t in ticks), ticks
    assert ticks == sorted(ticks)
    info = routed.cli("topic", "info", "/clock").finish(30, "topic info /clock")
    assert re.search(r"Publisher count: 1\b", info), info
    # The same with use_sim_time:=true said explicitly.
    explicit = routed.cli("launch", _own_launch(routed, "explicit.launch.py"),
                          "use_sim_time:=true", "--zenoh")
    _wait_for(lambda: len(_records(explicit, "now")) >= 2, 30, "sim-time ticks", explicit)
    assert all(0 < r["now"] < SIM_TIME_CEILING_NS for r in _records(explicit, "now"))
    # A launch with a world of its own would be a second clock source: refused, one line.
    second = routed.cli("launch", _own_launch(routed, "world.launch.py", world=True),
                        "--zenoh", "--until-sim-time", "1")
    second.finish(60, "the launch with a world")
    assert second.popen.returncode != 0
    err = "".join(second.err).strip()
    assert err.count("\n") == 0, err
    assert "another clock source already publishes /clock (/posekit_sim_clock)" in err
    assert sim.popen.poll() is None
    assert nodes.popen.poll() is None, nodes.describe()
