"""rclpy.service_introspection: ``ServiceIntrospectionState`` (OFF, METADATA, CONTENTS)."""

from posekit.runtime.services import ServiceIntrospectionState

__all__ = ["ServiceIntrospectionState"]
