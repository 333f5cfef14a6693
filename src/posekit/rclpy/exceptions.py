"""rclpy.exceptions (re-exported from posekit.runtime)."""

from posekit.runtime.context import NotInitializedException
from posekit.runtime.names import (
    InvalidNamespaceException,
    InvalidNodeNameException,
    InvalidTopicNameException,
)
from posekit.runtime.parameters import (
    InvalidParameterTypeException,
    InvalidParameterValueException,
    ParameterAlreadyDeclaredException,
    ParameterImmutableException,
    ParameterNotDeclaredException,
)

__all__ = [
    "InvalidNamespaceException",
    "InvalidNodeNameException",
    "InvalidParameterTypeException",
    "InvalidParameterValueException",
    "InvalidTopicNameException",
    "NotInitializedException",
    "ParameterAlreadyDeclaredException",
    "ParameterImmutableException",
    "ParameterNotDeclaredException",
]
