"""``posekit lifecycle nodes|get|list|set``: ``ros2 lifecycle``'s verbs (Jazzy).

Output as ros2cli's ros2lifecycle prints it: ``nodes`` the nodes that serve
``<node>/get_state`` (``lifecycle_msgs/srv/GetState``), one per line (``-c``: their number);
``get [NODE]`` ``inactive [2]`` (every lifecycle node, prefixed by its name, without NODE);
``list NODE [-a]`` each available transition (``-a``: the whole graph) as
``- activate [3]`` with its start and goal states; ``set NODE TRANSITION`` (a label or an
id) ``Transitioning successful`` or, on stderr, ``Transitioning failed``. A node that is not
there is ``Node not found`` and an unknown transition lists the available ones, each one
line on stderr with exit code 1. It calls the node's lifecycle services, on the transport
``--transport`` (or ``POSEKIT_TRANSPORT``) names, as ``posekit param`` does.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable, Sequence
from typing import Any, TextIO

from posekit.cli._node_verbs import (
    SERVICE_WAIT_S,
    CliError,
    absolute_node_name,
    call_node_service,
    run_in_session,
    verb_entry,
    wait_for_node_or_fail,
)

__all__ = ["main_get", "main_list", "main_nodes", "main_set", "run"]

_SERVICES = "lifecycle services"


def _lifecycle_nodes(session: Any, include_hidden: bool) -> list[str]:
    """The nodes on the graph that serve ``<node>/get_state`` of lifecycle_msgs' type."""
    from posekit.cli._graph import is_hidden_name, node_names, sync_graph

    sync_graph(session, 2.0)
    served = dict(session.node.get_service_names_and_types())
    return sorted({
        n for n in node_names(session)
        if "lifecycle_msgs/srv/GetState" in served.get(f"{n}/get_state", [])
        and (include_hidden or not is_hidden_name(n))
    })


def _lifecycle_node(ns: argparse.Namespace, session: Any) -> str:
    """The node NODE names, once it is on the graph with its lifecycle services."""
    node = absolute_node_name(ns.node_name)
    wait_for_node_or_fail(session, node, ns.include_hidden_nodes, SERVICE_WAIT_S)
    deadline = time.monotonic() + SERVICE_WAIT_S
    while node not in _lifecycle_nodes(session, True):  # its services may come just after it
        if time.monotonic() > deadline:
            raise CliError("Node not found")
        session.spin_for(0.1)
    return node


def _transitions(session: Any, node: str, graph: bool) -> list[Any]:
    from posekit.msgs.lifecycle_msgs import GetAvailableTransitions

    suffix = "get_transition_graph" if graph else "get_available_transitions"
    return list(call_node_service(session, node, suffix, GetAvailableTransitions,
                                  GetAvailableTransitions.Request(),
                                  _SERVICES).available_transitions)


def _nodes(ns: argparse.Namespace, session: Any, out: TextIO, err: TextIO) -> None:
    names = _lifecycle_nodes(session, ns.all)
    if ns.count_nodes:
        out.write(f"{len(names)}\n")
    elif names:
        out.write("\n".join(names) + "\n")


def _get(ns: argparse.Namespace, session: Any, out: TextIO, err: TextIO) -> None:
    from posekit.msgs.lifecycle_msgs import GetState

    nodes = ([_lifecycle_node(ns, session)] if ns.node_name
             else _lifecycle_nodes(session, ns.include_hidden_nodes))
    for node in nodes:
        state = call_node_service(session, node, "get_state", GetState, GetState.Request(),
                                  _SERVICES).current_state
        prefix = "" if ns.node_name else f"{node}: "
        out.write(f"{prefix}{state.label} [{state.id}]\n")


def _list(ns: argparse.Namespace, session: Any, out: TextIO, err: TextIO) -> None:
    node = _lifecycle_node(ns, session)
    for t in _transitions(session, node, graph=ns.all):
        out.write(f"- {t.transition.label} [{t.transition.id}]\n"
                  f"\tStart: {t.start_state.label}\n\tGoal: {t.goal_state.label}\n")


def _set(ns: argparse.Namespace, session: Any, out: TextIO, err: TextIO) -> None:
    from posekit.msgs.lifecycle_msgs import ChangeState

    node = _lifecycle_node(ns, session)
    available = [t.transition for t in _transitions(session, node, graph=False)]
    chosen = next((t for t in available if t.label == ns.transition), None) or next(
        (t for t in available if str(t.id) == ns.transition), None)
    if chosen is None:
        raise CliError("Unknown transition requested, available ones are:" + "".join(
            f"\n- {t.label} [{t.id}]" for t in available))
    response = call_node_service(session, node, "change_state", ChangeState,
                                 ChangeState.Request(transition=chosen), _SERVICES)
    if response.success:
        out.write("Transitioning successful\n")
    else:
        err.write("Transitioning failed\n")


_VERBS: dict[str, tuple[str, Callable[..., None]]] = {
    "nodes": ("Output a list of nodes with lifecycle", _nodes),
    "get": ("Get lifecycle state for one or more nodes", _get),
    "list": ("Output a list of available transitions", _list),
    "set": ("Trigger lifecycle state transition", _set),
}


def _parser(verb: str) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog=f"posekit lifecycle {verb}",
                                     description=_VERBS[verb][0])
    parser.add_argument("--transport", default=None,
                        help="posekit transport (default: $POSEKIT_TRANSPORT or zenoh)")
    parser.add_argument("--zenoh", action="store_true", help="same as --transport zenoh")
    if verb == "nodes":
        parser.add_argument("-a", "--all", action="store_true",
                            help="Display all nodes even hidden ones")
        parser.add_argument("-c", "--count-nodes", action="store_true",
                            help="Only display the number of nodes discovered")
        return parser
    parser.add_argument("node_name", nargs="?" if verb == "get" else None,
                        help="Name of the ROS node")
    parser.add_argument("--include-hidden-nodes", action="store_true",
                        help="Consider hidden nodes as well")
    if verb == "list":
        parser.add_argument("-a", "--all", action="store_true",
                            help="Display all existing transitions")
    if verb == "set":
        parser.add_argument("transition", help="The lifecycle transition")
    return parser


def run(verb: str, argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
        err: TextIO | None = None) -> int:
    """Run ``posekit lifecycle VERB ARGV``; returns the exit code."""
    return run_in_session(f"posekit lifecycle {verb}", _parser(verb).parse_args(list(argv)),
                          _VERBS[verb][1], context, out or sys.stdout, err or sys.stderr)


main_nodes = verb_entry(run, "lifecycle", "nodes", _VERBS["nodes"][0])
main_get = verb_entry(run, "lifecycle", "get", _VERBS["get"][0])
main_list = verb_entry(run, "lifecycle", "list", _VERBS["list"][0])
main_set = verb_entry(run, "lifecycle", "set", _VERBS["set"][0])
