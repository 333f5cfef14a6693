"""posekit: poses, frames, tf2 and a ROS 2-style runtime in one pip install, with no ROS.

Layers (imports point one way): geometry -> msgs -> tf2 -> runtime -> robot / vision ->
demos -> cli / viewer. Importing :mod:`posekit` itself loads nothing heavy.
"""

__version__ = "0.1.0"
__all__ = ["__version__"]
