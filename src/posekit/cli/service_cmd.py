"""``posekit service list|type|find|call``: ``ros2 service``'s verbs (Jazzy) and output.

* ``list [-t] [-c] [--include-hidden-services]``: one service per line, ``-t`` adds
  ``[type]``.
* ``type SERVICE``: the service's type (exit code 1 if it is not on the graph).
* ``find TYPE [-c]``: the services of a type.
* ``call SERVICE TYPE [VALUES] [-r RATE]``: VALUES is YAML (``"{data: true}"``); prints
  ``requester: making request: std_srvs.srv.SetBool_Request(data=True)`` and
  ``response:`` with the response's repr, as ros2 does. ``--timeout`` (posekit's addition)
  bounds the wait for the service and the response (default: wait forever, like ros2).

The tool's hidden node runs on the tool transport (Zenoh by default), so services of other
posekit processes and of real ROS 2 nodes on rmw_zenoh are listed and callable.
"""

from __future__ import annotations

import argparse
import functools
import sys
import time
from collections.abc import Callable, Sequence
from typing import Any, TextIO

__all__ = ["main", "main_call", "main_echo", "main_find", "main_list", "main_type"]


_Verb = Callable[..., int]


def _one_line_errors(verb: str) -> Callable[[_Verb], _Verb]:
    """Report an unexpected failure (no transport, ...) as one line, exit code 1."""

    def decorate(fn: _Verb) -> _Verb:
        @functools.wraps(fn)
        def wrapper(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
                    err: TextIO | None = None) -> int:
            try:
                return fn(argv, context=context, out=out, err=err)
            except Exception as exc:
                from posekit.cli.errors import report

                return report(exc, f"posekit service {verb}", err)

        return wrapper

    return decorate


def _parser(verb: str) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog=f"posekit service {verb}")
    parser.add_argument("--transport", default=None,
                        help="posekit transport (default: $POSEKIT_TRANSPORT or zenoh)")
    parser.add_argument("--zenoh", action="store_true", help="same as --transport zenoh")
    return parser


def _session(ns: argparse.Namespace, context: Any) -> Any:
    from posekit.cli._session import ToolSession
    from posekit.cli.topic_cmd import cli_node_name

    return ToolSession(cli_node_name(), context=context,
                       transport="zenoh" if ns.zenoh else ns.transport,
                       start_parameter_services=False)


def _services(session: Any, include_hidden: bool) -> list[tuple[str, list[str]]]:
    from posekit.cli.topic_cmd import is_hidden_name, sync_graph

    sync_graph(session, 2.0)
    found: list[tuple[str, list[str]]] = session.node.get_service_names_and_types()
    return [(n, t) for n, t in found if include_hidden or not is_hidden_name(n)]


@_one_line_errors("list")
def main_list(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
              err: TextIO | None = None) -> int:
    """``service list [-t] [-c] [--include-hidden-services]``."""
    out = out or sys.stdout
    parser = _parser("list")
    parser.add_argument("-t", "--show-types", action="store_true",
                        help="Additionally show the service type")
    parser.add_argument("-c", "--count-services", action="store_true",
                        help="Only display the number of services discovered")
    parser.add_argument("--include-hidden-services", action="store_true",
                        help="Consider hidden services as well")
    ns = parser.parse_args(list(argv))
    with _session(ns, context) as session:
        services = _services(session, ns.include_hidden_services)
    if ns.count_services:
        out.write(f"{len(services)}\n")
        return 0
    for name, types in services:
        out.write(f"{name} [{', '.join(types)}]\n" if ns.show_types else f"{name}\n")
    out.flush()
    return 0


@_one_line_errors("type")
def main_type(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
              err: TextIO | None = None) -> int:
    """``service type SERVICE``."""
    out = out or sys.stdout
    parser = _parser("type")
    parser.add_argument("service_name", help="Name of the ROS service to get type")
    parser.add_argument("--include-hidden-services", action="store_true",
                        help="Consider hidden services as well")
    ns = parser.parse_args(list(argv))
    with _session(ns, context) as session:
        services = _services(session, ns.include_hidden_services)
    for name, types in services:
        if name == ns.service_name:
            out.write("".join(f"{t}\n" for t in types))
            return 0
    return 1


