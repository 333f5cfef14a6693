"""rclpy.parameter_service: ``ParameterService`` (re-exported from posekit.runtime)."""

from posekit.runtime.parameter_service import ParameterService

__all__ = ["ParameterService"]
