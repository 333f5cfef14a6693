"""``/rosout``: every node's log records published as ``rcl_interfaces/msg/Log``.

A node created with ``enable_rosout=True`` (rclpy's default) owns one :class:`RosoutPublisher`:
a publisher on ``/rosout`` with rcl's rosout QoS (KEEP_LAST 1000, RELIABLE, TRANSIENT_LOCAL,
lifespan 10 s) registered as the rosout handler of the node's logger name
(:func:`posekit.runtime.logging.register_rosout`). Like the rosout publisher rcl creates, it
is not among ``node.publishers``.

``Log.stamp`` is the record's stamp, i.e. the node clock (sim time under ``use_sim_time``),
matching the console line (rcl stamps with the wall clock; docs/runtime.md).

Cost: one small ``Log`` object per emitted record, handed to the transport without a copy
(``publish_transfer``). On the in-process bus with no subscription that is an append to the
publisher's history; records that are filtered by level or throttling cost nothing.
"""

from __future__ import annotations

import contextlib
from typing import TYPE_CHECKING

from posekit.msgs.builtin_interfaces import Time
from posekit.msgs.rcl_interfaces import Log
from posekit.runtime.logging import LogRecord, register_rosout, unregister_rosout
from posekit.runtime.qos import DurabilityPolicy, QoSProfile
from posekit.runtime.transport import EndpointInfo
from posekit.time import Duration

if TYPE_CHECKING:
    from posekit.runtime.node import Node

__all__ = ["ROSOUT_TOPIC", "RosoutPublisher", "qos_profile_rosout_default"]

ROSOUT_TOPIC = "/rosout"

#: rcl's ``rcl_qos_profile_rosout_default``: KEEP_LAST 1000, RELIABLE, TRANSIENT_LOCAL,
#: lifespan 10 s.
qos_profile_rosout_default = QoSProfile(
    depth=1000,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
    lifespan=Duration(seconds=10),
)


class RosoutPublisher:
    """Publishes the records of one node's logger (and its children) on ``/rosout``."""

    def __init__(self, node: Node) -> None:
        logger = node.get_logger()
        info = EndpointInfo(
            ROSOUT_TOPIC, Log, qos_profile_rosout_default, node.get_name(),
            node.get_namespace(), logger,
        )
        self._endpoint = node.transport.advertise(info)
        self._publish = self._endpoint.publish_transfer
        self._alive = True
        self._destroyed = False
        register_rosout(logger.name, self)
        node.context.on_shutdown(self.destroy)

    def __call__(self, record: LogRecord, file: str, function: str, line: int) -> None:
        """Publish ``record`` (called by the logger, see :func:`register_rosout`)."""
        if not self._alive:
            return
        sec, nanosec = divmod(record.stamp_ns, 1_000_000_000)
        msg = Log(Time(sec, nanosec), int(record.severity), record.name, record.message,
                  file, function, line)
        try:
            self._publish(msg)
        except (RuntimeError, OSError, ValueError):
            # The transport went away under the logger (shutdown): the line was printed.
            self.destroy()

    @property
    def subscription_count(self) -> int:
        """Matched ``/rosout`` subscriptions."""
        return self._endpoint.subscription_count

    def destroy(self) -> None:
        """Stop publishing and leave the graph."""
        if not self._destroyed:
            self._alive = False
            self._destroyed = True
            unregister_rosout(self)
            with contextlib.suppress(RuntimeError, OSError):  # transport closed already
                self._endpoint.destroy()
