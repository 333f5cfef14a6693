"""A node + executor for one command-line tool, on the transport other processes share."""

from __future__ import annotations

import argparse
import os
from types import TracebackType
from typing import Any

from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.transport import ENV_TRANSPORT

__all__ = ["TRANSPORT_CHOICES", "ToolSession", "add_transport_option", "tool_transport",
           "transport_option"]

#: What ``--transport`` accepts on every tool (``--zenoh`` stays as an alias).
TRANSPORT_CHOICES = ("inprocess", "zenoh", "dds")


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
            context.init(transport=tool_transport(transport))
        self.context = context
        self.node = Node(node_name, context=context, **node_kwargs)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.node)
        self._listener: Any = None

    def listen_tf(self, buffer: Any) -> None:
        """Fill ``buffer`` from /tf and /tf_static with tf2_ros's QoS."""
        from posekit.runtime.tf2_ros import TransformListener

        self._listener = TransformListener(buffer, self.node)

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
