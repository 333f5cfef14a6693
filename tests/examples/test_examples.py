"""The lecture's nodes in ``examples/`` (only their imports changed) against the simulator.

In one process, through the example launch files (``posekit.launch.load_launch_file``), and
from a second process over Zenoh. Oracles: the worlds' true marker poses (aruco_box_world:
marker 4 at (2.0, 0, 0.25), markers 2 and 5 at y = -+0.5002; aruco_box_camera_world: the top
marker at (2, 2, 0.5); docs/specs/rosbot_and_worlds.md), the simulator's true robot pose for
the controllers, and tf2's direct lookup for the KDL chain (an independent code path).
The log lines the examples' docstrings promise are checked as printed.
"""

from __future__ import annotations

import math
import os
import re
import signal
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("cv2")

from _support.ports import free_port
from _support.procs import Proc
from posekit.launch import LaunchRun, load_launch_file, start
from posekit.msgs.geometry_msgs import TwistStamped
from posekit.msgs.sensor_msgs import Image
from posekit.runtime.context import Context
from posekit.runtime.logging import LogRecord, add_sink, remove_sink
from posekit.runtime.node import Node
from posekit.tf2_ros import Buffer, TransformListener
from posekit.time import Time

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = REPO / "examples"
FRONT_MARKERS = {"aruco_marker_4": (2.000, 0.000, 0.250),
                 "aruco_marker_2": (2.000, -0.5002, 0.250),
                 "aruco_marker_5": (2.000, 0.5002, 0.250)}
BOX_TOP_MARKER = (2.0, 2.0, 0.5)


class Probe(Node):
    """A TF buffer and recorders of cmd_vel and the debug image, in the launch's context."""

    def __init__(self, ctx: Context) -> None:
        super().__init__("probe", context=ctx, parameter_overrides={"use_sim_time": True})
        self.buffer = Buffer()
        self.listener = TransformListener(self.buffer, self)
        self.cmd_vel: list[TwistStamped] = []
        self.debug_images: list[Image] = []
        self.create_subscription(TwistStamped, "/cmd_vel", self.cmd_vel.append, 10)
        self.create_subscription(Image, "/aruco_detection_image", self.debug_images.append, 10)


class Launched:
    def __init__(self, run: LaunchRun, probe: Probe, logs: list[LogRecord]) -> None:
        self.run, self.probe, self.logs = run, probe, logs

    def lines(self, node: str) -> list[str]:
        return [r.message for r in self.logs if r.name == node]

    def node(self, name: str) -> Any:
        return self.run.node(name)


@pytest.fixture
def launch_example() -> Iterator[Any]:
    runs: list[LaunchRun] = []
    sinks: list[Any] = []

    def launch(file: str, until: float) -> Launched:
        run = start(load_launch_file(EXAMPLES / file), context=Context())
        runs.append(run)
        probe = Probe(run.context)
        run.executor.add_node(probe)
        logs: list[LogRecord] = []
        add_sink(logs.append)
        sinks.append(logs.append)
        run.executor.run_until(until)
        return Launched(run, probe, logs)

    yield launch
    for sink in sinks:
        remove_sink(sink)
    for run in runs:
        run.shutdown()


def _position(buffer: Buffer, target: str, source: str) -> np.ndarray:
    p = buffer.lookup_transform(target, source, Time()).transform.translation
    return np.array([p.x, p.y, p.z])


def test_dynamic_detector_and_listener_put_the_markers_where_they_are(launch_example) -> None:
    out = launch_example("dynamic_detector_listener.launch.py", 3.0)
    # The markers hang off the image's frame, which is the camera's optical frame.
    t = out.probe.buffer.lookup_transform("oak_rgb_camera_optical_frame", "aruco_marker_4",
                                          Time())
    assert t.header.frame_id == "oak_rgb_camera_optical_frame"
    for frame, truth in FRONT_MARKERS.items():
        error = np.linalg.norm(_position(out.probe.buffer, "odom", frame) - truth)
        assert error < 0.03, (frame, error)
    # The expected output of the docstrings, as printed.
    assert "Detected markers: [2, 4, 5]" in out.lines("dynamic_detector_demo")
    listener = out.lines("aruco_marker_listener")
    assert len(listener) == 9  # three markers, once a second for 3 s
    line = re.compile(r"^aruco_marker_(\d): x=(-?\d+\.\d{3}), y=(-?\d+\.\d{3}), z=(-?\d+\.\d{3})$")
    for message in listener:
        match = line.match(message)
        assert match, message
        xyz = np.array([float(v) for v in match.groups()[1:]])
        assert np.linalg.norm(xyz - FRONT_MARKERS[f"aruco_marker_{match[1]}"]) < 0.03
    debug = out.probe.debug_images[-1]
    assert (debug.encoding, debug.header.frame_id) == ("bgr8", "oak_rgb_camera_optical_frame")


