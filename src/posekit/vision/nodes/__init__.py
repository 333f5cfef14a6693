"""The vision nodes of the lecture's frames demos, plus the simulated cameras.

==========================  =============================  ======================================
node (default name)         class                          role in the course
==========================  =============================  ======================================
``oak_camera``              :class:`OakCameraNode`         the ROSbot's OAK-D colour camera
                                                           (Gazebo sensor + ros_gz_bridge)
``overhead_camera``         :class:`OverheadCameraNode`    aruco_box_camera_world's fixed camera
                                                           and its static frames
``static_aruco_detector``   :class:`StaticArucoDetector`   frame_demo static_aruco_detector.py
``dynamic_detector``        :class:`DynamicDetector`       frame_demo dynamic_detector_demo.py
``aruco_marker_listener``   :class:`ArucoMarkerListener`   frame_demo aruco_marker_listener.py
``kdl_chain_demo``          :class:`KdlChainDemo`          frame_demo kdl_chain_demo.py
``image_saver``             :class:`ImageSaver`            posekit: PNG files for rqt_image_view
==========================  =============================  ======================================

Each class takes ``(node_name=..., **Node kwargs)`` and declares the course's parameters;
:mod:`posekit.vision.scenarios` puts them in the lecture's launch configurations. Needs
OpenCV (``pip install posekit[vision]``).
"""

from __future__ import annotations

from posekit.vision.nodes.aruco_marker_listener import ArucoMarkerListener
from posekit.vision.nodes.dynamic_detector import DynamicDetector
from posekit.vision.nodes.image_saver import ImageSaver, attach_image_saver, image_saver_entry
from posekit.vision.nodes.kdl_chain_demo import KdlChainDemo, kdl_to_pose, transform_to_kdl
from posekit.vision.nodes.oak_camera import OakCameraNode
from posekit.vision.nodes.overhead_camera import OverheadCameraNode
from posekit.vision.nodes.static_aruco_detector import StaticArucoDetector

__all__ = [
    "ArucoMarkerListener",
    "DynamicDetector",
    "ImageSaver",
    "KdlChainDemo",
    "OakCameraNode",
    "OverheadCameraNode",
    "StaticArucoDetector",
    "attach_image_saver",
    "image_saver_entry",
    "kdl_to_pose",
    "transform_to_kdl",
]
