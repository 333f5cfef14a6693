"""rclpy.parameter (re-exported from posekit.runtime.parameters)."""

from posekit.runtime.parameters import (
    PARAMETER_SEPARATOR_STRING,
    Parameter,
    ParameterDescriptor,
    SetParametersResult,
    get_parameter_value,
    parameter_dict_from_yaml_file,
    parameter_value_to_python,
)

__all__ = [
    "PARAMETER_SEPARATOR_STRING",
    "Parameter",
    "ParameterDescriptor",
    "SetParametersResult",
    "get_parameter_value",
    "parameter_dict_from_yaml_file",
    "parameter_value_to_python",
]