def test_static_detector_and_kdl_chain_match_the_direct_lookup(launch_example) -> None:
    out = launch_example("kdl_chain_demo.launch.py", 3.0)
    (published,) = [m for m in out.lines("static_aruco_detector")
                    if m.startswith("Published static TF ")]
    assert published.startswith("Published static TF overhead_camera_optical_frame -> "
                                "static_aruco_box: t=(")
    kdl = out.lines("kdl_chain_demo")
    assert len(kdl) == 3
    pos = re.compile(r"^static_aruco_box in odom: pos=\((-?[\d.]+), (-?[\d.]+), (-?[\d.]+)\) "
                     r"quat=\((-?[\d.]+), (-?[\d.]+), (-?[\d.]+), (-?[\d.]+)\)$")
    match = pos.match(kdl[-1])
    assert match, kdl[-1]
    xyz = np.array([float(v) for v in match.groups()[:3]])
    direct = _position(out.probe.buffer, "odom", "static_aruco_box")
    assert xyz == pytest.approx(direct, abs=0.0006)  # %.3f of the same transform
    assert np.linalg.norm(direct - BOX_TOP_MARKER) < 0.03
    q = out.probe.buffer.lookup_transform("odom", "static_aruco_box", Time()).transform.rotation
    quat = np.array([float(v) for v in match.groups()[3:]])
    q_direct = np.array([q.x, q.y, q.z, q.w])
    assert min(np.abs(quat - q_direct).max(), np.abs(quat + q_direct).max()) < 0.0006


def test_p_controller_reaches_the_goal_in_the_true_world(launch_example) -> None:
    out = launch_example("p_controller_demo.launch.py", 40.0)
    (reached,) = [m for m in out.lines("p_controller_demo") if m.startswith("Goal reached:")]
    assert re.match(r"^Goal reached: x=\d\.\d\d, y=\d\.\d\d, yaw=\d\.\d\d$", reached)
    x, y, yaw = out.node("world_simulation").true_pose
    assert math.hypot(x - 5.0, y - 5.0) < 0.25  # tolerance 0.10 on the EKF's estimate + drift
    assert abs(math.remainder(yaw - math.pi / 2, 2 * math.pi)) < 0.15
    last = out.probe.cmd_vel[-1].twist
    assert (last.linear.x, last.angular.z) == (0.0, 0.0)  # it stopped commanding motion


def test_random_mover_sends_bounded_random_commands_that_move_the_robot(launch_example) -> None:
    out = launch_example("random_mover_demo.launch.py", 5.0)
    commands = [(c.twist.linear.x, c.twist.angular.z) for c in out.probe.cmd_vel]
    assert len(commands) == 10  # 2 Hz for 5 s
    assert len(set(commands)) == 10
    assert all(abs(v) <= 0.5 and abs(w) <= 1.0 for v, w in commands)
    assert all(c.header.frame_id == "base_link" for c in out.probe.cmd_vel)
    x, y, yaw = out.node("world_simulation").true_pose
    assert math.hypot(x, y) > 0.01 or abs(yaw) > 0.05
    odom_lines = [m for m in out.lines("random_mover_demo") if m.startswith("Odom: ")]
    assert 4 <= len(odom_lines) <= 6  # at most once a second
    assert all(re.match(r"^Odom: x=-?\d+\.\d\d, y=-?\d+\.\d\d, yaw=-?\d+\.\d\d$", m)
               for m in odom_lines)


@pytest.mark.slow
def test_kdl_chain_demo_from_a_second_process_over_zenoh(tmp_path: Path) -> None:
    pytest.importorskip("zenoh")
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("ZENOH_", "ROS_DOMAIN", "POSEKIT_"))}
    env.update(POSEKIT_ZENOH_ROUTER=f"tcp/127.0.0.1:{free_port()}", PYTHONUNBUFFERED="1")
    world = Proc([sys.executable, "-m", "posekit.cli.main", "launch", "static_aruco_detector",
                  "--zenoh", "--realtime", "--until-sim-time", "60"], env, cwd=tmp_path)
    node = Proc([sys.executable, str(EXAMPLES / "kdl_chain_demo.py")],
                {**env, "POSEKIT_TRANSPORT": "zenoh"}, cwd=tmp_path)
    try:
        line = re.compile(r"\[kdl_chain_demo\]: static_aruco_box in odom: "
                          r"pos=\((-?[\d.]+), (-?[\d.]+), (-?[\d.]+)\)")
        deadline = time.monotonic() + 40.0
        found = None
        while found is None:
            found = next((m for m in map(line.search, node.err) if m), None)
            assert node.popen.poll() is None, node.describe()
            assert world.popen.poll() is None, world.describe()
            assert time.monotonic() < deadline, f"no KDL line\n{node.describe()}"
            time.sleep(0.2)
        xyz = np.array([float(v) for v in found.groups()])
        assert np.linalg.norm(xyz - BOX_TOP_MARKER) < 0.03
    finally:
        node.kill(signal.SIGINT)
        node.kill()
        world.kill(signal.SIGINT)
        world.kill()
