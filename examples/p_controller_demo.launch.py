"""posekit's form of ``ros2 launch robot_control_demo p_controller.launch.py`` with the world
of ``rosbot_gazebo empty_world.launch.py``: the simulator and ``p_controller_demo.py`` in
one process.

    posekit launch examples/p_controller_demo.launch.py --until-sim-time 5
"""

from pathlib import Path

from posekit.demos.scenarios import include_scenario
from posekit.launch import LaunchDescription, Node

HERE = Path(__file__).parent


def generate_launch_description():
    return LaunchDescription([
        *include_scenario("empty_world"),
        Node(f"{HERE / 'p_controller_demo.py'}:PControllerDemo", name="p_controller_demo"),
    ])
