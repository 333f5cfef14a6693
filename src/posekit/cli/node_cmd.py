"""``posekit node list [-a] [-c]``: the nodes on the graph, as ``ros2 node list`` prints them.

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

from posekit.cli._graph import cli_node_name, is_hidden_name, node_names, sync_graph

__all__ = ["main", "main_list", "node_names"]

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
    parser.add_argument("--transport", default=None)
    parser.add_argument("--zenoh", action="store_true")
    ns = parser.parse_args(list(argv))

    from posekit.cli._session import ToolSession

    transport = "zenoh" if ns.zenoh else ns.transport
    with ToolSession(cli_node_name(), context=context, transport=transport) as session:
        sync_graph(session)
        own = session.node.get_fully_qualified_name()
        names = [n for n in node_names(session) if n != own and (ns.all or not is_hidden_name(n))]
    if ns.count_nodes:
        out.write(f"{len(names)}\n")
        return 0
    counts = Counter(names)
    if any(c > 1 for c in counts.values()):
        err.write(DUPLICATE_WARNING)
    for name in sorted(counts):
        out.write(f"{name}\n")
    out.flush()
    return 0


def main(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
         err: TextIO | None = None) -> int:
    """``posekit node VERB``; only ``list`` exists."""
    args = list(argv)
    if not args or args[0] != "list":
        (err or sys.stderr).write("usage: posekit node list [-a] [-c]\n")
        return 2
    return main_list(args[1:], context=context, out=out, err=err)
