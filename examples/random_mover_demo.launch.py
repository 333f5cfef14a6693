"""posekit's form of ``ros2 run robot_control_demo random_mover`` with the world of
``rosbot_gazebo empty_world.launch.py``: the simulator and ``random_mover_demo.py`` in one
process.

    posekit launch examples/random_mover_demo.launch.py --until-sim-time 5
"""

from pathlib import Path

from posekit.demos.scenarios import include_scenario
from posekit.launch import LaunchDescription, Node

HERE = Path(__file__).parent


def generate_launch_description():
    return LaunchDescription([
        *include_scenario("empty_world"),
        Node(f"{HERE / 'random_mover_demo.py'}:RandomMoverDemo", name="random_mover_demo"),
    ])
