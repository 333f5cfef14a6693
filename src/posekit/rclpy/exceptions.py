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
from posekit.runtime.rate import ROSInterruptException

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
    "ROSInterruptException",
]
