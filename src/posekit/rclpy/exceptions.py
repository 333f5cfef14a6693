"""rclpy.exceptions (re-exported from posekit.runtime)."""

from posekit.runtime.context import NotInitializedException
from posekit.runtime.names import (
    InvalidNamespaceException,
    InvalidNodeNameException,
    InvalidServiceNameException,
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
    "InvalidServiceNameException",
    "InvalidTopicNameException",
    "NotInitializedException",
    "ParameterAlreadyDeclaredException",
    "ParameterImmutableException",
    "ParameterNotDeclaredException",
    "ROSInterruptException",
]
