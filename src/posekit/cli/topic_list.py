"""``posekit topic list|info|type|find``: ``ros2 topic``'s graph verbs (Jazzy formats).

* ``list [-t] [-c] [-v] [--include-hidden-topics]``: one topic per line, ``-t`` adds
  ``[type]``; ``-v`` prints ``Published topics:`` / ``Subscribed topics:`` sections with
  `` * /topic [type] N publishers`` lines.
* ``info TOPIC [-v]``: ``Type:``, ``Publisher count:``, ``Subscription count:``; ``-v`` lists
  every endpoint with node, type hash, GID and QoS.
* ``type TOPIC``: the topic's type(s), exit 1 when the topic is unknown.
* ``find TYPE [-c]``: the topics of a type.

When nothing but the tool itself is on the graph, a hint on stderr says what to check.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from typing import Any, TextIO

from posekit.cli._graph import (
    add_transport_args,
    empty_graph_hint,
    is_hidden_name,
    publishers_info,
    resolve_topic,
    session_for,
    subscriptions_info,
    sync_graph,
    topic_types,
)

__all__ = ["main_find", "main_info", "main_list", "main_type"]


def _topics(session: Any, include_hidden: bool, err: TextIO) -> list[tuple[str, list[str]]]:
    sync_graph(session)
    topics = [(name, list(types)) for name, types in session.node.get_topic_names_and_types()
              if include_hidden or not is_hidden_name(name)]
    hint = empty_graph_hint(session)
    if hint:
        err.write(hint + "\n")
    return topics


def _hidden_arg(parser: argparse.ArgumentParser, short: bool = False) -> None:
    names = ["-a", "--include-hidden-topics"] if short else ["--include-hidden-topics"]
    parser.add_argument(*names, action="store_true", help="Consider hidden topics as well")


def main_list(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
              err: TextIO | None = None) -> int:
    """``topic list [-t] [-c] [-v] [--include-hidden-topics]``."""
    out = out or sys.stdout
    err = err or sys.stderr
    parser = argparse.ArgumentParser(prog="posekit topic list",
                                     description="Output a list of available topics")
    parser.add_argument("-t", "--show-types", action="store_true",
                        help="Additionally show the topic type")
    parser.add_argument("-c", "--count-topics", action="store_true",
                        help="Only display the number of topics discovered")
    _hidden_arg(parser, short=True)
    parser.add_argument("-v", "--verbose", action="store_true",
                        help="List full details about each topic")
    add_transport_args(parser)
    ns = parser.parse_args(list(argv))
    with session_for(ns, context) as session:
        topics = _topics(session, ns.include_hidden_topics, err)
        counts = {name: (session.node.count_publishers(name),
                         session.node.count_subscribers(name))
                  for name, _ in topics} if ns.verbose else {}
    if ns.count_topics:
        out.write(f"{len(topics)}\n")
    elif topics and ns.verbose:
        for index, title in enumerate(("Published", "Subscribed")):
            lines = [f"{title} topics:"]
            for name, types in topics:
                count = counts[name][index]
                if count:
                    noun = "publisher" if index == 0 else "subscriber"
                    lines.append(f" * {name} [{', '.join(types)}] {count} {noun}"
                                 f"{'s' if count > 1 else ''}")
            out.write("\n".join(lines) + "\n\n")
    else:
        for name, types in topics:
            out.write(f"{name} [{', '.join(types)}]\n" if ns.show_types else f"{name}\n")
    out.flush()
    return 0


def main_type(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
              err: TextIO | None = None) -> int:
    """``topic type TOPIC``: its type names, one per line; exit 1 if unknown (as ros2)."""
    out = out or sys.stdout
    err = err or sys.stderr
    parser = argparse.ArgumentParser(prog="posekit topic type",
                                     description="Print a topic's type")
    parser.add_argument("topic_name", help="Name of the ROS topic to get type (e.g. '/chatter')")
    _hidden_arg(parser)
    add_transport_args(parser)
    ns = parser.parse_args(list(argv))
    with session_for(ns, context) as session:
        topic = resolve_topic(session, ns.topic_name)
        topics = dict(_topics(session, True, err))
    if topic not in topics:
        return 1
    for type_name in topics[topic]:
        out.write(f"{type_name}\n")
    out.flush()
    return 0


def main_find(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
              err: TextIO | None = None) -> int:
    """``topic find TYPE [-c]``: the topics carrying ``TYPE``."""
    out = out or sys.stdout
    err = err or sys.stderr
    parser = argparse.ArgumentParser(
        prog="posekit topic find",
        description="Output a list of available topics of a given type")
    parser.add_argument("topic_type", help="Name of the ROS topic type to filter for "
                                           "(e.g. 'std_msgs/msg/String')")
    parser.add_argument("-c", "--count-topics", action="store_true",
                        help="Only display the number of topics discovered")
    _hidden_arg(parser)
    add_transport_args(parser)
    ns = parser.parse_args(list(argv))
    with session_for(ns, context) as session:
        topics = _topics(session, ns.include_hidden_topics, err)
    found = [name for name, types in topics if ns.topic_type in types]
    if ns.count_topics:
        out.write(f"{len(found)}\n")
    else:
        out.write("".join(f"{name}\n" for name in found))
    out.flush()
    return 0


def _endpoint_block(info: Any, kind: str) -> str:
    """One endpoint as ``ros2 topic info -v`` prints it: rclpy's ``TopicEndpointInfo`` text."""
    from posekit.runtime.topic_endpoint_info import (
        TopicEndpointTypeEnum,
        endpoint_info_from_record,
    )

    return str(endpoint_info_from_record(info, TopicEndpointTypeEnum[kind])) + "\n\n"


def main_info(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
              err: TextIO | None = None) -> int:
    """``topic info TOPIC [-v]``."""
    out = out or sys.stdout
    err = err or sys.stderr
    parser = argparse.ArgumentParser(prog="posekit topic info")
    parser.add_argument("topic_name")
    parser.add_argument("-v", "--verbose", action="store_true",
                        help="print endpoint details (node, type hash, GID, QoS)")
    add_transport_args(parser)
    ns = parser.parse_args(list(argv))
    with session_for(ns, context) as session:
        topic = resolve_topic(session, ns.topic_name)
        sync_graph(session)
        types = topic_types(session, topic)
        if not types:
            err.write(f"Unknown topic '{topic}'\n")
            hint = empty_graph_hint(session)
            if hint:
                err.write(hint + "\n")
            return 1
        pubs = publishers_info(session, topic)
        subs = subscriptions_info(session, topic)
        n_pub = session.node.count_publishers(topic)
        n_sub = session.node.count_subscribers(topic)
    type_text = types[0] if len(types) == 1 else str(types)
    if not ns.verbose:
        out.write(f"Type: {type_text}\nPublisher count: {n_pub}\nSubscription count: {n_sub}\n")
        return 0
    out.write(f"Type: {type_text}\n\nPublisher count: {n_pub}\n\n")
    for info in pubs:
        out.write(_endpoint_block(info, "PUBLISHER"))
    out.write(f"Subscription count: {n_sub}\n\n")
    for info in subs:
        out.write(_endpoint_block(info, "SUBSCRIPTION"))
    return 0
