"""The lecture's two-terminal demonstrations under the lecture's own names.

In the lecture, terminal 1 starts a world (``ros2 launch rosbot_gazebo empty_world.launch.py``)
and terminal 2 a demo against it (``ros2 launch robot_control_demo p_controller.launch.py``,
``ros2 run robot_control_demo random_mover``). With posekit the same lines work with
``posekit`` in place of ``ros2``:

* **World launches** (``rosbot_gazebo``): the simulated ROSbot with its simulated sensors
  (wheel odometry, IMU, EKF, joint states, the OAK camera, which renders only while someone
  subscribes) in a world, owning the simulation and ``/clock``: ``empty_world`` (here),
  ``aruco_box_world`` and ``aruco_box_camera_world`` (plus the overhead camera and its
  static frames; both from :mod:`posekit.vision.scenarios`), ``aruco_markers_world`` (the
  lecture's name for the listener demo's world: the boxes of ``aruco_box_world``) and
  ``husarion_world`` (Husarion's logo as 1.8 m walls, which the LiDAR sees and the robot
  stops at; the OAK camera does not draw walls).
* **Demo launches** (``robot_control_demo``, ``frame_demo``): only the demo's nodes, on sim
  time that the running world owns (they follow its ``/clock`` and start no simulation), on
  the network transport. They are registered as scenarios named ``PACKAGE/NAME``.

The one-process combined scenarios (``posekit launch p_controller``: world and demo in one
deterministic process) are unchanged and remain the fast path for tests and ``make demo``.

:func:`resolve_launch` maps the command-line forms (``PACKAGE FILE.launch.py``,
``FILE.launch.py``, a scenario name) to a scenario name; :data:`EXECUTABLES` maps
``posekit run PACKAGE EXECUTABLE`` to a demo scenario or to a posekit tool.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from posekit.launch import LaunchDescription
from posekit.launch.scenarios import (
    ScenarioError,
    get_scenario,
    register_scenario,
    scenario_names,
    scenario_node,
)
from posekit.robot.headless import sub_seeds
from posekit.robot.nodes import PControllerNode, RandomMoverNode
from posekit.robot.scenarios import DEFAULT_GOAL, robot_nodes
from posekit.runtime.logging import get_logger

try:  # the ArUco worlds (OpenCV), registered first so that the aliases below find them
    import posekit.vision.scenarios  # noqa: F401
except ModuleNotFoundError as _exc:
    if _exc.name != "cv2":
        raise

__all__ = ["EXECUTABLES", "LAUNCH_FILES", "WORLD_ALIASES", "resolve_launch", "resolve_run"]

#: Worlds the lecture names that posekit runs as another world: name -> (world, note).
WORLD_ALIASES: dict[str, tuple[str, str]] = {
    "aruco_markers_world": (
        "aruco_box_world",
        "aruco_markers_world is the lecture's name for the boxes of aruco_box_world",
    ),
}


def _vision() -> Any:
    """posekit.vision.nodes, or None without OpenCV."""
    try:
        from posekit.vision import nodes
    except ModuleNotFoundError as exc:
        if exc.name != "cv2":
            raise
        return None
    return nodes


def _robot_world(world: str) -> Any:
    """The ROSbot in ``world`` with its OAK camera (when OpenCV is there)."""

    def factory(params: Mapping[str, Any], seed: int) -> LaunchDescription:
        nodes = robot_nodes(params, seed, world=world)
        vision = _vision()
        if vision is not None:
            nodes.append(scenario_node(vision.OakCameraNode, "oak_camera",
                                       {"world": world, "seed": seed}, params))
        return LaunchDescription(nodes)

    return factory


def _alias(name: str) -> Any:
    """The world ``WORLD_ALIASES[name]`` stands for, saying so when it starts."""
    target, note = WORLD_ALIASES[name]

    def factory(params: Mapping[str, Any], seed: int) -> LaunchDescription:
        logger = get_logger("posekit.launch")
        logger.info(f"{name}: {note}")
        description: LaunchDescription = get_scenario(target).factory(params, seed)
        return description

    return factory


#: The lecture's world launch names -> the scenario that runs them (the ArUco worlds are
#: registered by posekit.vision.scenarios when OpenCV is installed).
_WORLDS = ("empty_world", "husarion_world", "aruco_box_world", "aruco_box_camera_world",
           "aruco_markers_world")
register_scenario(
    "empty_world", _robot_world("empty_world"), replace=True,
    description="world only: the ROSbot with its sensors (OAK camera: with OpenCV) in "
                "empty_world",
)
register_scenario(
    "husarion_world", _robot_world("husarion_world"), replace=True,
    description="world only: the ROSbot with its sensors in husarion_world (Husarion's logo "
                "as walls; the cameras do not draw them)",
)
for _name, (_target, _note) in WORLD_ALIASES.items():
    if _target in scenario_names():
        register_scenario(_name, _alias(_name), replace=True,
                          description=f"world only: runs {_target} ({_note.split(':')[0]})")


# -- demos against a running world ----------------------------------------------------------
def _p_controller(params: Mapping[str, Any], seed: int) -> LaunchDescription:
    gx, gy, gyaw = DEFAULT_GOAL
    return LaunchDescription([scenario_node(
        PControllerNode, "p_controller", {"goal_x": gx, "goal_y": gy, "goal_yaw": gyaw}, params
    )])


def _random_mover(params: Mapping[str, Any], seed: int) -> LaunchDescription:
    return LaunchDescription([scenario_node(
        RandomMoverNode, "random_mover", {"seed": sub_seeds(seed)[2]}, params
    )])


def _frame_demo(kind: str) -> Any:
    def factory(params: Mapping[str, Any], seed: int) -> LaunchDescription:
        vision = _vision()
        if vision is None:
            raise ScenarioError(f"frame_demo/{kind} needs OpenCV (pip install posekit[vision])")
        from posekit.vision.scenarios import DYNAMIC_DETECTOR_PARAMS, STATIC_DETECTOR_PARAMS

        static = scenario_node(vision.StaticArucoDetector, "static_aruco_detector",
                               STATIC_DETECTOR_PARAMS, params)
        dynamic = scenario_node(vision.DynamicDetector, "dynamic_detector",
                                DYNAMIC_DETECTOR_PARAMS, params)
        nodes = {
            "static_aruco_detector": [static],
            "kdl_chain_demo": [static, scenario_node(vision.KdlChainDemo, "kdl_chain_demo", {
                "target_frame": "odom", "intermediate_frame": "overhead_camera_optical_frame",
                "source_frame": "static_aruco_box", "period": 1.0}, params)],
            "dynamic_detector_demo": [dynamic],
            "dynamic_detector_listener": [dynamic, scenario_node(
                vision.ArucoMarkerListener, "aruco_marker_listener",
                {"target_frame": "odom", "marker_prefix": "aruco_marker_", "period": 1.0},
                params)],
            "aruco_marker_listener": [scenario_node(
                vision.ArucoMarkerListener, "aruco_marker_listener",
                {"target_frame": "odom", "marker_prefix": "aruco_marker_", "period": 1.0},
                params)],
        }[kind]
        return LaunchDescription(nodes)

    return factory


_DEMOS: dict[str, tuple[Any, str]] = {
    "robot_control_demo/p_controller": (
        _p_controller, f"p_controller to ({DEFAULT_GOAL[0]:g}, {DEFAULT_GOAL[1]:g}, "
                       f"{DEFAULT_GOAL[2]:.2f})"),
    "robot_control_demo/random_mover": (_random_mover, "random 2 Hz velocity commands"),
    "frame_demo/static_aruco_detector": (
        _frame_demo("static_aruco_detector"), "one-shot ArUco detector on the overhead camera"),
    "frame_demo/kdl_chain_demo": (
        _frame_demo("kdl_chain_demo"), "static detector + KDL composition odom -> box"),
    "frame_demo/dynamic_detector_demo": (
        _frame_demo("dynamic_detector_demo"), "per-frame ArUco TF from the OAK camera"),
    "frame_demo/dynamic_detector_listener": (
        _frame_demo("dynamic_detector_listener"), "dynamic detector + marker listener in odom"),
    "frame_demo/aruco_marker_listener": (
        _frame_demo("aruco_marker_listener"), "marker listener in odom"),
}
for _name, (_factory, _text) in _DEMOS.items():
    register_scenario(_name, _factory, replace=True, follows_clock=True,
                      description=f"demo against a running world: {_text}")

#: ``(package, launch file)`` of the lecture -> scenario name.
LAUNCH_FILES: dict[tuple[str, str], str] = {
    **{("rosbot_gazebo", f"{name}.launch.py"): name for name in _WORLDS
       if name in scenario_names()},
    ("robot_control_demo", "p_controller.launch.py"): "robot_control_demo/p_controller",
    ("robot_control_demo", "random_mover.launch.py"): "robot_control_demo/random_mover",
    **{("frame_demo", f"{name}.launch.py"): f"frame_demo/{name}" for name in (
        "static_aruco_detector", "kdl_chain_demo", "dynamic_detector_demo",
        "dynamic_detector_listener")},
}

#: ``posekit run PACKAGE EXECUTABLE``: a demo scenario, or ``("tool", argv prefix)``.
EXECUTABLES: dict[tuple[str, str], str | tuple[str, ...]] = {
    ("robot_control_demo", "random_mover"): "robot_control_demo/random_mover",
    ("robot_control_demo", "p_controller"): "robot_control_demo/p_controller",
    ("frame_demo", "static_aruco_detector"): "frame_demo/static_aruco_detector",
    ("frame_demo", "dynamic_detector_demo"): "frame_demo/dynamic_detector_demo",
    ("frame_demo", "aruco_marker_listener"): "frame_demo/aruco_marker_listener",
    ("frame_demo", "kdl_chain_demo"): "frame_demo/kdl_chain_demo",
    ("tf2_ros", "tf2_echo"): ("tf", "echo"),
    ("tf2_ros", "static_transform_publisher"): ("tf", "static"),
    ("tf2_tools", "view_frames"): ("tf", "frames"),
    ("rqt_tf_tree", "rqt_tf_tree"): ("tf", "tree"),
}


def resolve_launch(words: list[str]) -> str:
    """The scenario that ``posekit launch WORDS...`` names (ScenarioError if none).

    ``[PACKAGE, FILE.launch.py]`` and ``[FILE.launch.py]`` use the lecture's launch files
    (:data:`LAUNCH_FILES`); ``[NAME]`` is a scenario name (``posekit launch --list``).
    """
    if len(words) == 2:
        key = (words[0], words[1] if words[1].endswith(".py") else f"{words[1]}.launch.py")
        if key in LAUNCH_FILES:
            return LAUNCH_FILES[key]
        known = sorted(f"{p} {f}" for p, f in LAUNCH_FILES)
        raise ScenarioError(f"no launch file '{words[1]}' in package '{words[0]}'; known: "
                            + ", ".join(known))
    if len(words) != 1:
        raise ScenarioError(f"expected a scenario, FILE.py or PACKAGE FILE.launch.py, "
                            f"got {' '.join(words)!r}")
    name = words[0]
    if name.endswith(".launch.py"):
        stem = name[: -len(".launch.py")]
        matches = [s for (_, f), s in LAUNCH_FILES.items() if f == name]
        if len(matches) == 1:
            return matches[0]
        name = stem
    if name in scenario_names():
        return name
    get_scenario(name)  # raises with the list of names
    return name


def resolve_run(package: str, executable: str) -> str | tuple[str, ...]:
    """What ``posekit run PACKAGE EXECUTABLE`` starts (ScenarioError listing the known ones)."""
    target = EXECUTABLES.get((package, executable))
    if target is None:
        known = ", ".join(sorted(f"{p} {e}" for p, e in EXECUTABLES))
        raise ScenarioError(f"no executable '{executable}' in package '{package}'; known: "
                            f"{known}")
    return target

