"""rclpy.qos (re-exported from posekit.runtime.qos)."""

from posekit.runtime.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    QoSProfile,
    ReliabilityPolicy,
    qos_profile_clock,
    qos_profile_parameter_events,
    qos_profile_parameters,
    qos_profile_sensor_data,
    qos_profile_services_default,
    qos_profile_system_default,
    qos_profile_unknown,
)

__all__ = [
    "DurabilityPolicy",
    "HistoryPolicy",
    "QoSProfile",
    "ReliabilityPolicy",
    "qos_profile_clock",
    "qos_profile_parameter_events",
    "qos_profile_parameters",
    "qos_profile_sensor_data",
    "qos_profile_services_default",
    "qos_profile_system_default",
    "qos_profile_unknown",
]
