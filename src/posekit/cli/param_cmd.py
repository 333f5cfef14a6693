"""``posekit param list|get|set|delete|describe|dump|load``: ``ros2 param``'s verbs (Jazzy).

Arguments and output follow ros2cli's ros2param: ``get`` prints ``Double value is: 0.4``,
``set`` prints ``Set parameter successful`` (or ``Setting parameter failed: <reason>`` on
stderr), ``list`` prints ``/node:`` headers with indented names, ``dump`` the YAML of
``{node: {ros__parameters: ...}}``. Values for ``set`` are YAML (``1.0`` is a double,
``1`` an integer, ``"[1, 2]"`` an integer array), exactly as ros2 reads them.

Each verb runs a hidden node (``_posekit_cli_<pid>``) on the tool transport (Zenoh by
default) and talks to the target node's parameter services, so it works with posekit
processes and with real ROS 2 nodes on rmw_zenoh alike. Errors are one line on stderr
(``Node not found``, ``Parameter not set``) with exit code 1, never a traceback.
"""

from __future__ import annotations

import argparse
import re
import sys
from collections.abc import Callable, Sequence
from typing import Any, TextIO

from posekit.cli._node_verbs import (
    SERVICE_WAIT_S,
    CliError,
    absolute_node_name,
    call_node_service,
    run_in_session,
    verb_entry,
    visible_nodes,
    wait_for_node_or_fail,
)

__all__ = ["main", "parameter_type_string"]

def parameter_type_string(parameter_type: int) -> str:
    """ros2param's name of a ParameterType constant (``double``, ``integer array``...)."""
    names = {
        0: "not set", 1: "boolean", 2: "integer", 3: "double", 4: "string", 5: "byte array",
        6: "boolean array", 7: "integer array", 8: "double array", 9: "string array",
    }
    return names[int(parameter_type)]


def _parser(prog: str) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog=f"posekit param {prog}")
    parser.add_argument("--transport", default=None,
                        help="posekit transport (default: $POSEKIT_TRANSPORT or zenoh)")
    parser.add_argument("--zenoh", action="store_true", help="same as --transport zenoh")
    return parser


def _node_args(parser: argparse.ArgumentParser, *, optional: bool = False) -> None:
    parser.add_argument("node_name", nargs="?" if optional else None,
                        help="Name of the ROS node")
    parser.add_argument("--include-hidden-nodes", action="store_true",
                        help="Consider hidden nodes as well")


def _timeout_arg(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--timeout", metavar="N", type=int, default=1,
                        help="Wait for N seconds until node becomes available (default 1 sec)")


# -- verbs ------------------------------------------------------------------------------------
def _list(ns: argparse.Namespace, session: Any, out: TextIO, err: TextIO) -> None:
    from posekit.msgs.rcl_interfaces import DescribeParameters, ListParameters

    if ns.node_name:
        nodes = [absolute_node_name(ns.node_name)]
        wait_for_node_or_fail(session, nodes[0], ns.include_hidden_nodes, SERVICE_WAIT_S)
    else:
        # as ros2 param list: only the nodes that serve list_parameters (not the tools, say)
        served = {name for name, _types in session.node.get_service_names_and_types()}
        nodes = [n for n in visible_nodes(session, ns.include_hidden_nodes)
                 if f"{n}/list_parameters" in served]
    pattern = re.compile(ns.filter[0]) if ns.filter else None
    for node in nodes:
        try:
            result = call_node_service(session, node, "list_parameters", ListParameters,
                           ListParameters.Request(prefixes=list(ns.param_prefixes))).result
        except CliError as exc:
            out.write(f"{exc}\n")
            continue
        names = sorted(result.names)
        if pattern is not None:
            names = [n for n in names if pattern.match(n)]
        if not ns.node_name and names:
            out.write(f"{node}:\n")
        types: dict[str, str] = {}
        if ns.param_type:
            described = call_node_service(session, node, "describe_parameters", DescribeParameters,
                              DescribeParameters.Request(names=names))
            types = {d.name: parameter_type_string(d.type) for d in described.descriptors}
        for name in names:
            out.write(f"  {name} (type: {types[name]})\n" if ns.param_type else f"  {name}\n")


_GET_LABELS = {
    1: ("Boolean value is:", "bool_value"),
    2: ("Integer value is:", "integer_value"),
    3: ("Double value is:", "double_value"),
    4: ("String value is:", "string_value"),
    5: ("Byte values are:", "byte_array_value"),
    6: ("Boolean values are:", "bool_array_value"),
    7: ("Integer values are:", "integer_array_value"),
    8: ("Double values are:", "double_array_value"),
    9: ("String values are:", "string_array_value"),
}


