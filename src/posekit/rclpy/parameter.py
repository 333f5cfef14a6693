"""rclpy.parameter (re-exported from posekit.runtime.parameters)."""

from posekit.runtime.parameters import Parameter, ParameterDescriptor, SetParametersResult

__all__ = ["Parameter", "ParameterDescriptor", "SetParametersResult"]