@_one_line_errors("find")
def main_find(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
              err: TextIO | None = None) -> int:
    """``service find TYPE [-c] [--include-hidden-services]``."""
    out = out or sys.stdout
    parser = _parser("find")
    parser.add_argument("service_type", help="Name of the ROS service type to filter for")
    parser.add_argument("-c", "--count-services", action="store_true",
                        help="Only display the number of services discovered")
    parser.add_argument("--include-hidden-services", action="store_true",
                        help="Consider hidden services as well")
    ns = parser.parse_args(list(argv))
    with _session(ns, context) as session:
        matches = [n for n, t in _services(session, ns.include_hidden_services)
                   if ns.service_type in t]
    out.write(f"{len(matches)}\n" if ns.count_services else "".join(f"{n}\n" for n in matches))
    return 0


@_one_line_errors("call")
def main_call(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
              err: TextIO | None = None) -> int:
    """``service call SERVICE TYPE [VALUES] [-r RATE] [--timeout S]``."""
    from posekit.cli.topic_cmd import MessageFieldError, parse_values, ros_repr, set_message_fields
    from posekit.msgs.errors import UnknownMessageTypeError
    from posekit.msgs.registry import get_service_class

    out = out or sys.stdout
    err = err or sys.stderr
    parser = _parser("call")
    parser.add_argument("service_name", help="Name of the ROS service to call to")
    parser.add_argument("service_type", help="Type of the ROS service (e.g. 'std_srvs/srv/Empty')")
    parser.add_argument("values", nargs="?", default="{}",
                        help="Values to fill the service request with in YAML format")
    parser.add_argument("-r", "--rate", metavar="N", type=float,
                        help="Repeat the call at a specific rate in Hz")
    parser.add_argument("--timeout", type=float, default=None,
                        help="give up after this many seconds without service or response")
    ns = parser.parse_args(list(argv))
    if ns.rate is not None and ns.rate <= 0:
        err.write("rate must be greater than zero\n")
        return 1
    try:
        srv_type = get_service_class(ns.service_type)
    except UnknownMessageTypeError:
        err.write("The passed service type is invalid\n")
        return 1
    try:
        values = parse_values(ns.values)
        request = srv_type.Request()
        set_message_fields(request, values)
    except MessageFieldError as exc:
        err.write(f"Failed to populate field: {exc}\n")
        return 1
    period = 1.0 / ns.rate if ns.rate else None
    with _session(ns, context) as session:
        client = session.node.create_client(srv_type, ns.service_name)
        if not client.service_is_ready():
            out.write("waiting for service to become available...\n")
            out.flush()
            if not client.wait_for_service(timeout_sec=ns.timeout):
                err.write(f"service '{client.service_name}' did not become available "
                          f"within {ns.timeout:g} s\n")
                return 1
        while session.context.ok():
            out.write(f"requester: making request: {ros_repr(request)}\n\n")
            out.flush()
            last_call = time.monotonic()
            future = client.call_async(request)
            session.executor.spin_until_future_complete(future, timeout_sec=ns.timeout)
            if not future.done():
                err.write(f"no response from '{client.service_name}' within {ns.timeout:g} s\n")
                return 1
            out.write(f"response:\n{ros_repr(future.result())}\n\n")
            out.flush()
            if period is None:
                break
            session.spin_for(max(0.0, last_call + period - time.monotonic()))
    return 0


_VERBS = {
    "list": (main_list, "Output a list of available services"),
    "type": (main_type, "Output a service's type"),
    "find": (main_find, "Output a list of available services of a given type"),
    "call": (main_call, "Call a service"),
}


def main(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
         err: TextIO | None = None) -> int:
    """``posekit service VERB ...``."""
    args = list(argv)
    if not args or args[0] not in _VERBS:
        lines = ["usage: posekit service VERB ...", "", "verbs:"]
        lines += [f"  {name:<6}{text}" for name, (_, text) in _VERBS.items()]
        ok = bool(args) and args[0] in ("-h", "--help")
        (out or sys.stdout if ok or not args else err or sys.stderr).write("\n".join(lines) + "\n")
        return 0 if ok or not args else 2
    function = _VERBS[args[0]][0]
    return function(args[1:], context=context, out=out, err=err)


