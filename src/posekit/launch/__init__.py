"""posekit.launch: describe nodes with parameters and remappings, run them in one process.

Example::

    from posekit.launch import LaunchDescription, Node, launch
    description = LaunchDescription([
        Node(MyController, name="p_controller", parameters=[{"k_rho": 0.5}],
             remappings=[("cmd_vel", "/robot/cmd_vel")]),
    ])
    launch(description, duration=60.0)   # simulated seconds, as fast as possible
"""

from __future__ import annotations

from posekit.launch.description import (
    CLOCK_SOURCE,
    DeclareLaunchArgument,
    LaunchConfiguration,
    LaunchDescription,
    LaunchDescriptionError,
    Node,
    register_executable,
)
from posekit.launch.runner import LaunchRun, launch, load_launch_file, main, run_launch_file, start

__all__ = [
    "CLOCK_SOURCE",
    "DeclareLaunchArgument",
    "LaunchConfiguration",
    "LaunchDescription",
    "LaunchDescriptionError",
    "LaunchRun",
    "Node",
    "launch",
    "load_launch_file",
    "main",
    "register_executable",
    "run_launch_file",
    "start",
]
