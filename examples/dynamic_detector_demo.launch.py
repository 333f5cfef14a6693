"""posekit's form of ``ros2 launch frame_demo dynamic_detector_demo.launch.py`` with the world
of ``rosbot_gazebo aruco_box_world.launch.py``: the simulator and
``dynamic_detector_demo.py`` in one process.

    posekit launch examples/dynamic_detector_demo.launch.py --until-sim-time 5
"""

from pathlib import Path

from posekit.demos.scenarios import include_scenario
from posekit.launch import LaunchDescription, Node

HERE = Path(__file__).parent


def generate_launch_description():
    return LaunchDescription([
        *include_scenario("aruco_box_world"),
        Node(f"{HERE / 'dynamic_detector_demo.py'}:DynamicDetectorDemo", name="dynamic_detector_demo"),
    ])
