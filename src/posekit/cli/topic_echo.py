r"""``posekit topic echo``: ``ros2 topic echo``'s options and output (Jazzy).

Each message prints as block YAML followed by ``---`` (``yaml_io.message_to_yaml``);
``--csv`` prints one comma-separated line, ``--flow-style`` one flow-style YAML line,
``--raw`` the CDR bytes (``b'\x00\x01...'``). ``--field a.b`` prints only that field (a
scalar prints as Python prints it), ``--filter EXPR`` only messages for which the Python
expression over ``m`` (the message, or the selected field) is true. The subscription QoS is
the ``--qos-profile`` (default ``sensor_data``) made reliable / transient-local when every
publisher offers it, unless a ``--qos-*`` option says otherwise. ``--timeout N`` ends after N
seconds (exit 0, as ros2); ``--count N`` after N messages (posekit's addition).
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable, Sequence
from typing import Any, TextIO

from posekit.cli._graph import (
    adapted_qos,
    add_transport_args,
    resolve_topic,
    session_for,
    wait_for_topic_type,
)
from posekit.cli._qos_args import add_qos_args, qos_from_args, qos_overridden
from posekit.cli.errors import CliError
from posekit.msgs.yaml_io import (
    TRUNCATE_LENGTH,
    MessageFieldError,
    get_field,
    message_class,
    message_to_csv,
    message_to_yaml,
)

__all__ = ["compile_filter", "main_echo", "non_negative_int", "positive_float", "positive_int"]


def _int_at_least(minimum: int, what: str) -> Callable[[str], int]:
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"invalid int value: '{text}'") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"value must be {what}: {value}")
        return value

    return parse


#: argparse type: an int >= 0 (ros2cli's ``unsigned_int``).
non_negative_int = _int_at_least(0, "non-negative")
#: argparse type: an int > 0 (ros2cli's ``positive_int``).
positive_int = _int_at_least(1, "positive")


def positive_float(text: str) -> float:
    """argparse type: a finite float > 0 (ros2cli's ``positive_float``)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"invalid float value: '{text}'") from None
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"value must be a positive finite number: {text}")
    return value


def compile_filter(expr: str | None) -> Callable[[Any], bool] | None:
    """A predicate evaluating the Python expression ``expr`` with ``m`` bound to the message.

    A syntax error is a :class:`CliError`; an expression failing on a message is one too.
    """
    if not expr:
        return None
    try:
        code = compile(expr, "<filter>", "eval")
    except SyntaxError as exc:
        raise CliError(f"invalid --filter expression {expr!r}: {exc.msg}", 2) from None

    def predicate(m: Any) -> bool:
        try:
            return bool(eval(code, {"__builtins__": __builtins__}, {"m": m}))
        except Exception as exc:  # the user's expression, not posekit
            raise CliError(f"--filter expression {expr!r} failed: "
                           f"{type(exc).__name__}: {exc}") from None

    return predicate


def build_parser() -> argparse.ArgumentParser:
    """``ros2 topic echo``'s options (Jazzy) plus posekit's ``--count`` and transport."""
    parser = argparse.ArgumentParser(prog="posekit topic echo",
                                     description="Output messages from a topic")
    parser.add_argument("topic_name",
                        help="Name of the ROS topic to listen to (e.g. '/chatter')")
    parser.add_argument("message_type", nargs="?", default=None,
                        help="Type of the ROS message (e.g. 'std_msgs/msg/String'; default: "
                             "learnt from the graph)")
    add_qos_args(parser, "subscribe", "sensor_data")
    parser.add_argument("--csv", action="store_true",
                        help="Output all recursive fields separated by commas (e.g. for "
                             "plotting)")
    parser.add_argument("--field", type=str, default=None,
                        help="Echo a selected field of a message. Use '.' to select "
                             "sub-fields (e.g. --field pose.pose.position)")
    parser.add_argument("--full-length", "-f", action="store_true",
                        help="Output all elements for arrays, bytes, and string with a length "
                             "> '--truncate-length'")
    parser.add_argument("--truncate-length", "-l", type=non_negative_int,
                        default=TRUNCATE_LENGTH,
                        help="The length to truncate arrays, bytes, and string to "
                             f"(default: {TRUNCATE_LENGTH})")
    parser.add_argument("--no-arr", action="store_true",
                        help="Don't print array fields of messages")
    parser.add_argument("--no-str", action="store_true",
                        help="Don't print string fields of messages")
    parser.add_argument("--flow-style", action="store_true",
                        help="Print collections in the flow style (not available with csv "
                             "format)")
    parser.add_argument("--no-lost-messages", action="store_true",
                        help="Don't report when a message is lost (posekit's transports "
                             "report no lost messages, as rmw_zenoh)")
    parser.add_argument("--raw", action="store_true",
                        help="Echo the raw binary representation (CDR bytes)")
    parser.add_argument("--filter", dest="filter_expr",
                        help="Python expression to filter messages that are printed. "
                             "Expression can use Python builtins as well as m (the message).")
    parser.add_argument("--once", action="store_true",
                        help="Print the first message received and then exit.")
    parser.add_argument("--timeout", metavar="N", type=positive_float, default=None,
                        help="Set a timeout in seconds for waiting")
    parser.add_argument("--include-message-info", "-i", action="store_true",
                        help="Shows the associated message info.")
    parser.add_argument("--count", type=non_negative_int, default=None,
                        help="exit after printing N messages (posekit addition)")
    add_transport_args(parser)
    return parser


