"""posekit's form of ``ros2 launch frame_demo kdl_chain_demo.launch.py``: the simulated
aruco_box_camera_world, ``static_aruco_detector.py`` (which publishes ``static_aruco_box``)
and ``kdl_chain_demo.py`` in one process.

    posekit launch examples/kdl_chain_demo.launch.py --until-sim-time 3
"""

from pathlib import Path

from posekit.demos.scenarios import include_scenario
from posekit.launch import LaunchDescription, Node

HERE = Path(__file__).parent


def generate_launch_description():
    return LaunchDescription([
        *include_scenario("aruco_box_camera_world"),
        Node(f"{HERE / 'static_aruco_detector.py'}:StaticArucoDetector",
             name="static_aruco_detector"),
        Node(f"{HERE / 'kdl_chain_demo.py'}:KdlChainDemo", name="kdl_chain_demo"),
    ])
