"""posekit's form of ``ros2 launch frame_demo dynamic_detector_listener.launch.py``: the
simulated aruco_box_world, ``dynamic_detector_demo.py`` and ``aruco_marker_listener.py`` in
one process.

    posekit launch examples/dynamic_detector_listener.launch.py --until-sim-time 3
"""

from pathlib import Path

from posekit.demos.scenarios import include_scenario
from posekit.launch import LaunchDescription, Node

HERE = Path(__file__).parent


def generate_launch_description():
    return LaunchDescription([
        *include_scenario("aruco_box_world"),
        Node(f"{HERE / 'dynamic_detector_demo.py'}:DynamicDetectorDemo",
             name="dynamic_detector_demo"),
        Node(f"{HERE / 'aruco_marker_listener.py'}:ArucoMarkerListener",
             name="aruco_marker_listener"),
    ])
