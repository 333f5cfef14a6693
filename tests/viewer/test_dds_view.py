"""The viewer's tap on the dds transport follows a real ROS 2 Jazzy node (rclpy on Fast DDS):
what ``posekit view --transport dds`` shows of a real robot. Oracle: the positions the real
node published."""

from __future__ import annotations

import textwrap
import time

import pytest

from _support.dds import dds_context, dds_domain
from _support.procs import Proc
from _support.ros2 import ros2_env, ros2_python
from posekit.viewer.taps import ViewerTap

pytestmark = pytest.mark.slow

ODOM_TALKER = textwrap.dedent("""
    import time
    import rclpy
    from nav_msgs.msg import Odometry
    rclpy.init()
    node = rclpy.create_node("real_ekf")
    pub = node.create_publisher(Odometry, "/odometry/filtered", 10)
    deadline = time.monotonic() + 30
    i = 0
    while time.monotonic() < deadline:
        msg = Odometry()
        msg.header.frame_id, msg.child_frame_id = "odom", "base_link"
        msg.pose.pose.position.x = 3.0
        msg.pose.pose.position.y = -1.5
        pub.publish(msg)
        i += 1
        rclpy.spin_once(node, timeout_sec=0.1)
    rclpy.shutdown()
""")


def test_tap_over_dds_follows_a_real_rclpy_odometry_publisher(
        monkeypatch: pytest.MonkeyPatch) -> None:
    domain = dds_domain(monkeypatch)
    talker = Proc([str(ros2_python()), "-c", ODOM_TALKER], env=ros2_env(domain))
    context = dds_context()
    try:
        tap = ViewerTap(context.transport())
        trail: dict[str, object] = {}
        end = time.monotonic() + 20.0
        while time.monotonic() < end and not trail:
            tap.refresh()
            trail = tap.trails().get("/odometry/filtered", {})
            time.sleep(0.1)
        tap.close()
    finally:
        talker.kill()
        context.try_shutdown()
    assert trail, talker.describe()
    assert trail["trail"][0][:2] == [3.0, -1.5]  # type: ignore[index]
