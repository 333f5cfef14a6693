"""rclpy.parameter (re-exported from posekit.runtime.parameters)."""

from posekit.runtime.parameters import (
    PARAMETER_SEPARATOR_STRING,
    Parameter,
    ParameterDescriptor,
    SetParametersResult,
    parameter_value_to_python,
)

__all__ = [
    "PARAMETER_SEPARATOR_STRING",
    "Parameter",
    "ParameterDescriptor",
    "SetParametersResult",
    "parameter_value_to_python",
]
