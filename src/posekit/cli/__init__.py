"""The ``posekit`` command: ROS's command-line tools.

tf2_echo, static_transform_publisher, view_frames, topic, node, launch, with their arguments and
output formats.
"""