def main_echo(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
              err: TextIO | None = None, timeout_s: float | None = None) -> int:
    """Run ``topic echo TOPIC [TYPE] [options]``.

    ``timeout_s`` (tests) bounds the wait and exits 1 if nothing was printed by then.
    """
    out = out or sys.stdout
    err = err or sys.stderr
    ns = build_parser().parse_args(list(argv))
    field = ns.field
    if field is not None and not [p for p in field.split(".") if p]:
        raise CliError(f"Invalid field value '{field}'", 2)
    if ns.csv and ns.flow_style:
        raise CliError("--flow-style is not available with --csv", 2)
    accept = compile_filter(ns.filter_expr)
    limit = 1 if ns.once else ns.count
    truncate = None if ns.full_length else ns.truncate_length
    wait_s = ns.timeout if timeout_s is None else timeout_s
    with session_for(ns, context) as session:
        topic = resolve_topic(session, ns.topic_name)
        msg_cls = _echo_class(session, ns.message_type, topic, err, wait_s, timeout_s)
        if msg_cls is None:  # --timeout and no publisher: ros2 ends quietly
            return 0
        if qos_overridden(ns):
            qos = qos_from_args(ns)
        else:
            qos = adapted_qos(session, topic, out, default=qos_from_args(ns))
        printed = 0
        failure: list[BaseException] = []

        def on_message(msg: Any, info: Any = None) -> None:
            nonlocal printed
            if failure or (limit is not None and printed >= limit):
                return
            try:
                text = _render(msg, ns, field, truncate, accept, info)
            except (CliError, MessageFieldError) as exc:
                failure.append(exc)
                return
            if text is None:
                return
            out.write(text)
            out.flush()
            printed += 1

        def on_message_with_info(msg: Any, info: Any) -> None:
            on_message(msg, info)

        session.node.create_subscription(
            msg_cls, topic, on_message_with_info if ns.include_message_info else on_message,
            qos)
        deadline = None if wait_s is None else time.monotonic() + wait_s
        while session.context.ok() and (limit is None or printed < limit):
            if failure:
                raise failure[0]
            if deadline is not None and time.monotonic() > deadline:
                return 1 if printed == 0 and timeout_s is not None else 0
            session.spin_for(0.1)
    return 0


def _echo_class(session: Any, type_name: str | None, topic: str, err: TextIO,
                wait_s: float | None, timeout_s: float | None) -> type | None:
    """The message class to echo ``topic`` with: the given type, else the publishers' type.

    None when ``--timeout`` ran out before a publisher showed its type (``timeout_s`` unset);
    raises CliError for an invalid type name, or when the type stays unknown otherwise.
    """
    if type_name is not None:
        try:
            return message_class(type_name)
        except ValueError:
            raise CliError(f"The passed message type '{type_name}' is invalid") from None
    found = wait_for_topic_type(session, topic, err, wait_s)
    if found is not None:
        return message_class(found)
    if timeout_s is None:
        return None
    raise CliError(f"Could not determine the type for the passed topic '{topic}'")


def _render(msg: Any, ns: argparse.Namespace, field: str | None, truncate: int | None,
            accept: Callable[[Any], bool] | None, info: Any = None) -> str | None:
    """What ros2 prints for one message, or None when the filter rejects it.

    With message info: before a YAML message ``yaml.dump(info)`` (keys sorted, as PyYAML
    does) and ``---``; before a CSV line the info values in rclpy's order; before a raw or
    scalar one, rclpy's ``---Got new message, message info:---`` block.
    """
    value = get_field(msg, field) if field is not None else msg
    if accept is not None and not accept(value):
        return None
    raw = ns.raw and field is None
    if raw or not hasattr(value, "__dataclass_fields__"):  # bytes, or a field not a message
        if raw:
            from posekit.msgs.cdr import to_cdr

            value = to_cdr(msg)
        head = ("---Got new message, message info:---\n"
                f"{dict(info)}\n---Message data:---\n") if info is not None else ""
        return f"{head}{value}\n---\n"
    if ns.csv:
        line = message_to_csv(value, truncate_length=truncate, no_arr=ns.no_arr,
                              no_str=ns.no_str)
        if info is not None:
            line = ",".join(str(v) for v in info.values()) + "," + line
        return line + "\n"
    head = ""
    if info is not None:
        import yaml  # type: ignore[import-untyped,unused-ignore]

        head = yaml.dump(dict(info)) + "---\n"
    return head + message_to_yaml(value, truncate_length=truncate, no_arr=ns.no_arr,
                                  no_str=ns.no_str, flow_style=ns.flow_style) + "---\n"
