"""A node + executor for one command-line tool, on the transport other processes share."""

from __future__ import annotations

import os
from types import TracebackType
from typing import Any

from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.transport import ENV_TRANSPORT

__all__ = ["ToolSession", "empty_graph_hint", "tool_transport"]


def tool_transport(explicit: str | None = None) -> str:
    """The transport a CLI tool uses: explicit, else $POSEKIT_TRANSPORT, else Zenoh.

    Command-line tools talk to *other* processes, so unlike nodes in one process their default
    is the distributed transport.
    """
    return explicit or os.environ.get(ENV_TRANSPORT, "").strip() or "zenoh"


def empty_graph_hint(what: str, transport: Any) -> str:
    """The one line a tool prints when it finds no ``what`` (topics, nodes) on the graph."""
    where = f"the {getattr(transport, 'name', 'selected')} transport"
    session = getattr(transport, "session", None)
    if session is not None and hasattr(session, "domain_id"):
        endpoint = getattr(getattr(session, "options", None), "router_endpoint", "?")
        hosted = " (hosted by this tool: no router was running)" if session.hosts_router else ""
        where = f"zenoh domain {session.domain_id} via router {endpoint}{hosted}"
    return (f"no {what} found on {where}; check that a launch or node is running (posekit "
            "launch NAME, not --isolated) with the same ROS_DOMAIN_ID, POSEKIT_ZENOH_ROUTER "
            "and POSEKIT_TRANSPORT\n")


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
