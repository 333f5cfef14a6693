"""rclpy.parameter_client: ``AsyncParameterClient`` (re-exported from posekit.runtime)."""

from posekit.runtime.parameter_client import AsyncParameterClient

__all__ = ["AsyncParameterClient"]
