"""rclpy.parameter_event_handler: ``ParameterEventHandler`` (re-exported from posekit.runtime)."""

from posekit.runtime.parameter_event_handler import (
    ParameterCallbackHandle,
    ParameterEventCallbackHandle,
    ParameterEventHandler,
)

__all__ = ["ParameterCallbackHandle", "ParameterEventCallbackHandle", "ParameterEventHandler"]
