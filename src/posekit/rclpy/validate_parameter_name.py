"""rclpy.validate_parameter_name: ``validate_parameter_name(name)`` (from posekit.runtime)."""

from posekit.runtime.parameters import validate_parameter_name

__all__ = ["validate_parameter_name"]
