"""``posekit topic list|info|echo|hz|pub``: ``ros2 topic``'s verbs, arguments and output formats.

Each verb runs one hidden node (``_posekit_cli_<pid>``) in a :class:`ToolSession` on the tool
transport (Zenoh by default), so it sees and talks to other posekit processes and to anything
speaking rmw_zenoh; the graph comes from liveliness tokens.

* ``list [-t] [-c] [--include-hidden-topics]``: one topic per line, ``-t`` adds ``[type]``.
* ``info TOPIC [-v]``: ``Type:``, ``Publisher count:``, ``Subscription count:``; ``-v`` lists
  every endpoint with node, type hash and QoS.
* ``echo TOPIC [TYPE] [--once] [--count N] [-l N | -f]``: each message as ``ros2 topic echo``
  prints it (``message_to_yaml``: block YAML, arrays and strings truncated to 128 items /
  characters with ``...``), followed by ``---``. The type is learnt from the graph when not
  given; the QoS adapts to the publishers (TRANSIENT_LOCAL if all offer it) as ros2 does.
* ``hz TOPIC [--window N] [--count N]``: once a second
  ``average rate: R\\n\\tmin: As max: Bs std dev: Cs window: N`` from receive times.
* ``pub TOPIC TYPE [VALUES] [-r R] [-1/--once] [-t TIMES] [-w N] [-p N]``: VALUES is YAML
  (``"{linear: {x: 0.5}}"``), parsed with PyYAML's ``safe_load`` exactly like ``ros2 topic
  pub`` (YAML 1.1 scalars, flow or block style); ``header: auto`` and ``stamp: now`` fill in
  the current time. Prints ``publishing #N: pkg.msg.Type(...)`` like ros2.

``--count`` on echo and hz is posekit's addition (exit after N messages / reports).
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import re
import sys
import time
import typing
from collections.abc import Callable, Sequence
from typing import Any, TextIO

import numpy as np

__all__ = [
    "TRUNCATE_LENGTH",
    "MessageFieldError",
    "hz_report",
    "main",
    "message_to_ordered",
    "message_to_yaml",
    "ros_repr",
    "set_message_fields",
    "yaml_scalar",
]

#: ``ros2 topic echo``'s default truncation of arrays, bytes and strings.
TRUNCATE_LENGTH = 128


class MessageFieldError(ValueError):
    """VALUES of ``topic pub`` do not fit the message type (the text says which field)."""


# ---------------------------------------------------------------------------------------
# Messages -> YAML (what rosidl_runtime_py.message_to_yaml prints, without PyYAML)


def _is_message(value: Any) -> bool:
    return dataclasses.is_dataclass(value) and not isinstance(value, type)


def message_to_ordered(value: Any, truncate_length: int | None = TRUNCATE_LENGTH) -> Any:
    """A message as nested dicts (field order kept), lists and Python scalars.

    Sequences longer than ``truncate_length`` keep their first items plus ``'...'``;
    strings keep their first characters plus ``...`` (rosidl_runtime_py's convention).
    """
    if _is_message(value):
        return {
            f.name: message_to_ordered(getattr(value, f.name), truncate_length)
            for f in dataclasses.fields(value)
            if not f.name.startswith("_")
        }
    if isinstance(value, np.ndarray):
        items: list[Any] = value.tolist()
        return _truncate_list(items, truncate_length)
    if isinstance(value, (bytes, bytearray)):
        return _truncate_list(list(value), truncate_length)
    if isinstance(value, (list, tuple)):
        converted = [message_to_ordered(v, truncate_length) for v in value]
        return _truncate_list(converted, truncate_length)
    if isinstance(value, str):
        if truncate_length is not None and len(value) > truncate_length:
            return value[:truncate_length] + "..."
        return value
    if isinstance(value, np.generic):
        return value.item()
    return value


def _truncate_list(items: list[Any], truncate_length: int | None) -> list[Any]:
    if truncate_length is not None and len(items) > truncate_length:
        return [*items[:truncate_length], "..."]
    return items


# YAML 1.1 implicit types (PyYAML's resolvers): a string matching one must be quoted.
_IMPLICIT = re.compile(
    r"""^(?:
      yes|Yes|YES|no|No|NO|true|True|TRUE|false|False|FALSE|on|On|ON|off|Off|OFF
    | [-+]?(?:[0-9][0-9_]*)\.[0-9_]*(?:[eE][-+][0-9]+)?
    | \.[0-9][0-9_]*(?:[eE][-+][0-9]+)?
    | [-+]?[0-9][0-9_]*(?::[0-5]?[0-9])+\.[0-9_]*
    | [-+]?\.(?:inf|Inf|INF)
    | \.(?:nan|NaN|NAN)
    | [-+]?0b[0-1_]+
    | [-+]?0[0-7_]+
    | [-+]?(?:0|[1-9][0-9_]*)
    | [-+]?0x[0-9a-fA-F_]+
    | [-+]?[1-9][0-9_]*(?::[0-5]?[0-9])+
    | <<
    | ~|null|Null|NULL
    | =
    | [0-9][0-9][0-9][0-9]-[0-9][0-9]-[0-9][0-9]
    | [0-9][0-9][0-9][0-9]-[0-9][0-9]?-[0-9][0-9]?(?:[Tt]|[\ \t]+)[0-9][0-9]?:[0-9][0-9]
      :[0-9][0-9](?:\.[0-9]*)?(?:[\ \t]*(?:Z|[-+][0-9][0-9]?(?::[0-9][0-9])?))?
    )$""",
    re.VERBOSE,
)
_WHITESPACE_OR_END = "\0 \t\r\n\x85\u2028\u2029"
_DOUBLE_ESCAPES = {
    "\0": "0", "\x07": "a", "\x08": "b", "\t": "t", "\n": "n", "\x0b": "v", "\x0c": "f",
    "\r": "r", "\x1b": "e", '"': '"', "\\": "\\", "\x85": "N", "\xa0": "_",
    "\u2028": "L", "\u2029": "P",
}


def _printable(ch: str) -> bool:
    o = ord(ch)
    if ch == "\n" or 0x20 <= o <= 0x7E:
        return True
    return (o == 0x85 or 0xA0 <= o <= 0xD7FF or 0xE000 <= o <= 0xFFFD or o >= 0x10000) and (
        o != 0xFEFF
    )


def _string_style(text: str) -> str:
    """'' (plain), "'" or '"' as PyYAML's emitter picks for a block-context value."""
    if not text:
        return "'"
    if any(not _printable(ch) for ch in text) or "\n" in text:
        return '"'
    plain = _IMPLICIT.match(text) is None
    if text[0] == " " or text[-1] == " " or text.startswith(("---", "...")):
        plain = False
    for i, ch in enumerate(text):
        followed = i + 1 == len(text) or text[i + 1] in _WHITESPACE_OR_END
        preceded = i == 0 or text[i - 1] in _WHITESPACE_OR_END
        if i == 0:
            if ch in "#,[]{}&*!|>'\"%@`" or (ch in "?:-" and followed):
                plain = False
        elif (ch == ":" and followed) or (ch == "#" and preceded):
            plain = False
    return "" if plain else "'"


def yaml_scalar(value: Any) -> str:
    """One scalar as PyYAML's ``yaml.dump(..., allow_unicode=True)`` writes it."""
    if value is None:
        return "null"
    if value is True:
        return "true"
    if value is False:
        return "false"
    if isinstance(value, int):
        return str(int(value))
    if isinstance(value, float):
        if value != value:
            return ".nan"
        if value == math.inf:
            return ".inf"
        if value == -math.inf:
            return "-.inf"
        text = repr(float(value)).lower()
        if "." not in text and "e" in text:
            text = text.replace("e", ".0e", 1)
        return text
    text = str(value)
    style = _string_style(text)
    if style == "":
        return text
    if style == "'":
        return "'" + text.replace("'", "''") + "'"
    out = []
    for ch in text:
        if ch in _DOUBLE_ESCAPES:
            out.append("\\" + _DOUBLE_ESCAPES[ch])
        elif _printable(ch) and ch != "\n":
            out.append(ch)
        elif ord(ch) <= 0xFF:
            out.append(f"\\x{ord(ch):02X}")
        elif ord(ch) <= 0xFFFF:
            out.append(f"\\u{ord(ch):04X}")
        else:
            out.append(f"\\U{ord(ch):08X}")
    return '"' + "".join(out) + '"'


def _emit_mapping(data: dict[str, Any], indent: int, lines: list[str]) -> None:
    pad = " " * indent
    for key, value in data.items():
        if isinstance(value, dict) and value:
            lines.append(f"{pad}{key}:")
            _emit_mapping(value, indent + 2, lines)
        elif isinstance(value, list) and value:
            lines.append(f"{pad}{key}:")
            _emit_sequence(value, indent, lines)  # PyYAML does not indent block sequences
        else:
            lines.append(f"{pad}{key}: {_flow_empty_or_scalar(value)}")


def _emit_sequence(items: list[Any], indent: int, lines: list[str]) -> None:
    pad = " " * indent
    for item in items:
        if isinstance(item, dict) and item:
            sub: list[str] = []
            _emit_mapping(item, indent + 2, sub)
            sub[0] = pad + "- " + sub[0][indent + 2 :]
            lines.extend(sub)
        elif isinstance(item, list) and item:
            sub = []
            _emit_sequence(item, indent + 2, sub)
            sub[0] = pad + "- " + sub[0][indent + 2 :]
            lines.extend(sub)
        else:
            lines.append(f"{pad}- {_flow_empty_or_scalar(item)}")


def _flow_empty_or_scalar(value: Any) -> str:
    if isinstance(value, dict):
        return "{}"
    if isinstance(value, list):
        return "[]"
    return yaml_scalar(value)


def message_to_yaml(msg: Any, *, truncate_length: int | None = TRUNCATE_LENGTH) -> str:
    """``msg`` as ``ros2 topic echo`` prints it (before its ``---`` separator line)."""
    data = message_to_ordered(msg, truncate_length)
    if not isinstance(data, dict):
        return yaml_scalar(data) + "\n"
    if not data:
        return "{}\n"
    lines: list[str] = []
    _emit_mapping(data, 0, lines)
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------------------
# ROS's generated __repr__ (``publishing #1: std_msgs.msg.String(data='hi')``)


def _python_type_path(msg: Any) -> str:
    name = getattr(msg, "__msgtype__", None)
    if isinstance(name, str) and name.count("/") == 2:
        pkg, kind, type_name = name.split("/")
        return f"{pkg}.{kind}.{type_name}"
    return type(msg).__name__


def ros_repr(value: Any) -> str:
    """rclpy's message ``repr``: ``geometry_msgs.msg.Vector3(x=1.0, y=0.0, z=0.0)``.

    Fixed-size arrays are numpy arrays in rclpy and print as ``array([...])``; dynamic
    sequences of numbers print as lists.
    """
    if _is_message(value):
        defaults: Any
        try:
            defaults = type(value)()
        except Exception:  # not default-constructible
            defaults = None
        args = []
        for f in dataclasses.fields(value):
            field_value = getattr(value, f.name)
            if isinstance(field_value, np.ndarray):
                default = getattr(defaults, f.name, None)
                fixed = isinstance(default, np.ndarray) and default.size > 0
                text = repr(field_value) if fixed else repr(field_value.tolist())
            else:
                text = ros_repr(field_value)
            args.append(f"{f.name}={text}")
        return f"{_python_type_path(value)}({', '.join(args)})"
    if isinstance(value, list):
        return "[" + ", ".join(ros_repr(v) for v in value) + "]"
    return repr(value)


# ---------------------------------------------------------------------------------------
# VALUES -> message (rosidl_runtime_py.set_message_fields semantics)


def _list_element_class(msg_cls: type, field_name: str) -> type | None:
    """The message class of a ``list[Message]`` field, or None for lists of scalars."""
    try:
        hint = typing.get_type_hints(msg_cls).get(field_name)
    except Exception:
        hint = None
    if hint is not None:
        args = typing.get_args(hint)
        if typing.get_origin(hint) is list and args and dataclasses.is_dataclass(args[0]):
            return typing.cast(type, args[0])
        return None
    # rosbags classes annotate as strings such as 'list[visualization_msgs__msg__Marker]'
    raw = getattr(msg_cls, "__annotations__", {}).get(field_name)
    if isinstance(raw, str):
        match = re.fullmatch(r"list\[(\w+?)__(\w+?)__(\w+)\]", raw)
        if match:
            return message_class("/".join(match.groups()))
    return None


def _now_msg(now_ns: Callable[[], int] | None = None) -> Any:
    from posekit.msgs.builtin_interfaces import Time

    ns = (now_ns or time.time_ns)()
    return Time(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000)


def set_message_fields(msg: Any, values: Any, *, path: str = "",
                       now_ns: Callable[[], int] | None = None) -> None:
    """Assign a parsed YAML mapping to ``msg`` field by field, converting like ros2cli.

    ``header: auto`` -> stamp now and empty frame id; ``stamp: now`` (any Time field) -> now,
    read from ``now_ns`` (default the wall clock; ``topic pub`` passes its node clock, which
    is the simulation's time when one runs).
    Raises :class:`MessageFieldError` naming the field on unknown fields or bad values.
    """
    if values is None:
        return
    if not isinstance(values, dict):
        raise MessageFieldError(
            f"{path or 'message'}: expected a mapping of field names, got {values!r}"
        )
    names = {f.name for f in dataclasses.fields(msg)}
    for name, value in values.items():
        where = f"{path}.{name}" if path else str(name)
        if name not in names:
            raise MessageFieldError(
                f"{type(msg).__name__} has no field {where!r} (fields: {', '.join(sorted(names))})"
            )
        current = getattr(msg, name)
        setattr(msg, name, _converted(type(msg), name, current, value, where, now_ns))


def _converted(owner: type, name: str, current: Any, value: Any, where: str,
               now_ns: Callable[[], int] | None = None) -> Any:
    msgtype = getattr(current, "__msgtype__", "")
    if msgtype == "std_msgs/msg/Header" and value == "auto":
        header = type(current)()
        header.stamp = _now_msg(now_ns)
        return header
    if msgtype == "builtin_interfaces/msg/Time" and value == "now":
        return _now_msg(now_ns)
    try:
        if _is_message(current):
            fresh = type(current)()
            set_message_fields(fresh, value, path=where, now_ns=now_ns)
            return fresh
        if isinstance(current, np.ndarray):
            arr = np.asarray(value, dtype=current.dtype)
            if current.size and arr.shape != current.shape:
                raise MessageFieldError(
                    f"{where}: expected {current.size} values, got {arr.size}"
                )
            return arr
        if isinstance(current, list):
            if not isinstance(value, list):
                raise MessageFieldError(f"{where}: expected a list, got {value!r}")
            elem = _list_element_class(owner, name)
            if elem is None:
                return list(value)
            out = []
            for i, item in enumerate(value):
                child = elem()
                set_message_fields(child, item, path=f"{where}[{i}]", now_ns=now_ns)
                out.append(child)
            return out
        if isinstance(current, bool):
            if not isinstance(value, bool):
                raise MessageFieldError(f"{where}: expected true/false, got {value!r}")
            return value
        if isinstance(current, (bytes, bytearray)):
            return bytes(value)
        if isinstance(current, (int, float, str)):
            if isinstance(current, (int, float)) and isinstance(value, (dict, list)):
                raise MessageFieldError(f"{where}: expected a number, got {value!r}")
            return type(current)(value)
    except MessageFieldError:
        raise
    except (TypeError, ValueError, OverflowError) as exc:
        raise MessageFieldError(f"{where}: cannot use {value!r}: {exc}") from None
    return value


def message_class(type_name: str) -> type:
    """posekit's class for a ROS type, else the rosbags class (any ROS 2 Jazzy type)."""
    from posekit.msgs.registry import find_message_class

    return find_message_class(type_name)


# ---------------------------------------------------------------------------------------
# Graph helpers


def cli_node_name() -> str:
    """The hidden node name every ``posekit topic``/``node`` command uses."""
    return f"_posekit_cli_{os.getpid()}"


def sync_graph(session: Any, timeout: float = 5.0) -> None:
    """Complete the transport's graph snapshot (liveliness query on Zenoh; no-op otherwise)."""
    session.sync_graph(timeout)


def is_hidden_name(name: str) -> bool:
    """ROS's rule: a name with a component starting with ``_`` is hidden."""
    return any(part.startswith("_") for part in name.split("/") if part)


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
            err.flush()
            warned = True
        if deadline is not None and time.monotonic() > deadline:
            return None
        session.spin_for(0.1)


def _publishers_info(session: Any, topic: str) -> list[Any]:
    fn = getattr(session.node.transport, "get_publishers_info_by_topic", None)
    return list(fn(topic)) if fn is not None else []


def _subscriptions_info(session: Any, topic: str) -> list[Any]:
    fn = getattr(session.node.transport, "get_subscriptions_info_by_topic", None)
    return list(fn(topic)) if fn is not None else []


def adapted_qos(session: Any, topic: str, out: TextIO) -> Any:
    """``ros2 topic echo``'s choice: depth 10, reliable / transient-local only if all offer it."""
    from posekit.runtime.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

    pubs = [p for p in _publishers_info(session, topic) if p.qos is not None]
    if not pubs:
        return QoSProfile(depth=10)
    reliable = sum(1 for p in pubs if p.qos.reliable)
    latched = sum(1 for p in pubs if p.qos.transient_local)
    if 0 < reliable < len(pubs):
        out.write("Some publishers offer RELIABLE and some BEST_EFFORT: using BEST_EFFORT to "
                  "connect to all of them\n")
    if 0 < latched < len(pubs):
        out.write("Some publishers offer TRANSIENT_LOCAL and some VOLATILE: using VOLATILE to "
                  "connect to all of them\n")
    return QoSProfile(
        depth=10,
        reliability=(ReliabilityPolicy.RELIABLE if reliable == len(pubs)
                     else ReliabilityPolicy.BEST_EFFORT),
        durability=(DurabilityPolicy.TRANSIENT_LOCAL if latched == len(pubs)
                    else DurabilityPolicy.VOLATILE),
    )


def _add_transport_args(parser: argparse.ArgumentParser) -> None:
    from posekit.cli._session import add_transport_option

    add_transport_option(parser)


def _uses_now(values: Any) -> bool:
    """Whether parsed VALUES ask for the current time (``header: auto`` / ``stamp: now``)."""
    if isinstance(values, dict):
        return any(_uses_now(v) for v in values.values())
    if isinstance(values, list):
        return any(_uses_now(v) for v in values)
    return values in ("auto", "now")


def _transport(ns: argparse.Namespace) -> str | None:
    from posekit.cli._session import transport_option

    return transport_option(ns)


def _session(ns: argparse.Namespace, context: Any) -> Any:
    from posekit.cli._session import ToolSession

    return ToolSession(cli_node_name(), context=context, transport=_transport(ns))


def _resolve(session: Any, topic: str) -> str:
    resolved: str = session.node.resolve_topic_name(topic)
    return resolved


# ---------------------------------------------------------------------------------------
# Verbs


def main_list(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
              err: TextIO | None = None) -> int:
    """``topic list [-t] [-c] [--include-hidden-topics]``."""
    out = out or sys.stdout
    parser = argparse.ArgumentParser(prog="posekit topic list")
    parser.add_argument("-t", "--show-types", action="store_true",
                        help="additionally show the topic type")
    parser.add_argument("-c", "--count-topics", action="store_true",
                        help="only display the number of topics discovered")
    parser.add_argument("-a", "--include-hidden-topics", action="store_true",
                        help="consider hidden topics as well")
    _add_transport_args(parser)
    ns = parser.parse_args(list(argv))
    with _session(ns, context) as session:
        sync_graph(session)
        topics = [
            (name, types) for name, types in session.node.get_topic_names_and_types()
            if ns.include_hidden_topics or not is_hidden_name(name)
        ]
        # The tool's own node publishes /rosout (as ros2cli's does): not a sign of a system.
        if not [name for name, _ in topics if name not in ("/rosout", "/parameter_events")]:
            from posekit.cli._session import empty_graph_hint

            (err or sys.stderr).write(empty_graph_hint("topics", session.node.transport))
    if ns.count_topics:
        out.write(f"{len(topics)}\n")
    for name, types in [] if ns.count_topics else topics:
        out.write(f"{name} [{', '.join(types)}]\n" if ns.show_types else f"{name}\n")
    out.flush()
    return 0


def _qos_lines(info: Any) -> list[str]:
    qos = info.qos
    inf = (9223372036, 854775807)

    def duration(value: tuple[int, int]) -> str:
        if tuple(value) == inf:
            return "Infinite"
        return f"{value[0] * 1_000_000_000 + value[1]} nanoseconds"

    history = {2: "KEEP_ALL", 3: "UNKNOWN"}.get(qos.history, "KEEP_LAST")
    liveliness = {1: "AUTOMATIC", 3: "MANUAL_BY_TOPIC"}.get(qos.liveliness, "UNKNOWN")
    return [
        "QoS profile:",
        f"  Reliability: {'RELIABLE' if qos.reliable else 'BEST_EFFORT'}",
        f"  History (Depth): {history}" + ("" if history == "UNKNOWN" else f" ({qos.depth})"),
        f"  Durability: {'TRANSIENT_LOCAL' if qos.transient_local else 'VOLATILE'}",
        f"  Lifespan: {duration(qos.lifespan)}",
        f"  Deadline: {duration(qos.deadline)}",
        f"  Liveliness: {liveliness}",
        f"  Liveliness lease duration: {duration(qos.liveliness_lease)}",
    ]


def _endpoint_block(info: Any, kind: str) -> str:
    from posekit.transport.zenoh_wire import entity_gid

    own_gid = getattr(info, "gid", None)  # DDS endpoints carry their GUID
    gid = (own_gid.hex() if isinstance(own_gid, bytes)
           else entity_gid(info.keyexpr).hex() if info.keyexpr else "")
    lines = [
        f"Node name: {info.node_name}",
        f"Node namespace: {info.namespace}",
        f"Topic type: {info.ros_type}",
        f"Topic type hash: {info.type_hash}",
        f"Endpoint type: {kind}",
        f"GID: {'.'.join(gid[i:i + 2] for i in range(0, len(gid), 2))}",
        *(_qos_lines(info) if info.qos is not None else []),
    ]
    return "\n".join(lines) + "\n\n"


def main_info(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
              err: TextIO | None = None) -> int:
    """``topic info TOPIC [-v]``."""
    out = out or sys.stdout
    err = err or sys.stderr
    parser = argparse.ArgumentParser(prog="posekit topic info")
    parser.add_argument("topic_name")
    parser.add_argument("-v", "--verbose", action="store_true",
                        help="print endpoint details (node, type hash, GID, QoS)")
    _add_transport_args(parser)
    ns = parser.parse_args(list(argv))
    with _session(ns, context) as session:
        topic = _resolve(session, ns.topic_name)
        sync_graph(session)
        types = topic_types(session, topic)
        if not types:
            err.write(f"Unknown topic '{topic}'\n")
            return 1
        pubs = _publishers_info(session, topic)
        subs = _subscriptions_info(session, topic)
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


def main_echo(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
              err: TextIO | None = None, timeout_s: float | None = None) -> int:
    """``topic echo TOPIC [TYPE] [--once] [--count N] [-l N] [-f]``."""
    out = out or sys.stdout
    err = err or sys.stderr
    parser = argparse.ArgumentParser(prog="posekit topic echo")
    parser.add_argument("topic_name")
    parser.add_argument("message_type", nargs="?", default=None,
                        help="type of the messages (default: learnt from the graph)")
    parser.add_argument("--once", action="store_true", help="print the first message and exit")
    parser.add_argument("--count", type=int, default=None,
                        help="exit after printing N messages (posekit addition)")
    parser.add_argument("-l", "--truncate-length", type=int, default=TRUNCATE_LENGTH,
                        help="truncate arrays, bytes and strings to this length (default 128)")
    parser.add_argument("-f", "--full-length", action="store_true",
                        help="do not truncate arrays, bytes and strings")
    _add_transport_args(parser)
    ns = parser.parse_args(list(argv))
    limit = 1 if ns.once else ns.count
    truncate = None if ns.full_length else ns.truncate_length
    with _session(ns, context) as session:
        topic = _resolve(session, ns.topic_name)
        type_name = ns.message_type or wait_for_topic_type(session, topic, err, timeout_s)
        if type_name is None:
            err.write(f"Could not determine the type for the passed topic '{topic}'\n")
            return 1
        try:
            msg_cls = message_class(type_name)
        except ValueError as exc:
            err.write(f"{exc}\n")
            return 1
        printed = 0

        def on_message(msg: Any) -> None:
            nonlocal printed
            if limit is not None and printed >= limit:
                return
            out.write(message_to_yaml(msg, truncate_length=truncate) + "---\n")
            out.flush()
            printed += 1

        session.node.create_subscription(msg_cls, topic, on_message,
                                         adapted_qos(session, topic, out))
        deadline = None if timeout_s is None else time.monotonic() + timeout_s
        while session.context.ok() and (limit is None or printed < limit):
            if deadline is not None and time.monotonic() > deadline:
                return 1 if printed == 0 else 0
            session.spin_for(0.1)
    return 0


def hz_report(deltas_ns: Sequence[int]) -> str:
    """``ros2 topic hz``'s two-line report for inter-arrival times (ns); needs >= 1 delta."""
    n = len(deltas_ns)
    mean = sum(deltas_ns) / n
    rate = 1.0 / mean if mean > 0 else 0.0
    std_dev = math.sqrt(sum((x - mean) ** 2 for x in deltas_ns) / n)
    return (
        f"average rate: {rate * 1e9:.3f}\n"
        f"\tmin: {min(deltas_ns) * 1e-9:.3f}s max: {max(deltas_ns) * 1e-9:.3f}s "
        f"std dev: {std_dev * 1e-9:.5f}s window: {n + 1}\n"
    )


def main_hz(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
            err: TextIO | None = None, timeout_s: float | None = None) -> int:
    """``topic hz TOPIC [--window N] [--count N]``: receive rate, reported once a second."""
    from collections import deque

    from posekit.cli._session import add_sim_time_args
    from posekit.runtime.qos import qos_profile_sensor_data

    out = out or sys.stdout
    err = err or sys.stderr
    parser = argparse.ArgumentParser(prog="posekit topic hz")
    parser.add_argument("topic_name")
    parser.add_argument("-w", "--window", type=int, default=10000,
                        help="window size, in # of messages, for calculating rate")
    parser.add_argument("--count", type=int, default=None,
                        help="exit after N reports (posekit addition)")
    _add_transport_args(parser)
    add_sim_time_args(parser)
    ns = parser.parse_args(list(argv))
    if ns.window < 1:
        err.write("--window must be at least 1\n")
        return 2
    with _session(ns, context) as session:
        topic = _resolve(session, ns.topic_name)
        type_name = wait_for_topic_type(session, topic, err, timeout_s)
        if type_name is None:
            err.write(f"Could not determine the type for the passed topic '{topic}'\n")
            return 1
        # Rates per simulated second while a simulation publishes /clock, as ros2 topic hz
        # measures with its node's ROS clock; the reports come once a wall second.
        stamp_ns = (session.node.get_clock().now_ns if session.follow_sim_time(ns.use_sim_time)
                    else time.monotonic_ns)
        deltas: deque[int] = deque(maxlen=ns.window)
        last_ns: list[int] = []
        printed_at = [-1]
        reports = [0]

        def on_message(_msg: Any) -> None:
            now = stamp_ns()
            if last_ns:
                deltas.append(now - last_ns[0])
                last_ns[0] = now
            else:
                last_ns.append(now)

        def report() -> None:
            if not deltas:
                return
            if printed_at[0] == last_ns[0]:
                out.write("no new messages\n")
            else:
                out.write(hz_report(list(deltas)))
                printed_at[0] = last_ns[0]
            out.flush()
            reports[0] += 1

        session.node.create_subscription(message_class(type_name), topic, on_message,
                                         qos_profile_sensor_data)
        from posekit.runtime.clock import Clock, ClockType

        session.node.create_timer(1.0, report, clock=Clock(clock_type=ClockType.STEADY_TIME))
        deadline = None if timeout_s is None else time.monotonic() + timeout_s
        while session.context.ok() and (ns.count is None or reports[0] < ns.count):
            if deadline is not None and time.monotonic() > deadline:
                break
            session.spin_for(0.1)
    return 0


def parse_values(text: str) -> Any:
    """VALUES as ``ros2 topic pub`` reads them: ``yaml.safe_load`` (PyYAML)."""
    try:
        import yaml  # type: ignore[import-untyped,unused-ignore]
    except ImportError:
        raise MessageFieldError(
            "posekit topic pub needs PyYAML to read VALUES (pip install pyyaml)"
        ) from None
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise MessageFieldError(f"the passed value needs to be valid YAML: {exc}") from None


def main_pub(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
             err: TextIO | None = None, sleep: Callable[[float], None] | None = None) -> int:
    """``topic pub TOPIC TYPE [VALUES] [-r R] [-1] [-t N] [-w N] [-p N] [--keep-alive S]``."""
    from posekit.cli._session import add_sim_time_args
    from posekit.runtime.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

    out = out or sys.stdout
    err = err or sys.stderr
    parser = argparse.ArgumentParser(prog="posekit topic pub")
    parser.add_argument("topic_name")
    parser.add_argument("message_type")
    parser.add_argument("values", nargs="?", default="{}")
    parser.add_argument("-r", "--rate", type=float, default=1.0,
                        help="publishing rate in Hz (default 1)")
    parser.add_argument("-p", "--print", dest="print_nth", type=int, default=1,
                        help="print every N-th published message (0: never)")
    group = parser.add_mutually_exclusive_group()
    group.add_argument("-1", "--once", action="store_true", help="publish one message and exit")
    group.add_argument("-t", "--times", type=int, default=0, help="publish N messages and exit")
    parser.add_argument("-w", "--wait-matching-subscriptions", type=int, default=None,
                        help="wait for N matching subscriptions first (default 1 with "
                             "--once/--times, else 0)")
    parser.add_argument("--keep-alive", type=float, default=0.1,
                        help="seconds to stay alive after the last message (default 0.1)")
    parser.add_argument("--qos-durability", choices=["volatile", "transient_local"],
                        default="volatile")
    parser.add_argument("--qos-reliability", choices=["reliable", "best_effort"],
                        default="reliable")
    parser.add_argument("--qos-depth", type=int, default=10)
    _add_transport_args(parser)
    add_sim_time_args(parser)
    ns = parser.parse_args(list(argv))
    times = 1 if ns.once else ns.times
    if not ns.rate > 0 or ns.rate == math.inf:  # NaN fails the first test
        err.write(f"rate must be a positive finite number of Hz, got {ns.rate}\n")
        return 2
    try:
        msg_cls = message_class(ns.message_type)
        values = parse_values(ns.values)
        try:
            msg = msg_cls()
        except TypeError:
            raise MessageFieldError(
                f"{ns.message_type}: posekit has no message class with defaults for this type "
                "(echo and hz decode any ROS 2 type; pub needs one of posekit.msgs)"
            ) from None
        set_message_fields(msg, values)
    except ValueError as exc:  # MessageFieldError, UnknownMessageTypeError
        err.write(f"Failed to populate field: {exc}\n" if isinstance(exc, MessageFieldError)
                  else f"{exc}\n")
        return 1
    wait_subs = ns.wait_matching_subscriptions
    if wait_subs is None:
        wait_subs = 1 if times else 0
    qos = QoSProfile(
        depth=max(1, ns.qos_depth),
        durability=(DurabilityPolicy.TRANSIENT_LOCAL if ns.qos_durability == "transient_local"
                    else DurabilityPolicy.VOLATILE),
        reliability=(ReliabilityPolicy.BEST_EFFORT if ns.qos_reliability == "best_effort"
                     else ReliabilityPolicy.RELIABLE),
    )
    with _session(ns, context) as session:
        if ns.use_sim_time or (ns.use_sim_time is None and _uses_now(values)):
            session.follow_sim_time(ns.use_sim_time)  # header: auto stamps sim time
        now_ns = session.node.get_clock().now_ns
        topic = _resolve(session, ns.topic_name)
        pub = session.node.create_publisher(msg_cls, topic, qos)
        waited = 0
        while pub.get_subscription_count() < wait_subs and session.context.ok():
            if waited % 10 == 0:
                out.write(f"Waiting for at least {wait_subs} matching subscription(s)...\n")
                out.flush()
            waited += 1
            session.spin_for(0.1)
        out.write("publisher: beginning loop\n")
        count = 0
        period = 1.0 / ns.rate
        next_at = time.monotonic()
        while session.context.ok():
            # header: auto / stamp: now are re-evaluated for every message, as ros2 does
            fresh = msg_cls()
            set_message_fields(fresh, values, now_ns=now_ns)
            pub.publish(fresh)
            count += 1
            if ns.print_nth and count % ns.print_nth == 0:
                out.write(f"publishing #{count}: {ros_repr(fresh)}\n\n")
                out.flush()
            if times and count >= times:
                break
            next_at += period
            session.spin_for(max(0.0, next_at - time.monotonic()))
        session.spin_for(max(0.0, ns.keep_alive))
    return 0


_VERBS: dict[str, tuple[Callable[..., int], str]] = {
    "list": (main_list, "Output a list of available topics"),
    "info": (main_info, "Print information about a topic"),
    "echo": (main_echo, "Output messages from a topic"),
    "hz": (main_hz, "Print the average receiving rate to screen"),
    "pub": (main_pub, "Publish a message to a topic"),
}


def main(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
         err: TextIO | None = None) -> int:
    """``posekit topic VERB ...``."""
    out = out or sys.stdout
    args = list(argv)
    if not args or args[0] not in _VERBS:
        lines = ["usage: posekit topic VERB ...", "", "verbs:"]
        lines += [f"  {name:<6}{text}" for name, (_, text) in _VERBS.items()]
        (out if not args or args[0] in ("-h", "--help") else (err or sys.stderr)).write(
            "\n".join(lines) + "\n"
        )
        return 0 if args and args[0] in ("-h", "--help") else 2
    function = _VERBS[args[0]][0]
    return function(args[1:], context=context, out=out, err=err)
