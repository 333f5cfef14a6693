"""``wait_for_message(msg_type, node, topic)``: block until one message arrives (rclpy's).

Like rclpy (which waits on a wait set holding only a fresh subscription), this subscribes on
the node's transport directly, so no executor is involved: it works whether or not the node
is being spun elsewhere, and the node's callbacks never see the message. The subscription is
removed before returning. ``time_to_wait`` is in wall-clock seconds (negative: no limit); a
context shutdown during the wait returns ``(False, None)``.

In one process with a stepped ``SimulatedTimeExecutor`` nothing is published while the
stepping thread waits here: call it from another thread, or use a subscription.
"""

from __future__ import annotations

import queue
import time
from typing import TYPE_CHECKING, Any

from posekit.runtime.qos import QoSProfile, to_qos_profile

if TYPE_CHECKING:
    from posekit.runtime.node import Node

__all__ = ["wait_for_message"]

_POLL_S = 0.1  # how often a wait checks the context for shutdown


def wait_for_message(
    msg_type: type,
    node: Node,
    topic: str,
    *,
    qos_profile: QoSProfile | int = 1,
    time_to_wait: float = -1,
) -> tuple[bool, Any]:
    """Wait for the next message on ``topic``.

    Returns:
        ``(True, msg)`` when a message arrived, ``(False, None)`` on timeout or when the
        node's context was shut down during the wait.
    """
    node._check_alive()
    qos = to_qos_profile(qos_profile)
    full = node.resolve_topic_name(topic)
    box: queue.SimpleQueue[Any] = queue.SimpleQueue()
    endpoint = node.transport.subscribe(node._info(msg_type, full, qos), box.put)
    try:
        deadline = None if time_to_wait < 0 else time.monotonic() + float(time_to_wait)
        while node.context.ok():
            wait = _POLL_S if deadline is None else min(_POLL_S, deadline - time.monotonic())
            try:
                return True, box.get(timeout=max(0.0, wait))
            except queue.Empty:
                if deadline is not None and time.monotonic() >= deadline:
                    break
        return False, None
    finally:
        endpoint.destroy()
