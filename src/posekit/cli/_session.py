"""A node + executor for one command-line tool, on the transport other processes share.

Sim time, as ROS tools do it with ``use_sim_time``: :meth:`ToolSession.follow_sim_time` puts
the tool's node clock on ``/clock`` when asked (``--use-sim-time``) or, by default, when a
``/clock`` publisher is on the graph (a simulation is running), so ``header: auto`` stamps,
frame ages, ``tf echo`` and ``topic hz`` use the simulation's time, not the wall clock.
"""

from __future__ import annotations

import argparse
import os
import time
from types import TracebackType
from typing import Any

from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.parameters import Parameter
from posekit.runtime.sim_executor import graph_clock_publishers
from posekit.runtime.transport import ENV_TRANSPORT

__all__ = ["TRANSPORT_CHOICES", "ToolSession", "add_sim_time_args", "add_transport_option",
           "tool_transport", "transport_option"]

#: What ``--transport`` accepts on every tool (``--zenoh`` stays as an alias).
TRANSPORT_CHOICES = ("inprocess", "zenoh", "dds")


def add_sim_time_args(parser: argparse.ArgumentParser) -> None:
    """``--use-sim-time`` (True) / ``--wall-time`` (False) into ``ns.use_sim_time``; neither
    gives None: detect a running simulation (see :meth:`ToolSession.follow_sim_time`)."""
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--use-sim-time", dest="use_sim_time", action="store_const", const=True,
                       default=None, help="use the simulation's /clock (default: when a "
                       "/clock publisher is on the graph)")
    group.add_argument("--wall-time", dest="use_sim_time", action="store_const", const=False,
                       help="use the wall clock even when a simulation publishes /clock")


def tool_transport(explicit: str | None = None) -> str:
    """The transport a CLI tool uses: explicit, else $POSEKIT_TRANSPORT, else Zenoh.

    Command-line tools talk to *other* processes, so unlike nodes in one process their default
    is the distributed transport.
    """
    return explicit or os.environ.get(ENV_TRANSPORT, "").strip() or "zenoh"


def add_transport_option(parser: argparse.ArgumentParser, default_text: str = "zenoh") -> None:
    """``--transport {inprocess,zenoh,dds}`` and its alias ``--zenoh``."""
    parser.add_argument("--transport", default=None, choices=TRANSPORT_CHOICES,
                        help=f"posekit transport (default: $POSEKIT_TRANSPORT or "
                             f"{default_text}); dds joins ROS 2 systems on DDS")
    parser.add_argument("--zenoh", action="store_true", help="same as --transport zenoh")


def transport_option(ns: argparse.Namespace) -> str | None:
    """The transport named by :func:`add_transport_option`'s options (None: the default)."""
    return "zenoh" if getattr(ns, "zenoh", False) else getattr(ns, "transport", None)


class ToolSession:
    """Owns a context (unless one is given), one node named like the ROS tool, an executor."""

    def __init__(self, node_name: str, *, context: Context | None = None,
                 transport: str | None = None, **node_kwargs: Any) -> None:
        self._own_context = context is None
        if context is None:
            context = Context()
            context.init(args=[], transport=tool_transport(transport))
        self.context = context
        # As ros2cli's node: no parameter services (a tool is not a parameter server).
        node_kwargs.setdefault("start_parameter_services", False)
        self.node = Node(node_name, context=context, **node_kwargs)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.node)
        self._listener: Any = None

    def listen_tf(self, buffer: Any) -> None:
        """Fill ``buffer`` from /tf and /tf_static with tf2_ros's QoS."""
        from posekit.tf2_ros import TransformListener

        self._listener = TransformListener(buffer, self.node)

    def sync_graph(self, timeout: float = 5.0) -> None:
        """Complete the transport's graph snapshot (a liveliness query on Zenoh; elsewhere
        just the callbacks ready now)."""
        transport = self.node.transport
        if transport.crosses_processes:
            transport.sync_graph(timeout)
        else:
            self.spin_for(0.0)

    def follow_sim_time(self, use_sim_time: bool | None = None, *,
                        wait_s: float = 2.0) -> bool:
        """Use the simulation's time: True forces it (``--use-sim-time``), None (default)
        detects a ``/clock`` publisher on the graph, False keeps the wall clock. When sim
        time is used, waits up to ``wait_s`` wall seconds for the first ``/clock`` message
        (so ``now()`` is not 0). Returns whether the node clock is on sim time."""
        if use_sim_time is False:
            return False
        if use_sim_time is None and not graph_clock_publishers(self.node.transport):
            return False
        self.node.set_parameters([Parameter("use_sim_time", value=True)])
        clock = self.node.get_clock()
        deadline = time.monotonic() + wait_s
        while clock.now_ns() == 0 and time.monotonic() < deadline and self.context.ok():
            self.spin_for(0.02)
        return True

    def spin_for(self, seconds: float) -> None:
        """Run callbacks for ``seconds`` of wall time (0: only what is ready now)."""
        self.executor.spin_some(max(0.0, seconds))

    def close(self) -> None:
        """Destroy the node, and shut the context down if this session created it."""
        self.executor.remove_node(self.node)
        self.node.destroy_node()
        if self._own_context:
            self.context.shutdown()

    def __enter__(self) -> ToolSession:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()
