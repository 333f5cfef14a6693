"""rclpy.constants: ``S_TO_NS``, nanoseconds per second."""

__all__ = ["S_TO_NS"]

S_TO_NS = 1000 * 1000 * 1000