def _get(ns: argparse.Namespace, session: Any, out: TextIO, err: TextIO) -> None:
    from posekit.msgs.rcl_interfaces import GetParameters
    from posekit.runtime.parameters import parameter_value_to_python

    node = absolute_node_name(ns.node_name)
    wait_for_node_or_fail(session, node, ns.include_hidden_nodes, ns.timeout)
    response = call_node_service(session, node, "get_parameters", GetParameters,
                     GetParameters.Request(names=[ns.parameter_name]))
    if not response.values:
        raise CliError("Parameter not set")
    value_msg = response.values[0]
    if value_msg.type == 0:
        out.write("Parameter not set.\n")
        return
    if value_msg.type not in _GET_LABELS:
        raise CliError(f"Unknown parameter type '{value_msg.type}'")
    label = _GET_LABELS[value_msg.type][0]
    value = parameter_value_to_python(value_msg)
    out.write(f"{value}\n" if ns.hide_type else f"{label} {value}\n")


def _print_result(result: Any, ok: str, failed: str, out: TextIO, err: TextIO) -> None:
    if result.successful:
        out.write(ok + (f": {result.reason}" if result.reason else "") + "\n")
    else:
        err.write(failed + (f": {result.reason}" if result.reason else "") + "\n")


def _set(ns: argparse.Namespace, session: Any, out: TextIO, err: TextIO) -> None:
    from posekit.msgs.rcl_interfaces import Parameter as ParameterMsg
    from posekit.msgs.rcl_interfaces import SetParameters
    from posekit.runtime.parameters import get_parameter_value

    node = absolute_node_name(ns.node_name)
    wait_for_node_or_fail(session, node, ns.include_hidden_nodes, ns.timeout)
    parameter = ParameterMsg(name=ns.parameter_name, value=get_parameter_value(ns.value))
    response = call_node_service(session, node, "set_parameters", SetParameters,
                     SetParameters.Request(parameters=[parameter]))
    _print_result(response.results[0], "Set parameter successful", "Setting parameter failed",
                  out, err)


def _delete(ns: argparse.Namespace, session: Any, out: TextIO, err: TextIO) -> None:
    from posekit.msgs.rcl_interfaces import Parameter as ParameterMsg
    from posekit.msgs.rcl_interfaces import SetParameters

    node = absolute_node_name(ns.node_name)
    wait_for_node_or_fail(session, node, ns.include_hidden_nodes, ns.timeout)
    response = call_node_service(session, node, "set_parameters", SetParameters,
                     SetParameters.Request(parameters=[ParameterMsg(name=ns.parameter_name)]))
    _print_result(response.results[0], "Deleted parameter successfully",
                  "Deleting parameter failed", out, err)


def _describe(ns: argparse.Namespace, session: Any, out: TextIO, err: TextIO) -> None:
    from posekit.msgs.rcl_interfaces import DescribeParameters

    node = absolute_node_name(ns.node_name)
    wait_for_node_or_fail(session, node, ns.include_hidden_nodes, ns.timeout)
    response = call_node_service(session, node, "describe_parameters", DescribeParameters,
                     DescribeParameters.Request(names=list(ns.parameter_names)))
    for d in response.descriptors:
        lines = [f"Parameter name: {d.name}", f"  Type: {parameter_type_string(d.type)}"]
        if d.description:
            lines.append(f"  Description: {d.description}")
        lines.append("  Constraints:")
        if d.read_only:
            lines.append("    Read only: true")
        ranges = list(d.floating_point_range) + list(d.integer_range)
        if ranges:
            lines.append(f"    Min value: {ranges[0].from_value}")
            lines.append(f"    Max value: {ranges[0].to_value}")
            if ranges[0].step:
                lines.append(f"    Step: {ranges[0].step}")
        if d.additional_constraints:
            lines.append(f"    Additional constraints: {d.additional_constraints}")
        out.write("\n".join(lines) + "\n")


def _dump(ns: argparse.Namespace, session: Any, out: TextIO, err: TextIO) -> None:
    import yaml

    from posekit.msgs.rcl_interfaces import GetParameters, ListParameters
    from posekit.runtime.parameters import PARAMETER_SEPARATOR_STRING, parameter_value_to_python

    node = absolute_node_name(ns.node_name)
    wait_for_node_or_fail(session, node, ns.include_hidden_nodes, ns.timeout)
    names = sorted(call_node_service(session, node, "list_parameters", ListParameters,
                         ListParameters.Request()).result.names)
    values = call_node_service(session, node, "get_parameters", GetParameters,
                   GetParameters.Request(names=names)).values
    params: dict[str, Any] = {}
    for name, value in zip(names, values, strict=False):
        target = params
        *parents, leaf = name.split(PARAMETER_SEPARATOR_STRING)
        for part in parents:
            target = target.setdefault(part, {})
        target[leaf] = parameter_value_to_python(value)
    out.write(yaml.dump({node: {"ros__parameters": params}}, default_flow_style=False) + "\n")


