"""posekit's form of ``ros2 launch frame_demo static_aruco_detector.launch.py`` with the world
of ``rosbot_gazebo aruco_box_camera_world.launch.py``: the simulator and
``static_aruco_detector.py`` in one process.

    posekit launch examples/static_aruco_detector.launch.py --until-sim-time 5
"""

from pathlib import Path

from posekit.demos.scenarios import include_scenario
from posekit.launch import LaunchDescription, Node

HERE = Path(__file__).parent


def generate_launch_description():
    return LaunchDescription([
        *include_scenario("aruco_box_camera_world"),
        Node(f"{HERE / 'static_aruco_detector.py'}:StaticArucoDetector", name="static_aruco_detector"),
    ])
