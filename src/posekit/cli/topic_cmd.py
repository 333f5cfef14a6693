"""``posekit topic VERB``: ``ros2 topic``'s verbs, each in its own module.

* :mod:`posekit.cli.topic_list`: ``list``, ``info``, ``type``, ``find``
* :mod:`posekit.cli.topic_echo`: ``echo``
* :mod:`posekit.cli.topic_rate`: ``hz``, ``bw``, ``delay``
* :mod:`posekit.cli.topic_pub`: ``pub``

Each verb runs one hidden node (``_posekit_cli_<pid>``) on the tool transport (Zenoh by
default), so it sees and talks to other posekit processes and to anything speaking rmw_zenoh.
Message <-> YAML conversion lives in :mod:`posekit.msgs.yaml_io`, graph queries in
:mod:`posekit.cli._graph`; their names are re-exported here for existing callers.
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence
from typing import Any, TextIO

from posekit.cli._graph import (
    adapted_qos,
    cli_node_name,
    is_hidden_name,
    sync_graph,
    topic_types,
    wait_for_topic_type,
)
from posekit.cli.topic_echo import main_echo
from posekit.cli.topic_list import main_find, main_info, main_list, main_type
from posekit.cli.topic_pub import main_pub
from posekit.cli.topic_rate import hz_report, main_bw, main_delay, main_hz
from posekit.msgs.yaml_io import (
    TRUNCATE_LENGTH,
    MessageFieldError,
    message_class,
    message_to_ordered,
    message_to_yaml,
    parse_values,
    ros_repr,
    set_message_fields,
    yaml_scalar,
)

__all__ = [
    "TRUNCATE_LENGTH",
    "VERBS",
    "MessageFieldError",
    "adapted_qos",
    "cli_node_name",
    "hz_report",
    "is_hidden_name",
    "main",
    "main_bw",
    "main_delay",
    "main_echo",
    "main_find",
    "main_hz",
    "main_info",
    "main_list",
    "main_pub",
    "main_type",
    "message_class",
    "message_to_ordered",
    "message_to_yaml",
    "parse_values",
    "ros_repr",
    "set_message_fields",
    "sync_graph",
    "topic_types",
    "wait_for_topic_type",
    "yaml_scalar",
]

#: verb -> (function, ros2's one-line description)
VERBS: dict[str, tuple[Callable[..., int], str]] = {
    "bw": (main_bw, "Display bandwidth used by topic"),
    "delay": (main_delay, "Display delay of topic from timestamp in header"),
    "echo": (main_echo, "Output messages from a topic"),
    "find": (main_find, "Output a list of available topics of a given type"),
    "hz": (main_hz, "Print the average publishing rate to screen"),
    "info": (main_info, "Print information about a topic"),
    "list": (main_list, "Output a list of available topics"),
    "pub": (main_pub, "Publish a message to a topic"),
    "type": (main_type, "Print a topic's type"),
}


def main(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
         err: TextIO | None = None) -> int:
    """``posekit topic VERB ...`` (no verb: list the verbs, exit 0, as ``ros2 topic``)."""
    out = out or sys.stdout
    args = list(argv)
    if not args or args[0] not in VERBS:
        lines = ["usage: posekit topic VERB ...", "", "verbs:"]
        lines += [f"  {name:<6}{text}" for name, (_, text) in VERBS.items()]
        known = not args or args[0] in ("-h", "--help")
        (out if known else (err or sys.stderr)).write("\n".join(lines) + "\n")
        return 0 if known else 2
    function = VERBS[args[0]][0]
    return function(args[1:], context=context, out=out, err=err)
