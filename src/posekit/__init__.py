"""posekit: poses, frames, tf2 and a ROS 2-style runtime in one pip install, with no ROS.

Layers, lowest first (a package imports only packages of lower layers; tests/test_layers.py
pins the table and docs/architecture.md describes it): msgs; time, geometry, cv_bridge; tf2,
kdl, worlds; runtime; transport, rclpy, tf2_ros, launch; robot; vision; bag, demos, viewer; cli.
Importing :mod:`posekit` itself loads nothing heavy.
"""

__version__ = "0.1.0"
__all__ = ["__version__"]
