"""rclpy.subscription: ``Subscription`` and ``MessageInfo`` (from posekit.runtime.entities)."""

from posekit.runtime.entities import MessageInfo, Subscription

__all__ = ["MessageInfo", "Subscription"]