#: ``service_msgs/msg/ServiceEventInfo``'s event types by number, as ros2 service echo
#: prints them.
_EVENT_NAMES = {0: "REQUEST_SENT", 1: "REQUEST_RECEIVED", 2: "RESPONSE_SENT",
                3: "RESPONSE_RECEIVED"}


@_one_line_errors("echo")
def main_echo(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
              err: TextIO | None = None) -> int:
    """``service echo SERVICE [TYPE] [--csv] [-f] [-l N] [--no-arr] [--no-str] [--flow-style]``.

    Prints the service's introspection events (``<service>/_service_event``) as ros2 does:
    block YAML with the event type by name, then ``---`` (``--csv``: one line each). Until
    Ctrl-C, or posekit's ``--count N`` events / ``--timeout S`` seconds.
    """
    from posekit.cli.errors import CliError
    from posekit.cli.topic_echo import non_negative_int, positive_float, positive_int
    from posekit.msgs.yaml_io import (
        TRUNCATE_LENGTH,
        message_class,
        message_to_csv,
        message_to_ordered,
        ordered_to_yaml,
    )
    from posekit.runtime.qos import qos_profile_services_default
    from posekit.runtime.services import SERVICE_EVENT_SUFFIX

    out = out or sys.stdout
    parser = _parser("echo")
    parser.add_argument("service_name", help="Name of the ROS service to echo")
    parser.add_argument("service_type", nargs="?", help="Type of the ROS service")
    parser.add_argument("--csv", action="store_true", help="Output all fields comma-separated")
    parser.add_argument("--full-length", "-f", action="store_true",
                        help="Output all elements of arrays, bytes and strings")
    parser.add_argument("--truncate-length", "-l", type=non_negative_int,
                        default=TRUNCATE_LENGTH, help="The length to truncate them to")
    parser.add_argument("--no-arr", action="store_true", help="Don't print array fields")
    parser.add_argument("--no-str", action="store_true", help="Don't print string fields")
    parser.add_argument("--flow-style", action="store_true", help="Print collections in flow style")
    parser.add_argument("--count", type=positive_int, default=None,
                        help="exit after N events (posekit's)")
    parser.add_argument("--timeout", type=positive_float, default=None,
                        help="exit after S seconds (posekit's)")
    ns = parser.parse_args(list(argv))
    truncate = None if ns.full_length else ns.truncate_length
    with _session(ns, context) as session:
        srv_type = ns.service_type
        if srv_type is None:
            types = dict(_services(session, True)).get(ns.service_name)
            if not types:
                raise CliError("Could not load the type for the passed service")
            srv_type = types[0]
        try:
            event_cls = message_class(f"{srv_type}_Event")
        except ValueError:
            raise CliError(f"The service type '{srv_type}' is invalid") from None
        topic = ns.service_name + SERVICE_EVENT_SUFFIX
        printed = 0

        def on_event(event: Any) -> None:
            nonlocal printed
            if ns.count is not None and printed >= ns.count:
                return
            if ns.csv:
                text = message_to_csv(event, truncate_length=truncate, no_arr=ns.no_arr,
                                      no_str=ns.no_str) + "\n"
            else:
                data = message_to_ordered(event, truncate, no_arr=ns.no_arr, no_str=ns.no_str)
                info = data.get("info", {})
                if "event_type" in info:
                    info["event_type"] = _EVENT_NAMES.get(info["event_type"], info["event_type"])
                text = ordered_to_yaml(data, flow_style=ns.flow_style) + "---\n"
            out.write(text)
            out.flush()
            printed += 1

        sub = session.node.create_subscription(event_cls, topic, on_event,
                                               qos_profile_services_default)
        warned = False
        deadline = None if ns.timeout is None else time.monotonic() + ns.timeout
        while session.context.ok() and (ns.count is None or printed < ns.count):
            if not warned and sub.get_publisher_count() < 1:
                out.write(f"No publishers on topic '{topic}'; is service introspection on the "
                          "client or server enabled?\n")
                out.flush()
                warned = True
            if deadline is not None and time.monotonic() > deadline:
                break
            session.spin_for(0.1)
    return 0
