"""The ROSbot's nodes: thin posekit.runtime wrappers around the :mod:`posekit.robot` models.

=====================  ====================================  =================================
node (default name)    class                                 role in the course
=====================  ====================================  =================================
``world_simulation``   :class:`WorldSimulation`              Gazebo + ros2_control hardware +
                                                             robot_state_publisher
``wheel_odometry``     :class:`WheelOdometryNode`            diff_drive_controller's odometry
``ekf_node``           :class:`EkfNode`                      robot_localization ekf_node
``p_controller``       :class:`PControllerNode`              robot_control_demo p_controller
``random_mover``       :class:`RandomMoverNode`              robot_control_demo random_mover
``odometry_recorder``  :class:`OdometryRecorder`             posekit: records odometry topics
=====================  ====================================  =================================

Each class takes ``(node_name=..., **Node kwargs)``, declares the course's parameters and
works under any executor; :mod:`posekit.robot.scenarios` puts them in launch descriptions.
"""

from __future__ import annotations

from posekit.robot.nodes.ekf import EkfNode
from posekit.robot.nodes.p_controller import PControllerNode
from posekit.robot.nodes.random_mover import RandomMoverNode
from posekit.robot.nodes.recorder import OdometryRecorder, OdometryRecording
from posekit.robot.nodes.wheel_odometry import WheelOdometryNode
from posekit.robot.nodes.world_simulation import WorldSimulation

__all__ = [
    "EkfNode",
    "OdometryRecorder",
    "OdometryRecording",
    "PControllerNode",
    "RandomMoverNode",
    "WheelOdometryNode",
    "WorldSimulation",
]
