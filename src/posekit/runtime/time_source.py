"""TimeSource: drives a node's ROS clocks from /clock when ``use_sim_time`` is true.

One clock per simulation: a node follows the first publisher of ``/clock`` it hears from.
Where the transport identifies the sending publisher (Zenoh: rmw_zenoh's GID in every
sample), ``/clock`` messages from any other publisher are ignored, with one warning, so a
second simulation or a stray ``topic pub /clock`` cannot move this node's time. If the
followed source falls silent for :data:`SOURCE_SILENCE_S` wall seconds (a simulation that
was stopped and started again), the next source that speaks is followed instead (logged).

A node on a :class:`~posekit.runtime.sim_executor.SimulatedTimeExecutor` is *driven*: the
executor sets its time at every step, and the node does not follow (nor receive) ``/clock``
at all, so nothing outside the simulation can disturb the simulation's own nodes.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any

from posekit.msgs.rosgraph_msgs import Clock as ClockMsg
from posekit.runtime.clock import ROSClock
from posekit.runtime.qos import qos_profile_clock
from posekit.time import stamp_to_ns

if TYPE_CHECKING:
    from posekit.runtime.entities import Subscription
    from posekit.runtime.node import Node

__all__ = ["CLOCK_TOPIC", "SOURCE_SILENCE_S", "TimeSource"]

CLOCK_TOPIC = "/clock"
#: Wall seconds without a message from the followed /clock source before another may take over.
SOURCE_SILENCE_S = 2.0


class TimeSource:
    """Keeps attached ROSClocks on the latest /clock time while ROS time is active."""

    def __init__(self, node: Node) -> None:
        self._node = node
        self._clocks: list[ROSClock] = []
        self._active = False
        self._driven = False
        self._last_ns = 0
        self._sub: Subscription | None = None
        self._source: bytes | None = None
        self._source_seen = 0.0
        self._warned_sources: set[bytes] = set()
        #: /clock messages ignored because a second source sent them.
        self.ignored_messages = 0

    @property
    def ros_time_is_active(self) -> bool:
        """True while clocks follow simulated time."""
        return self._active

    @ros_time_is_active.setter
    def ros_time_is_active(self, active: bool) -> None:
        active = bool(active)
        if active == self._active:
            return
        self._active = active
        self._update_subscription()
        for clock in self._clocks:
            clock._set_ros_time_override(self._last_ns)
            clock._set_ros_time_is_active(active)

    @property
    def driven(self) -> bool:
        """True while an executor sets the time directly (no /clock subscription)."""
        return self._driven

    def set_driven(self, driven: bool) -> None:
        """A simulated-time executor calls this when it takes (or gives back) the node."""
        self._driven = bool(driven)
        self._update_subscription()

    def _update_subscription(self) -> None:
        want = self._active and not self._driven
        if want and self._sub is None:
            self._sub = self._node._subscribe(
                ClockMsg, CLOCK_TOPIC, self._on_clock, qos_profile_clock, None, True
            )
        elif not want and self._sub is not None:
            self._node.destroy_subscription(self._sub)
            self._sub = None

    def attach_clock(self, clock: ROSClock) -> None:
        """Drive ``clock`` too."""
        if not isinstance(clock, ROSClock):
            raise TypeError("only ROSClock instances can follow /clock")
        clock._set_ros_time_override(self._last_ns)
        clock._set_ros_time_is_active(self._active)
        self._clocks.append(clock)

    def _on_clock(self, item: tuple[Any, bytes | None]) -> None:
        msg, source = item
        if source is not None and not self._accept(source):
            return
        self.set_time_ns(stamp_to_ns(msg.clock))

    def _accept(self, source: bytes) -> bool:
        """Whether a /clock message from publisher ``source`` is followed (see module doc)."""
        now = time.monotonic()
        current = self._source
        if current is None or source == current or now - self._source_seen > SOURCE_SILENCE_S:
            if current is not None and source != current:
                self._node.get_logger().info(
                    f"/clock source {current.hex()} fell silent for {SOURCE_SILENCE_S:g} s; "
                    f"following /clock from {source.hex()} now"
                )
            self._source, self._source_seen = source, now
            return True
        self.ignored_messages += 1
        if source not in self._warned_sources:
            self._warned_sources.add(source)
            self._node.get_logger().warning(
                f"Ignoring /clock from a second source (publisher {source.hex()}): this node "
                f"follows the simulation clock of publisher {current.hex()}; only one "
                "simulation may publish /clock on a network"
            )
        return False

    def set_time_ns(self, ns: int) -> None:
        """Set the simulated time of every attached clock (jump callbacks may fire)."""
        if ns == self._last_ns:
            return
        self._last_ns = ns
        if self._active:
            for clock in self._clocks:
                if clock._jump_handles:
                    clock._set_ros_time_override(ns)
                else:  # nothing to notify (the stepped executor's per-step fast path)
                    clock._override_ns = ns

    def destroy(self) -> None:
        """Stop following /clock."""
        if self._sub is not None:
            self._node.destroy_subscription(self._sub)
            self._sub = None
        self._clocks.clear()
