"""Graph queries shared by the ``topic``, ``node`` and ``bag`` tools (ros2cli's ``api`` role).

Every tool runs one hidden node (``_posekit_cli_<pid>``) in a :class:`ToolSession` on the tool
transport. Over Zenoh the graph is every liveliness token of the domain, so these helpers see
posekit processes and real ROS 2 nodes on rmw_zenoh alike.
"""

from __future__ import annotations

import argparse
import os
import time
from dataclasses import dataclass, field
from typing import Any, TextIO

from posekit.runtime.names import is_hidden_name

__all__ = [
    "NodeInterfaces",
    "adapted_qos",
    "add_transport_args",
    "cli_node_name",
    "empty_graph_hint",
    "graph_entities",
    "hint_if_alone",
    "is_hidden_name",
    "node_interfaces",
    "node_names",
    "publishers_info",
    "resolve_topic",
    "session_for",
    "subscriptions_info",
    "sync_graph",
    "topic_types",
    "wait_for_node",
    "wait_for_topic_type",
]


def cli_node_name() -> str:
    """The hidden node name every ``posekit topic``/``node`` command uses."""
    return f"_posekit_cli_{os.getpid()}"


def sync_graph(session: Any, timeout: float = 5.0) -> None:
    """Complete the transport's graph snapshot (liveliness query on Zenoh; no-op otherwise)."""
    session.sync_graph(timeout)


def topic_types(session: Any, topic: str) -> list[str]:
    """The types announced for ``topic`` on the graph (empty when unknown)."""
    for name, types in session.node.get_topic_names_and_types():
        if name == topic:
            return list(types)
    return []


def wait_for_topic_type(
    session: Any, topic: str, err: TextIO, timeout: float | None = None
) -> str | None:
    """Wait until ``topic`` is on the graph and return its (first) type; None on timeout."""
    deadline = None if timeout is None else time.monotonic() + timeout
    warned = False
    while True:
        sync_graph(session, 1.0)
        types = topic_types(session, topic)
        if types:
            return types[0]
        if not warned:
            err.write(f"WARNING: topic [{topic}] does not appear to be published yet\n")
            hint = empty_graph_hint(session)
            if hint:
                err.write(hint + "\n")
            err.flush()
            warned = True
        if deadline is not None and time.monotonic() > deadline:
            return None
        session.spin_for(0.1)


def publishers_info(session: Any, topic: str) -> list[Any]:
    """The transport's endpoint records of the publishers on ``topic`` (empty if it cannot tell)."""
    return list(session.node.transport.get_publishers_info_by_topic(topic))


def subscriptions_info(session: Any, topic: str) -> list[Any]:
    """The transport's endpoint records of the subscriptions on ``topic``."""
    return list(session.node.transport.get_subscriptions_info_by_topic(topic))


def graph_entities(session: Any) -> list[Any]:
    """Every entity (node or endpoint record) the transport's graph knows.

    Empty on a transport that cannot tell (the in-process bus).
    """
    return list(session.node.transport.graph_entities())


def node_names(session: Any) -> list[str]:
    """Fully qualified node names on the session's transport (duplicates kept), sorted."""
    return sorted(session.node.transport.get_node_names())


#: The shortest first graph sync of :func:`wait_for_node`: what a fresh participant needs to
#: hear from the peers already running (a shorter ``--timeout`` still gets this much).
_FIRST_SYNC_S = 2.0


def wait_for_node(session: Any, node_fqn: str, timeout: float) -> bool:
    """Whether the node ``node_fqn`` (``/ns/name``) is on the graph, waiting for it if needed.

    The graph of a network transport completes over time: DDS discovery may report itself
    settled before a remote participant (and so its nodes) was found. So the graph is synced
    and asked again until the node is listed or ``timeout`` seconds have passed (the first
    sync may take up to :data:`_FIRST_SYNC_S` s even when ``timeout`` is shorter). Returns
    at once when the node is there. Every command that names a node looks it up here.
    """
    start = time.monotonic()
    deadline = start + max(0.0, timeout)
    sync_graph(session, max(_FIRST_SYNC_S, timeout))
    while node_fqn not in node_names(session):
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            return False
        session.spin_for(min(0.1, remaining))
        sync_graph(session, max(0.0, min(1.0, deadline - time.monotonic())))
    return True


def empty_graph_hint(session: Any) -> str:
    """A one-line hint when no node but the tool's own is visible on a network transport.

    Else ``""`` (an in-process context has no one else to find).
    """
    transport = session.node.transport
    if not transport.crosses_processes:
        return ""
    own = session.node.get_fully_qualified_name()
    if any(name != own for name in node_names(session)):
        return ""
    where = transport.graph_description()
    return (f"hint: no other node is visible on {where}; check that a launch or node is "
            "running (posekit launch NAME, not --isolated) with the same ROS_DOMAIN_ID, "
            "POSEKIT_ZENOH_ROUTER and POSEKIT_TRANSPORT")


def hint_if_alone(session: Any, err: TextIO) -> None:
    """Write :func:`empty_graph_hint` to ``err`` if no other node is on the graph."""
    sync_graph(session, 1.0)
    hint = empty_graph_hint(session)
    if hint:
        err.write(hint + "\n")
        err.flush()