def _load(ns: argparse.Namespace, session: Any, out: TextIO, err: TextIO) -> None:
    from posekit.msgs.rcl_interfaces import SetParameters
    from posekit.runtime.parameters import parameter_dict_from_yaml_file

    node = absolute_node_name(ns.node_name)
    wait_for_node_or_fail(session, node, ns.include_hidden_nodes, ns.timeout)
    try:
        parameters = list(parameter_dict_from_yaml_file(
            ns.parameter_file, not ns.no_use_wildcard).values())
    except OSError as exc:
        raise CliError(f"cannot read {ns.parameter_file}: {exc.strerror or exc}") from None
    except Exception as exc:  # RuntimeError for a non-parameter file, yaml errors
        raise CliError(f"{ns.parameter_file}: {exc}".replace("\n", " ")) from None
    response = call_node_service(session, node, "set_parameters", SetParameters,
                     SetParameters.Request(parameters=parameters))
    for parameter, result in zip(parameters, response.results, strict=False):
        _print_result(result, f"Set parameter {parameter.name} successful",
                      f"Set parameter {parameter.name} failed", out, err)


def _build(verb: str) -> tuple[argparse.ArgumentParser, Callable[..., None]]:
    parser = _parser(verb)
    if verb == "list":
        _node_args(parser, optional=True)
        parser.add_argument("--filter", nargs=1,
                            help="Only parameters matching the regex expression will be showed.")
        parser.add_argument("--param-prefixes", nargs="+", default=[],
                            help="Only list parameters with the provided prefixes")
        parser.add_argument("--param-type", action="store_true",
                            help="Print parameter types with parameter names")
        return parser, _list
    _node_args(parser)
    if verb in ("get", "set", "delete"):
        parser.add_argument("parameter_name", help="Name of the parameter")
    if verb == "get":
        parser.add_argument("--hide-type", action="store_true", help="Hide the type information")
    if verb == "set":
        parser.add_argument("value", help="Value of the parameter")
    if verb == "describe":
        parser.add_argument("parameter_names", nargs="+", help="Names of the parameters")
    if verb == "load":
        parser.add_argument("parameter_file", help="Parameter file")
        parser.add_argument("--no-use-wildcard", action="store_true",
                            help="Do not load parameters in the '/**' namespace into the node")
    _timeout_arg(parser)
    handler = {"get": _get, "set": _set, "delete": _delete, "describe": _describe,
               "dump": _dump, "load": _load}[verb]
    return parser, handler


_VERBS = {
    "list": "Output a list of available parameters",
    "get": "Get parameter",
    "set": "Set parameter",
    "delete": "Delete parameter",
    "describe": "Show descriptive information about declared parameters",
    "dump": "Show all of the parameters of a node in a YAML file format",
    "load": "Load parameter file for a node",
}


def run(verb: str, argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
        err: TextIO | None = None) -> int:
    """Run ``posekit param VERB ARGV``; returns the exit code."""
    parser, handler = _build(verb)
    return run_in_session(f"posekit param {verb}", parser.parse_args(list(argv)), handler,
                          context, out or sys.stdout, err or sys.stderr)


def main(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
         err: TextIO | None = None) -> int:
    """``posekit param VERB ...``."""
    args = list(argv)
    if not args or args[0] not in _VERBS:
        lines = ["usage: posekit param VERB ...", "", "verbs:"]
        lines += [f"  {name:<9}{text}" for name, text in _VERBS.items()]
        ok = bool(args) and args[0] in ("-h", "--help")
        (out or sys.stdout if ok or not args else err or sys.stderr).write("\n".join(lines) + "\n")
        return 0 if ok or not args else 2
    return run(args[0], args[1:], context=context, out=out, err=err)


def _verb(name: str) -> Callable[..., int]:
    return verb_entry(run, "param", name, _VERBS[name])


main_list = _verb("list")
main_get = _verb("get")
main_set = _verb("set")
main_delete = _verb("delete")
main_describe = _verb("describe")
main_dump = _verb("dump")
main_load = _verb("load")
