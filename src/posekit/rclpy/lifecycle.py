"""rclpy.lifecycle: managed nodes (re-exported from posekit.runtime.lifecycle).

``LifecycleNode`` (also ``Node``), ``LifecycleNodeMixin`` (``NodeMixin``), ``LifecycleState``
(``State``), ``LifecyclePublisher`` (``Publisher``), ``ManagedEntity``,
``SimpleManagedEntity`` and ``TransitionCallbackReturn``.
"""

from posekit.runtime.lifecycle import (
    LifecycleNode,
    LifecycleNodeMixin,
    LifecyclePublisher,
    LifecycleState,
    ManagedEntity,
    SimpleManagedEntity,
    TransitionCallbackReturn,
)

Node = LifecycleNode
NodeMixin = LifecycleNodeMixin
State = LifecycleState
Publisher = LifecyclePublisher

__all__ = [
    "LifecycleNode",
    "LifecycleNodeMixin",
    "LifecyclePublisher",
    "LifecycleState",
    "ManagedEntity",
    "SimpleManagedEntity",
    "TransitionCallbackReturn",
]
