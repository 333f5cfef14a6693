"""``posekit node list|info``: the nodes on the graph, as ``ros2 node`` prints them (Jazzy).

* ``list [-a] [-c]``: one fully qualified name per line.
* ``info NODE [--include-hidden]``: the node's subscribers, publishers, service servers and
  clients, action servers and clients (``    /name: type``), every section printed, an empty
  one as an empty line, as ``ros2 node info`` prints them. ``Unable to find node 'NODE'`` and
  exit 1 for a node not on the graph within 5 s (a node discovered late is waited for).

Over Zenoh the graph is every ``NN`` liveliness token of the domain: posekit processes and
real ROS 2 nodes running rmw_zenoh alike. Hidden nodes (a name starting with ``_``, such as
the tools' own ``_posekit_cli_<pid>``) are listed only with ``-a``.
"""

from __future__ import annotations

import argparse
import sys
from collections import Counter
from collections.abc import Sequence
from typing import Any, TextIO

from posekit.cli._graph import (
    add_transport_args,
    empty_graph_hint,
    is_hidden_name,
    node_interfaces,
    node_names,
    session_for,
    sync_graph,
    wait_for_node,
)

__all__ = ["main", "main_info", "main_list", "node_names"]

DUPLICATE_WARNING = (
    "WARNING: Be aware that there are nodes in the graph that share an exact name, "
    "which can have unintended side effects.\n"
)


def main_list(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
              err: TextIO | None = None) -> int:
    """``node list``: one fully qualified name per line."""
    out = out or sys.stdout
    err = err or sys.stderr
    parser = argparse.ArgumentParser(prog="posekit node list")
    parser.add_argument("-a", "--all", action="store_true",
                        help="display all nodes even hidden ones")
    parser.add_argument("-c", "--count-nodes", action="store_true",
                        help="only display the number of nodes discovered")
    add_transport_args(parser)
    ns = parser.parse_args(list(argv))
    with session_for(ns, context) as session:
        sync_graph(session)
        own = session.node.get_fully_qualified_name()
        names = [n for n in node_names(session) if n != own and (ns.all or not is_hidden_name(n))]
        hint = empty_graph_hint(session)
    if hint:
        err.write(hint + "\n")
    if ns.count_nodes:
        out.write(f"{len(names)}\n")
        return 0
    if any(c > 1 for c in Counter(names).values()):
        err.write(DUPLICATE_WARNING)
    for name in sorted(names):  # every node, duplicates too, as ros2 node list prints them
        out.write(f"{name}\n")
    out.flush()
    return 0


#: How long ``node info`` waits for the named node to appear on the graph.
INFO_WAIT_S = 5.0

INFO_NONUNIQUE_WARNING = (
    "There are {count} nodes in the graph with the exact name \"{name}\". You are seeing "
    "information about only one of them.\n"
)


def main_info(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
              err: TextIO | None = None) -> int:
    """``node info NODE [--include-hidden]``."""
    from posekit.cli.errors import CliError

    out = out or sys.stdout
    err = err or sys.stderr
    parser = argparse.ArgumentParser(prog="posekit node info",
                                     description="Output information about a node")
    parser.add_argument("node_name", help="Node name to request information")
    parser.add_argument("--include-hidden", action="store_true",
                        help="Display hidden topics, services, and actions as well")
    add_transport_args(parser)
    ns = parser.parse_args(list(argv))
    with session_for(ns, context) as session:
        wait_for_node(session, ns.node_name, INFO_WAIT_S)
        names = [n for n in node_names(session) if ns.include_hidden or not is_hidden_name(n)]
        found = node_interfaces(session, ns.node_name) if ns.node_name in names else None
        hint = empty_graph_hint(session)
    if found is None:
        if hint:
            err.write(hint + "\n")
        raise CliError(f"Unable to find node '{ns.node_name}'")
    count = names.count(ns.node_name)
    if count > 1:
        err.write(INFO_NONUNIQUE_WARNING.format(count=count, name=ns.node_name))

    def visible(items: list[tuple[str, list[str]]]) -> list[tuple[str, list[str]]]:
        return [(n, t) for n, t in items if ns.include_hidden or not is_hidden_name(n)]

    lines = [ns.node_name]
    for title, items in (("Subscribers", found.subscribers), ("Publishers", found.publishers),
                         ("Service Servers", found.service_servers),
                         ("Service Clients", found.service_clients),
                         ("Action Servers", found.action_servers),
                         ("Action Clients", found.action_clients)):
        lines.append(f"  {title}:")
        shown = visible(items)
        lines.extend(f"    {name}: {', '.join(types)}" for name, types in shown)
        if not shown:
            lines.append("")
    out.write("\n".join(lines) + "\n")
    out.flush()
    return 0


def main(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
         err: TextIO | None = None) -> int:
    """``posekit node VERB``: ``list`` or ``info``."""
    args = list(argv)
    verbs = {"list": main_list, "info": main_info}
    if not args or args[0] not in verbs:
        (err or sys.stderr).write("usage: posekit node {list,info} ...\n")
        return 2
    return verbs[args[0]](args[1:], context=context, out=out, err=err)
