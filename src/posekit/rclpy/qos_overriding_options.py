"""rclpy.qos_overriding_options (re-exported from posekit.runtime.qos_overriding_options)."""

from posekit.runtime.qos_overriding_options import (
    InvalidQosOverridesError,
    QosCallbackResult,
    QosCallbackType,
    QoSOverridingOptions,
)

__all__ = ["InvalidQosOverridesError", "QoSOverridingOptions", "QosCallbackResult",
           "QosCallbackType"]
