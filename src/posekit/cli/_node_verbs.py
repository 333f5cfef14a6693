"""What the verbs that call a node's services share (``posekit param``, ``posekit lifecycle``).

A tool session without parameter services of its own, the node lookup that waits for a
node discovered late, a service call with bounded waits, one-line errors (:class:`CliError`,
exit code 1) and the run of a verb with its errors reported, never as a traceback.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable, Sequence
from typing import Any, TextIO

from posekit.cli.errors import CliError

__all__ = [
    "SERVICE_WAIT_S",
    "CliError",
    "absolute_node_name",
    "call_node_service",
    "node_lookup_session",
    "run_in_session",
    "verb_entry",
    "visible_nodes",
    "wait_for_node_or_fail",
]

#: How long a verb waits for a node, or for a service to appear (s).
SERVICE_WAIT_S = 5.0
_CALL_TIMEOUT_S = 10.0


def absolute_node_name(name: str) -> str:
    """``talker`` -> ``/talker`` (ros2node's get_absolute_node_name)."""
    return name if name.startswith("/") else "/" + name


# -- graph and service helpers -------------------------------------------------------------
def visible_nodes(session: Any, include_hidden: bool) -> list[str]:
    """The nodes on the graph but the tool's own, sorted (hidden ones with ``include_hidden``)."""
    from posekit.cli._graph import is_hidden_name, node_names, sync_graph

    sync_graph(session, 2.0)
    own = session.node.get_fully_qualified_name()
    return sorted({
        n for n in node_names(session)
        if n != own and (include_hidden or not is_hidden_name(n))
    })


def wait_for_node_or_fail(session: Any, node: str, include_hidden: bool,
                          timeout: float) -> None:
    """Return once ``node`` is on the graph (waiting up to ``timeout`` s), else "Node not found"."""
    from posekit.cli._graph import is_hidden_name, wait_for_node

    hidden = is_hidden_name(node) and not include_hidden
    if hidden or not wait_for_node(session, node, timeout) or \
            node == session.node.get_fully_qualified_name():
        raise CliError("Node not found")


def call_node_service(session: Any, node: str, suffix: str, srv_type: type, request: Any,
                      services: str = "parameter services") -> Any:
    """Call ``<node>/<suffix>`` and return the response (one-line errors otherwise).

    Raises :class:`CliError` when the service does not appear within 5 s ("... waiting for
    ``services`` for node ...") or does not answer within 10 s.
    """
    client = session.node.create_client(srv_type, f"{node}/{suffix}")
    try:
        if not client.wait_for_service(timeout_sec=SERVICE_WAIT_S):
            raise CliError(
                f"Wait for service timed out waiting for {services} for node {node}")
        future = client.call_async(request)
        session.executor.spin_until_future_complete(future, timeout_sec=_CALL_TIMEOUT_S)
        if not future.done():
            raise CliError(
                f"Exception while calling service of node '{node}': no response to "
                f"{suffix} within {_CALL_TIMEOUT_S:g} s"
            )
        return future.result()
    finally:
        session.node.destroy_client(client)


def node_lookup_session(ns: argparse.Namespace, context: Any) -> Any:
    """The tool session of a verb that calls a node's services (``--transport``/``--zenoh``)."""
    from posekit.cli._session import ToolSession
    from posekit.cli.topic_cmd import cli_node_name

    return ToolSession(cli_node_name(), context=context,
                       transport="zenoh" if ns.zenoh else ns.transport,
                       start_parameter_services=False)


def run_in_session(prog: str, ns: argparse.Namespace,
                   handler: Callable[[argparse.Namespace, Any, TextIO, TextIO], None],
                   context: Any, out: TextIO, err: TextIO) -> int:
    """``handler(ns, session, out, err)`` in a :func:`node_lookup_session`; the exit code.

    A :class:`CliError` is its line on ``err`` and its exit code; anything else (a transport that
    cannot start...) one line through :func:`posekit.cli.errors.report`.
    """
    try:
        with node_lookup_session(ns, context) as session:
            handler(ns, session, out, err)
    except CliError as exc:
        err.write(f"{exc}\n")
        return exc.code
    except Exception as exc:  # one line, no traceback
        from posekit.cli.errors import report

        return report(exc, prog, err)
    finally:
        out.flush()
    return 0


def verb_entry(run: Callable[..., int], group: str, verb: str, text: str) -> Callable[..., int]:
    """``main_<verb>(argv, *, context, out, err)``: ``run(verb, argv, ...)`` of ``group``."""
    def entry(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
              err: TextIO | None = None) -> int:
        return run(verb, argv, context=context, out=out, err=err)

    entry.__name__ = f"main_{verb}"
    entry.__doc__ = f"``posekit {group} {verb}``: {text}."
    return entry
