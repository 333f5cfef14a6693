"""rclpy.logging (re-exported from posekit.runtime.logging)."""

from posekit.runtime.logging import (
    LoggingSeverity,
    RcutilsLogger,
    get_logger,
    get_logger_effective_level,
    get_logger_level,
    get_logging_severity_from_string,
    set_logger_level,
)

__all__ = ["LoggingSeverity", "RcutilsLogger", "get_logger", "get_logger_effective_level",
           "get_logger_level", "get_logging_severity_from_string", "set_logger_level"]
