"""``posekit action list|info|send_goal``: ``ros2 action``'s verbs (Jazzy) and output.

* ``list [-t] [-c]``: the actions on the graph (an action is the
  ``<name>/_action/feedback`` topic of an ``..._FeedbackMessage`` type), ``-t`` adds the type.
* ``info ACTION [-t] [-c]``: ``Action: ...``, then the nodes with a client and with a server
  of it (the nodes serving / calling ``<name>/_action/send_goal``).
* ``send_goal ACTION TYPE [GOAL] [-f|--feedback] [--stdin]``: GOAL is YAML
  (``"{pose: {header: {frame_id: odom}, pose: {position: {x: 1.0}}}}"``); prints
  ``Waiting for an action server...``, ``Sending goal:``, ``Goal accepted with ID: <hex>``,
  ``Feedback:`` blocks (``-f``), ``Result:`` and ``Goal finished with status: SUCCEEDED``
  as ros2 does. Ctrl-C while the goal runs cancels it (``Canceling goal...``,
  ``Goal canceled.``). ``--timeout S`` (posekit's addition) bounds the waits for the
  server and the result.

The tool's hidden node runs on the tool transport (Zenoh by default).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from typing import Any, TextIO

__all__ = ["main_info", "main_list", "main_send_goal"]


def _parser(verb: str) -> argparse.ArgumentParser:
    from posekit.cli._graph import add_transport_args

    parser = argparse.ArgumentParser(prog=f"posekit action {verb}")
    add_transport_args(parser)
    return parser


def _session(ns: argparse.Namespace, context: Any) -> Any:
    from posekit.cli._graph import cli_node_name, sync_graph
    from posekit.cli._session import ToolSession, transport_option

    session = ToolSession(cli_node_name(), context=context, transport=transport_option(ns),
                          start_parameter_services=False)
    sync_graph(session, 2.0)
    return session


def main_list(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
              err: TextIO | None = None) -> int:
    """``action list [-t] [-c]``."""
    from posekit.runtime.action import get_action_names_and_types

    out = out or sys.stdout
    parser = _parser("list")
    parser.add_argument("-t", "--show-types", action="store_true",
                        help="Additionally show the action type")
    parser.add_argument("-c", "--count-actions", action="store_true",
                        help="Only display the number of actions discovered")
    ns = parser.parse_args(list(argv))
    with _session(ns, context) as session:
        actions = get_action_names_and_types(session.node)
    if ns.count_actions:
        out.write(f"{len(actions)}\n")
        return 0
    for name, types in actions:
        out.write(f"{name} [{', '.join(types)}]\n" if ns.show_types else f"{name}\n")
    out.flush()
    return 0


def _endpoints(session: Any, action: str) -> tuple[list[tuple[str, list[str]]],
                                                   list[tuple[str, list[str]]]]:
    from posekit.cli.node_cmd import node_names
    from posekit.runtime.action import (
        get_action_client_names_and_types_by_node,
        get_action_server_names_and_types_by_node,
    )

    clients: list[tuple[str, list[str]]] = []
    servers: list[tuple[str, list[str]]] = []
    for fqn in sorted(set(node_names(session))):
        namespace, _, name = fqn.rpartition("/")
        for query, kind in ((get_action_client_names_and_types_by_node, clients),
                            (get_action_server_names_and_types_by_node, servers)):
            kind += [(fqn, types) for found, types in query(session.node, name, namespace or "/")
                     if found == action]
    return clients, servers


def main_info(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
              err: TextIO | None = None) -> int:
    """``action info ACTION [-t] [-c]``."""
    out = out or sys.stdout
    err = err or sys.stderr
    parser = _parser("info")
    parser.add_argument("action_name",
                        help="Name of the ROS action to get info (e.g. '/fibonacci')")
    parser.add_argument("-t", "--show-types", action="store_true",
                        help="Additionally show the action type")
    parser.add_argument("-c", "--count", action="store_true",
                        help="Only display the number of action clients and action servers")
    ns = parser.parse_args(list(argv))
    from posekit.runtime.names import InvalidTopicNameException

    with _session(ns, context) as session:
        try:
            action = session.node.resolve_topic_name(ns.action_name, only_expand=True)
        except InvalidTopicNameException as exc:
            err.write(f"{exc}\n")
            return 1
        own = session.node.get_fully_qualified_name()
        clients, servers = _endpoints(session, action)
    clients = [c for c in clients if c[0] != own]
    lines = [f"Action: {ns.action_name}", f"Action clients: {len(clients)}"]
    if not ns.count:
        lines += [f"    {n} [{', '.join(t)}]" if ns.show_types else f"    {n}" for n, t in clients]
    lines.append(f"Action servers: {len(servers)}")
    if not ns.count:
        lines += [f"    {n} [{', '.join(t)}]" if ns.show_types else f"    {n}" for n, t in servers]
    out.write("".join(f"{line}\n" for line in lines))
    out.flush()
    return 0


_STATUS = {1: "ACCEPTED", 2: "EXECUTING", 3: "CANCELING", 4: "SUCCEEDED", 5: "CANCELED",
           6: "ABORTED"}


def main_send_goal(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
                   err: TextIO | None = None) -> int:
    """``action send_goal ACTION TYPE [GOAL] [-f] [--stdin] [--timeout S]``."""
    from posekit.cli.topic_cmd import (
        MessageFieldError,
        message_to_yaml,
        parse_values,
        set_message_fields,
    )
    from posekit.msgs.errors import UnknownMessageTypeError
    from posekit.msgs.registry import get_action_class
    from posekit.runtime.action import ActionClient

    out = out or sys.stdout
    err = err or sys.stderr
    parser = _parser("send_goal")
    parser.add_argument("action_name", help="Name of the ROS action (e.g. '/fibonacci')")
    parser.add_argument("action_type",
                        help="Type of the ROS action (e.g. 'example_interfaces/action/Fibonacci')")
    group = parser.add_mutually_exclusive_group()
    group.add_argument("goal", nargs="?", default="{}",
                       help="Goal request values in YAML format (e.g. '{order: 10}')")
    group.add_argument("--stdin", action="store_true", help="Read goal from standard input")
    parser.add_argument("-f", "--feedback", action="store_true",
                        help="Echo feedback messages for the goal")
    parser.add_argument("--timeout", type=float, default=None,
                        help="give up after this many seconds without server or result")
    ns = parser.parse_args(list(argv))
    try:
        action_type = get_action_class(ns.action_type)
    except UnknownMessageTypeError:
        err.write("The passed action type is invalid\n")
        return 1
    goal = action_type.Goal()
    try:
        set_message_fields(goal, parse_values(sys.stdin.read() if ns.stdin else ns.goal))
    except MessageFieldError as exc:
        err.write(f"Failed to populate message fields: {exc}\n")
        return 1

    def on_feedback(message: Any) -> None:
        out.write(f"Feedback:\n    {message_to_yaml(message.feedback)}\n")
        out.flush()

    with _session(ns, context) as session:
        client = ActionClient(session.node, action_type, ns.action_name)
        spin = session.executor.spin_until_future_complete
        out.write("Waiting for an action server to become available...\n")
        out.flush()
        if not client.wait_for_server(timeout_sec=ns.timeout):
            err.write(f"action server '{ns.action_name}' did not become available within "
                      f"{ns.timeout:g} s\n")
            return 1
        out.write(f"Sending goal:\n     {message_to_yaml(goal)}\n")
        out.flush()
        sent = client.send_goal_async(goal, on_feedback if ns.feedback else None)
        spin(sent, timeout_sec=ns.timeout)
        if not sent.done():
            err.write(f"no goal response within {ns.timeout:g} s\n")
            return 1
        handle: Any = sent.result()
        if not handle.accepted:
            out.write("Goal was rejected.\n")
            return 0
        out.write(f"Goal accepted with ID: {bytes(bytearray(handle.goal_id.uuid)).hex()}\n\n")
        out.flush()
        result = handle.get_result_async()
        try:
            spin(result, timeout_sec=ns.timeout)
        except KeyboardInterrupt:
            _cancel(session, handle, out)
            raise
        if not result.done():
            err.write(f"no result within {ns.timeout:g} s\n")
            _cancel(session, handle, out)
            return 1
        response = result.result()
        out.write(f"Result:\n    {message_to_yaml(response.result)}\n")
        out.write(f"Goal finished with status: {_STATUS.get(response.status, 'UNKNOWN')}\n")
        out.flush()
    return 0


def _cancel(session: Any, handle: Any, out: TextIO) -> None:
    out.write("Canceling goal...\n")
    out.flush()
    cancel = handle.cancel_goal_async()
    session.executor.spin_until_future_complete(cancel, timeout_sec=10.0)
    if cancel.done() and cancel.result().goals_canceling:
        out.write("Goal canceled.\n")
    out.flush()