@dataclass
class NodeInterfaces:
    """What ``ros2 node info`` lists for one node: ``(name, [types])`` pairs, sorted."""

    subscribers: list[tuple[str, list[str]]] = field(default_factory=list)
    publishers: list[tuple[str, list[str]]] = field(default_factory=list)
    service_servers: list[tuple[str, list[str]]] = field(default_factory=list)
    service_clients: list[tuple[str, list[str]]] = field(default_factory=list)
    action_servers: list[tuple[str, list[str]]] = field(default_factory=list)
    action_clients: list[tuple[str, list[str]]] = field(default_factory=list)


_ACTION_SERVICE = "/_action/send_goal"


def node_interfaces(session: Any, node_fqn: str) -> NodeInterfaces | None:
    """The interfaces of the node ``node_fqn`` (``/ns/name``) from the graph; None if absent.

    Actions are recognised as rcl_action names them: a service ``<action>/_action/send_goal``
    of type ``pkg/action/Name_SendGoal`` makes ``<action>`` an action server (a client of it,
    an action client) of type ``pkg/action/Name``. The action's own services and topics stay
    in the other sections; their names are hidden (``_action``) as in ROS.
    """
    from posekit.transport.zenoh_wire import EntityKind

    entities = [e for e in graph_entities(session) if e.node_fqn == node_fqn]
    if not any(e.kind is EntityKind.NODE for e in entities):
        return None
    found: dict[str, dict[str, set[str]]] = {}
    for e in entities:
        if e.kind is EntityKind.NODE or not e.topic:
            continue
        kind, name, type_name = e.kind.value, e.topic, e.ros_type or ""
        if kind in ("SS", "SC"):
            type_name = type_name.removesuffix("_Request").removesuffix("_Response")
            if name.endswith(_ACTION_SERVICE):
                action_kind = "AS" if kind == "SS" else "AC"
                found.setdefault(action_kind, {}).setdefault(
                    name[: -len(_ACTION_SERVICE)], set()).add(type_name.removesuffix("_SendGoal"))
        found.setdefault(kind, {}).setdefault(name, set()).add(type_name)

    def section(kind: str) -> list[tuple[str, list[str]]]:
        return [(n, sorted(t)) for n, t in sorted(found.get(kind, {}).items())]

    return NodeInterfaces(
        subscribers=section("MS"), publishers=section("MP"), service_servers=section("SS"),
        service_clients=section("SC"), action_servers=section("AS"),
        action_clients=section("AC"),
    )


def adapted_qos(session: Any, topic: str, out: TextIO, *, default: Any = None) -> Any:
    """The QoS ``ros2 topic echo`` picks for the publishers of a topic.

    Reliable / transient-local only if every publisher offers it, else best effort / volatile
    with a note (starting from ``default``, depth 10).
    """
    from posekit.runtime.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

    base = default if default is not None else QoSProfile(depth=10)
    offers = [info.qos_profile for info in
              session.node.get_publishers_info_by_topic(topic, no_mangle=True)]
    pubs = [q for q in offers if q.reliability != ReliabilityPolicy.UNKNOWN]
    if not pubs:
        return base
    reliable = sum(1 for q in pubs if q.resolved_reliability == ReliabilityPolicy.RELIABLE)
    latched = sum(1 for q in pubs if q.resolved_durability == DurabilityPolicy.TRANSIENT_LOCAL)
    if 0 < reliable < len(pubs):
        out.write("Some, but not all, publishers are offering QoSReliabilityPolicy.RELIABLE. "
                  "Falling back to QoSReliabilityPolicy.BEST_EFFORT as it will connect to all "
                  "publishers\n")
    if 0 < latched < len(pubs):
        out.write("Some, but not all, publishers are offering "
                  "QoSDurabilityPolicy.TRANSIENT_LOCAL. Falling back to "
                  "QoSDurabilityPolicy.VOLATILE as it will connect to all publishers\n")
    return QoSProfile(
        depth=base.depth,
        history=base.history,
        reliability=(ReliabilityPolicy.RELIABLE if reliable == len(pubs)
                     else ReliabilityPolicy.BEST_EFFORT),
        durability=(DurabilityPolicy.TRANSIENT_LOCAL if latched == len(pubs)
                    else DurabilityPolicy.VOLATILE),
    )


def add_transport_args(parser: argparse.ArgumentParser) -> None:
    """``--transport NAME`` and ``--zenoh``, as every graph tool takes them."""
    from posekit.cli._session import add_transport_option

    add_transport_option(parser)


def session_for(ns: argparse.Namespace, context: Any) -> Any:
    """A :class:`ToolSession` on the transport ``ns`` names (or on ``context``, for tests)."""
    from posekit.cli._session import ToolSession, transport_option

    return ToolSession(cli_node_name(), context=context, transport=transport_option(ns))


def resolve_topic(session: Any, topic: str) -> str:
    """``topic`` made fully qualified against the tool node.

    A bad name raises :class:`~posekit.runtime.names.InvalidTopicNameException`.
    """
    resolved: str = session.node.resolve_topic_name(topic)
    return resolved
