"""Runnable demonstrations of the lecture's material (``python -m posekit.demos.<name>``).

* :mod:`posekit.demos.pose_walkthrough` - the "Pose" section: quaternions, composition,
  gimbal lock, computed with :mod:`posekit.geometry`.
"""
