"""The reference peer itself: the real ROS 2 Jazzy rclpy from ``.venv-ros2`` starts, runs on
Fast DDS and answers a graph query. Oracle: the real rclpy (every differential and
interoperability test relies on this environment working)."""

from __future__ import annotations

import pytest

from _support.ros2 import run_ros2_script

pytestmark = pytest.mark.slow  # real processes, sessions or a browser


def test_real_rclpy_runs_on_fast_dds() -> None:
    result = run_ros2_script(
        """
        import rclpy
        from rclpy.utilities import get_rmw_implementation_identifier
        rclpy.init()
        node = rclpy.create_node("reference_probe")
        print(get_rmw_implementation_identifier())
        print(sorted(node.get_node_names()))
        node.destroy_node()
        rclpy.shutdown()
        """,
        domain_id=101,
    )
    assert result.returncode == 0, result.stderr
    lines = result.stdout.split("\n")
    assert lines[0] == "rmw_fastrtps_cpp"
    assert "reference_probe" in lines[1]
