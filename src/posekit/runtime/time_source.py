"""TimeSource: drives a node's ROS clocks from /clock when ``use_sim_time`` is true."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from posekit.msgs.rosgraph_msgs import Clock as ClockMsg
from posekit.runtime.clock import ROSClock
from posekit.runtime.qos import qos_profile_clock

if TYPE_CHECKING:
    from posekit.runtime.entities import Subscription
    from posekit.runtime.node import Node

__all__ = ["CLOCK_TOPIC", "TimeSource"]

CLOCK_TOPIC = "/clock"


class TimeSource:
    """Keeps attached ROSClocks on the latest /clock time while ROS time is active."""

    def __init__(self, node: Node) -> None:
        self._node = node
        self._clocks: list[ROSClock] = []
        self._active = False
        self._last_ns = 0
        self._sub: Subscription | None = None

    @property
    def ros_time_is_active(self) -> bool:
        """True while clocks follow /clock."""
        return self._active

    @ros_time_is_active.setter
    def ros_time_is_active(self, active: bool) -> None:
        active = bool(active)
        if active == self._active:
            return
        self._active = active
        if active and self._sub is None:
            self._sub = self._node.create_subscription(
                ClockMsg, CLOCK_TOPIC, self._on_clock, qos_profile_clock
            )
        elif not active and self._sub is not None:
            self._node.destroy_subscription(self._sub)
            self._sub = None
        for clock in self._clocks:
            clock._set_ros_time_override(self._last_ns)
            clock._set_ros_time_is_active(active)

    def attach_clock(self, clock: ROSClock) -> None:
        """Drive ``clock`` too."""
        if not isinstance(clock, ROSClock):
            raise TypeError("only ROSClock instances can follow /clock")
        clock._set_ros_time_override(self._last_ns)
        clock._set_ros_time_is_active(self._active)
        self._clocks.append(clock)

    def _on_clock(self, msg: Any) -> None:
        self.set_time_ns(int(msg.clock.sec) * 1_000_000_000 + int(msg.clock.nanosec))

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
