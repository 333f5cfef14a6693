"""The lecture's ArUco demonstrations as named scenarios (``posekit launch NAME``).

=============================  ==============================================================
name                           nodes
=============================  ==============================================================
``aruco_box_camera_world``     ROSbot (with ``oak_camera``) in aruco_box_camera_world and
                               ``overhead_camera`` (image, CameraInfo, its static frames):
                               the world alone, for your
                               own detector (``rosbot_gazebo aruco_box_camera_world.launch.py``)
``aruco_box_world``            ROSbot standing in aruco_box_world and ``oak_camera``: the
                               world alone (``rosbot_gazebo aruco_box_world.launch.py``)
``static_aruco_detector``      ROSbot in aruco_box_camera_world, ``overhead_camera`` (image,
                               CameraInfo, its static frames), ``static_aruco_detector``
``kdl_chain_demo``             the same + ``kdl_chain_demo``
``dynamic_detector``           ROSbot in aruco_box_world approaching the boxes
                               (``p_controller``), ``oak_camera``, ``dynamic_detector``
``dynamic_detector_listener``  the same + ``aruco_marker_listener``
=============================  ==============================================================

Detector parameters are the course launch files' (``static_aruco_detector.launch.py``,
``dynamic_detector_demo.launch.py``) with one deliberate change: the dynamic detector's
``marker_size`` is **0.2 m**, the printed size of the aruco_box markers, not the launch's
0.194 m, which scales every estimated range by 0.97 (6 cm short at 2 m). Pass
``marker_size:=0.194`` for the course's value. No ``parent_frame_id`` is set: the simulated
cameras stamp their images with their optical frames, so the detectors parent each marker on
the image's ``header.frame_id`` exactly as the lecture's code does.

Robot motion in the dynamic scenarios: all three front markers (ids 2, 4, 5) are already in
the OAK camera's 60 deg view from the spawn pose, 2 m away. The robot then approaches them,
as the course drives it towards the boxes, with the course's own ``p_controller`` and goal
``(0.8, 0, 0)``: it accelerates to ~0.3 m/s, slows down and stops about 1.2 m from the
markers after ~6 s, where all three still fit in the image (the outer edges at y = +-0.6 m
need a range above 1.04 m). The moving camera shows what the lecture's listener demo is
about: the markers' camera-frame transforms change every frame while their ``odom``
positions stay put. ``p_controller.goal_x:=0.0`` (the controller's inactive goal) keeps
the robot still.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from posekit.launch import LaunchDescription, Node
from posekit.launch.scenarios import register_scenario, scenario_node
from posekit.robot.nodes import PControllerNode
from posekit.robot.scenarios import robot_nodes
from posekit.vision.nodes import (
    ArucoMarkerListener,
    DynamicDetector,
    KdlChainDemo,
    OakCameraNode,
    OverheadCameraNode,
    StaticArucoDetector,
)

__all__ = [
    "APPROACH_GOAL",
    "DYNAMIC_DETECTOR_PARAMS",
    "STATIC_DETECTOR_PARAMS",
    "dynamic_nodes",
    "static_nodes",
]

#: static_aruco_detector.launch.py's detector parameters.
STATIC_DETECTOR_PARAMS: dict[str, Any] = {
    "camera_image_topic": "/overhead_camera/image_raw",
    "camera_info_topic": "/overhead_camera/camera_info",
    "marker_size": 0.2,
    "dictionary_id": "DICT_5X5_250",
    "child_frame_id": "static_aruco_box",
}

#: dynamic_detector_demo.launch.py's parameters, marker_size corrected to the printed 0.2 m.
DYNAMIC_DETECTOR_PARAMS: dict[str, Any] = {
    "camera_image_topic": "/oak/rgb/color",
    "camera_info_topic": "/oak/stereo/camera_info",
    "marker_size": 0.2,
    "dictionary_id": "DICT_5X5_250",
    "publish_tf": True,
}

#: Where the p_controller drives the robot in the dynamic scenarios (x m, y m, yaw rad).
APPROACH_GOAL: tuple[float, float, float] = (0.8, 0.0, 0.0)


def _robot(params: Mapping[str, Any], seed: int, world: str, *,
           world_statics: bool = True) -> list[Node]:
    robot_params = dict(params)
    if not world_statics:
        # The overhead camera node latches its own frames, as the course's launch file does.
        robot_params.setdefault("world_simulation.publish_world_static_transforms", False)
    return robot_nodes(robot_params, seed, world=world)


def static_nodes(params: Mapping[str, Any], seed: int) -> list[Node]:
    """ROSbot in aruco_box_camera_world + overhead camera + static detector."""
    return [
        *_overhead_world(params, seed),
        scenario_node(StaticArucoDetector, "static_aruco_detector", STATIC_DETECTOR_PARAMS,
                      params),
    ]


def dynamic_nodes(params: Mapping[str, Any], seed: int) -> list[Node]:
    """ROSbot approaching the boxes of aruco_box_world + OAK camera + dynamic detector."""
    gx, gy, gyaw = APPROACH_GOAL
    return [
        *_robot(params, seed, "aruco_box_world"),
        scenario_node(PControllerNode, "p_controller",
                      {"goal_x": gx, "goal_y": gy, "goal_yaw": gyaw}, params),
        scenario_node(OakCameraNode, "oak_camera", {"world": "aruco_box_world", "seed": seed},
                      params),
        scenario_node(DynamicDetector, "dynamic_detector", DYNAMIC_DETECTOR_PARAMS, params),
    ]


def _overhead_world(params: Mapping[str, Any], seed: int) -> list[Node]:
    return [
        *_robot(params, seed, "aruco_box_camera_world", world_statics=False),
        scenario_node(OverheadCameraNode, "overhead_camera",
                      {"world": "aruco_box_camera_world", "seed": seed}, params),
        # The robot's own camera too (it renders only while someone subscribes).
        scenario_node(OakCameraNode, "oak_camera",
                      {"world": "aruco_box_camera_world", "seed": seed}, params),
    ]


def _aruco_box_camera_world(params: Mapping[str, Any], seed: int) -> LaunchDescription:
    return LaunchDescription(_overhead_world(params, seed))


def _aruco_box_world(params: Mapping[str, Any], seed: int) -> LaunchDescription:
    return LaunchDescription([
        *_robot(params, seed, "aruco_box_world"),
        scenario_node(OakCameraNode, "oak_camera", {"world": "aruco_box_world", "seed": seed},
                      params),
    ])


def _static_aruco_detector(params: Mapping[str, Any], seed: int) -> LaunchDescription:
    return LaunchDescription(static_nodes(params, seed))


def _kdl_chain_demo(params: Mapping[str, Any], seed: int) -> LaunchDescription:
    return LaunchDescription([
        *static_nodes(params, seed),
        scenario_node(KdlChainDemo, "kdl_chain_demo", {
            "target_frame": "odom", "intermediate_frame": "overhead_camera_optical_frame",
            "source_frame": "static_aruco_box", "period": 1.0}, params),
    ])


def _dynamic_detector(params: Mapping[str, Any], seed: int) -> LaunchDescription:
    return LaunchDescription(dynamic_nodes(params, seed))


def _dynamic_detector_listener(params: Mapping[str, Any], seed: int) -> LaunchDescription:
    return LaunchDescription([
        *dynamic_nodes(params, seed),
        scenario_node(ArucoMarkerListener, "aruco_marker_listener",
                      {"target_frame": "odom", "marker_prefix": "aruco_marker_", "period": 1.0},
                      params),
    ])


register_scenario(
    "aruco_box_camera_world", _aruco_box_camera_world, replace=True,
    description="aruco_box_camera_world: ROSbot + overhead camera, no detector (run your own)",
)
register_scenario(
    "aruco_box_world", _aruco_box_world, replace=True,
    description="aruco_box_world: ROSbot standing + OAK camera, no detector (run your own)",
)
register_scenario(
    "static_aruco_detector", _static_aruco_detector, replace=True,
    description="aruco_box_camera_world: overhead camera + one-shot static ArUco detector",
)
register_scenario(
    "kdl_chain_demo", _kdl_chain_demo, replace=True,
    description="static_aruco_detector + KDL composition of odom -> camera -> box",
)
register_scenario(
    "dynamic_detector", _dynamic_detector, replace=True,
    description="aruco_box_world: ROSbot approaching, OAK camera + per-frame ArUco TF",
)
register_scenario(
    "dynamic_detector_listener", _dynamic_detector_listener, replace=True,
    description="dynamic_detector + listener logging each marker's position in odom",
)
