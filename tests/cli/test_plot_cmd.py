"""``posekit plot odometry|topic`` on recorded bags (directory and lone ``.mcap``).

Oracles: the values the publisher sent (yaw from scipy's Rotation, not posekit's), the PNG
read back by matplotlib's image reader, and the one-line errors of ``posekit.cli.main``.
"""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from posekit.bag import BagOptionError, Recorder
from posekit.bag.series import field_series, odometry_recording
from posekit.cli.main import main
from posekit.msgs.geometry_msgs import PoseStamped
from posekit.msgs.nav_msgs import Odometry
from posekit.runtime.context import Context
from posekit.runtime.node import Node
from posekit.runtime.sim_executor import SimulatedTimeExecutor

pytest.importorskip("matplotlib")


def _quat(yaw: float) -> tuple[float, float, float, float]:
    return tuple(Rotation.from_euler("z", yaw).as_quat())  # type: ignore[return-value]


@pytest.fixture(scope="module")
def bag(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[tuple[float, ...]]]:
    """2 s of /odometry/filtered (a circle), /ground_truth/odom and /goal_pose, at 10 Hz."""
    path = tmp_path_factory.mktemp("plot") / "run"
    context = Context()
    context.init(transport="inprocess")
    sent: list[tuple[float, ...]] = []
    try:
        executor = SimulatedTimeExecutor(context=context, start_time=5.0)
        node = Node("driver", context=context)
        odom = node.create_publisher(Odometry, "/odometry/filtered", 10)
        truth = node.create_publisher(Odometry, "/ground_truth/odom", 10)
        goal = node.create_publisher(PoseStamped, "/goal_pose", 10)

        def tick() -> None:
            now = node.get_clock().now()
            t = now.nanoseconds / 1e9
            yaw = 0.5 * (t - 5.0)
            for pub, offset in ((odom, 0.05), (truth, 0.0)):
                m = Odometry()
                m.header.stamp = now.to_msg()
                m.header.frame_id = "odom"
                m.pose.pose.position.x = math.cos(yaw) + offset
                m.pose.pose.position.y = math.sin(yaw)
                (m.pose.pose.orientation.x, m.pose.pose.orientation.y,
                 m.pose.pose.orientation.z, m.pose.pose.orientation.w) = _quat(yaw + math.pi / 2)
                m.twist.twist.linear.x = 0.5
                m.twist.twist.angular.z = 0.5
                pub.publish(m)
            p = PoseStamped()
            p.header.stamp = now.to_msg()
            p.pose.position.x = 2.0
            p.pose.orientation.w = 1.0
            goal.publish(p)
            sent.append((t, math.cos(yaw), math.sin(yaw), yaw + math.pi / 2))

        node.create_timer(0.1, tick)
        executor.add_node(node)
        recorder = Recorder(path, ["/odometry/filtered", "/ground_truth/odom", "/goal_pose"],
                            context=context)
        executor.add_node(recorder.node)
        executor.run_for(2.05)
        recorder.close()
    finally:
        context.try_shutdown()
    return path, sent


def _wrap(a: np.ndarray) -> np.ndarray:
    return (a + np.pi) % (2 * np.pi) - np.pi


def test_odometry_series_from_directory_and_lone_mcap(
        bag: tuple[Path, list[tuple[float, ...]]], tmp_path: Path) -> None:
    path, sent = bag
    expected = np.array(sent)
    rec = odometry_recording(path)
    assert set(rec.series) == {"filtered", "ground_truth", "/goal_pose"}
    truth = rec.series["ground_truth"]
    np.testing.assert_allclose(truth[:, 0], expected[:, 0], atol=1e-9)
    np.testing.assert_allclose(truth[:, 1:3], expected[:, 1:3], atol=1e-9)
    np.testing.assert_allclose(_wrap(truth[:, 3] - expected[:, 3]), 0.0, atol=1e-9)
    np.testing.assert_allclose(rec.series["filtered"][:, 1], expected[:, 1] + 0.05, atol=1e-9)
    np.testing.assert_allclose(rec.series["filtered"][:, 4:], 0.5)
    np.testing.assert_allclose(rec.series["/goal_pose"][:, 1], 2.0)
    lone = tmp_path / "copy.mcap"  # a storage file without its metadata.yaml
    shutil.copy(path / "run_0.mcap", lone)
    again = odometry_recording(lone, ["/ground_truth/odom"])
    np.testing.assert_array_equal(again.series["ground_truth"], truth)


def test_plot_commands_write_pngs(bag: tuple[Path, list[tuple[float, ...]]],
                                  tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from matplotlib.image import imread

    path, _ = bag
    out = tmp_path / "odom.png"
    assert main(["plot", "odometry", str(path), "-o", str(out)]) == 0
    assert imread(out).shape[:2] == (500, 1500)  # 15 x 5 inches at 100 dpi
    assert main(["plot", "odometry", str(path / "run_0.mcap"), "-o", str(out)]) == 0
    topic_png = tmp_path / "x.png"
    assert main(["plot", "topic", str(path), "/odometry/filtered", "--field",
                 "pose.pose.position.x", "-f", "twist.twist.angular.z", "--subplots",
                 "-o", str(topic_png)]) == 0
    assert imread(topic_png).shape[:2] == (700, 1000)  # 10 x (3 + 2*2) inches
    assert "(20 messages)" in capsys.readouterr().out


def test_field_series_values_and_errors(bag: tuple[Path, list[tuple[float, ...]]],
                                        capsys: pytest.CaptureFixture[str]) -> None:
    path, sent = bag
    t, values = field_series(path, "/odometry/filtered", ["pose.pose.position.y"],
                             header_stamp=True)
    np.testing.assert_allclose(t, [s[0] for s in sent], atol=1e-9)
    np.testing.assert_allclose(values["pose.pose.position.y"], [s[2] for s in sent], atol=1e-9)
    with pytest.raises(BagOptionError, match="not in"):
        field_series(path, "/nope", ["x"])
    with pytest.raises(BagOptionError, match="not a number"):
        field_series(path, "/odometry/filtered", ["header.frame_id"])
    # through the command line: one line, non-zero exit, no traceback
    assert main(["plot", "topic", str(path), "/odometry/filtered", "-f", "pose.nope"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("posekit plot topic: error: Invalid field 'pose.nope'")
    assert err.count("\n") == 1
    assert main(["plot", "odometry", str(path), "--topics", "/nope"]) == 1
    assert "no pose topic ['/nope']" in capsys.readouterr().err
