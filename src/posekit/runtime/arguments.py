"""ROS command-line arguments as rcl parses them (``--ros-args ... --``).

``rclpy.init()`` (``args=None``: ``sys.argv``) and ``Node(cli_args=...)`` read these flags
between ``--ros-args`` and ``--`` (or the end; a later ``--ros-args`` opens another section):

=====================================  ====================================================
flag                                   meaning
=====================================  ====================================================
``-p/--param [node:]name:=value``      parameter override; ``value`` is a YAML value typed
                                       as rcl types it (see :func:`parse_parameter_value`);
                                       ``node`` is a plain name (root namespace only)
``--params-file FILE``                 ROS 2 parameter YAML (``/**:``, ``node:``,
                                       ``/ns/node:``, wildcards, ``ros__parameters``)
``-r/--remap [node:]from:=to``         topic and service remapping (``rostopic://``
                                       / ``rosservice://`` for one kind); ``__node:=`` /
                                       ``__name:=`` rename the node, ``__ns:=`` moves it
``--log-level LEVEL``                  default logger level; ``name:=LEVEL`` one logger
``-e/--enclave NAME``                  accepted (posekit has no security enclaves)
``--log-config-file``, ``--enable-``/  accepted and ignored (``stdout-logs``,
``--disable-`` ...                     ``rosout-logs``, ``external-lib-logs``)
=====================================  ====================================================

Everything outside the sections is left to the program (:func:`remove_ros_args` returns it).
A flag missing its value, an assignment without ``:=``, an unreadable parameter file or a
bad level raises :class:`RCLError`; an unknown flag inside a section raises
:class:`UnknownROSArgsError` listing every unknown argument (rclpy's two errors).

Parameter scalars follow rcl's YAML rules, not YAML 1.1's: ``true``/``True``/``TRUE``,
``yes``/``Yes``/``YES``, ``on``/``On``/``ON`` and ``y``/``Y`` (and the false spellings) are
booleans; integers as C's ``strtoll`` with base 0 (so ``0x10`` is 16 and ``010`` is 8);
doubles as ``strtod`` (``1e3``, ``.5``, ``nan``, ``inf``, ``.inf``); quoted values are
strings; a flow sequence ``[1, 2]`` is an array whose items share one type.

Which file entries reach a node (rclpy's rule): an entry's node name, made absolute, must
equal the node's fully qualified name or match it as a wildcard (``*`` one token, ``**`` any
number of tokens); entries are applied in the order they first appear, so a node-specific
entry after ``/**`` overrides it and a ``-p`` given before a file is overridden by the file's
``/**`` entry.
"""

from __future__ import annotations

import math
import re
import sys
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from posekit.runtime.logging import (
    LoggingSeverity,
    get_logging_severity_from_string,
    set_logger_level,
)
from posekit.runtime.names import (
    NameValidationError,
    RemapRule,
    validate_namespace,
    validate_node_name,
    validate_topic_name,
)

__all__ = [
    "RCLError",
    "RosArguments",
    "UnknownROSArgsError",
    "compose_parameter_file",
    "flatten_parameters",
    "load_parameter_file",
    "node_name_matches",
    "parse_arguments",
    "parse_parameter_value",
    "remove_ros_args",
]

ROS_ARGS_FLAG = "--ros-args"
END_TOKEN = "--"
_VALUE_FLAGS = {"-p", "--param", "-r", "--remap", "--params-file", "--log-level", "-e",
                "--enclave", "--log-config-file"}
_WHAT = {"-p": "parameter override rule", "--param": "parameter override rule",
         "-r": "remap rule", "--remap": "remap rule", "--params-file": "file path",
         "--log-level": "log level", "-e": "enclave name", "--enclave": "enclave name",
         "--log-config-file": "log config file"}
_KIND = {"-p": "parameter override rule", "--param": "parameter override rule",
         "-r": "remap rule", "--remap": "remap rule", "--params-file": "params file",
         "--log-level": "log level"}
_SWITCHES = {f"--{state}-{what}" for state in ("enable", "disable")
             for what in ("stdout-logs", "rosout-logs", "external-lib-logs")}


class RCLError(RuntimeError, ValueError):
    """A malformed ROS argument (rclpy raises ``RCLError`` with rcl's message)."""


class UnknownROSArgsError(RuntimeError, ValueError):
    """Arguments inside ``--ros-args`` that are no ROS flag (rclpy's error of that name)."""

    def __init__(self, unknown: Sequence[str]) -> None:
        self.unknown = list(unknown)
        super().__init__(f"Found unknown ROS arguments: {self.unknown}")


# ---------------------------------------------------------------------------- scalars
_TRUE = frozenset({"Y", "y", "yes", "Yes", "YES", "true", "True", "TRUE", "on", "On", "ON"})
_FALSE = frozenset({"N", "n", "no", "No", "NO", "false", "False", "FALSE", "off", "Off", "OFF"})
_INT = re.compile(r"[+-]?(?:0[xX][0-9a-fA-F]+|0[0-7]*|[1-9][0-9]*)")
_FLOAT = re.compile(
    r"[+-]?(?:(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"
    r"|0[xX](?:[0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)(?:[pP][+-]?[0-9]+)?"
    r"|inf(?:inity)?|nan)",
    re.IGNORECASE,
)
_YAML_SPECIAL = {".nan": math.nan, ".NaN": math.nan, ".NAN": math.nan,
                 ".inf": math.inf, ".Inf": math.inf, ".INF": math.inf,
                 "-.inf": -math.inf, "-.Inf": -math.inf, "-.INF": -math.inf}
_INT64 = (-(2**63), 2**63 - 1)


def _scalar(text: str, quoted: bool) -> Any:
    """One YAML scalar typed as rcl_yaml_param_parser types it."""
    if quoted:
        return text
    if text in _TRUE:
        return True
    if text in _FALSE:
        return False
    if _INT.fullmatch(text):
        sign = -1 if text.startswith("-") else 1
        digits = text.lstrip("+-")
        if len(digits) > 1 and digits[0] == "0" and digits[1] not in "xX":
            value = sign * int(digits, 8)
        else:
            value = sign * int(digits, 0)
        if _INT64[0] <= value <= _INT64[1]:
            return value
        # out of range for strtoll: rcl tries strtod next
    if text in _YAML_SPECIAL:
        return _YAML_SPECIAL[text]
    if _FLOAT.fullmatch(text):
        value_f = float.fromhex(text) if "x" in text.lower() else float(text)
        if math.isinf(value_f) and "inf" not in text.lower():
            return text  # strtod overflow (ERANGE): rcl keeps the text as a string
        return value_f
    return text


def _type_tag(value: Any) -> str:
    return type(value).__name__


def _node_value(node: Any, where: str) -> Any:
    """A parameter value from a composed YAML node (scalar or flow/block sequence)."""
    import yaml

    if isinstance(node, yaml.ScalarNode):
        return _scalar(node.value, node.style in ("'", '"'))
    if isinstance(node, yaml.SequenceNode):
        items = []
        for item in node.value:
            if not isinstance(item, yaml.ScalarNode):
                raise RCLError(f"{where}: arrays must hold scalars, not sequences or mappings")
            items.append(_scalar(item.value, item.style in ("'", '"')))
        if len({_type_tag(v) for v in items}) > 1:
            raise RCLError(f"{where}: sequence items must all have the same type, got {items}")
        return items
    raise RCLError(f"{where}: a mapping is not a parameter value")


def parse_parameter_value(text: str) -> Any:
    """A ``-p name:=VALUE`` value as rcl types it (see the module docstring).

    Raises :class:`RCLError` for what rcl refuses (mappings, mixed-type arrays, no value).
    """
    import yaml

    try:
        node = yaml.compose(text)
    except yaml.YAMLError as exc:
        raise RCLError(f"not a YAML value: {exc}") from None
    if node is None:
        raise RCLError("no value given")
    return _node_value(node, f"value {text!r}")


# ---------------------------------------------------------------------------- files
def compose_parameter_file(path: str | Path) -> Any:
    """The composed YAML of a ROS 2 parameter file (``yaml.Node``; ``None`` when empty).

    Composed, not constructed, so that a leaf keeps whether it was quoted (rcl types
    ``'1'`` as a string). Raises ``OSError`` for an unreadable file and ``yaml.YAMLError``
    for text that is not YAML; callers word these as their API does.
    """
    import yaml

    return yaml.compose(Path(path).read_text(encoding="utf-8"))


def flatten_parameters(
    mapping: Any, leaf: Callable[[Any, str], Any], prefix: str = ""
) -> dict[str, Any]:
    """The parameters of one ``ros__parameters`` mapping (a composed YAML node), by name.

    Nested mappings become dotted names (``pid: {kp: 1}`` gives ``pid.kp``); every other
    node is typed by ``leaf(node, name)``. The one walk of a parameter section: rcl's
    ``--params-file`` (:func:`load_parameter_file`) types leaves with rcl's rules, rclpy's
    ``parameter_dict_from_yaml_file`` with its own.
    """
    import yaml

    out: dict[str, Any] = {}
    for key_node, value_node in mapping.value:
        name = f"{prefix}{key_node.value}"
        if isinstance(value_node, yaml.MappingNode):
            out.update(flatten_parameters(value_node, leaf, name + "."))
        else:
            out[name] = leaf(value_node, name)
    return out


def load_parameter_file(path: str | Path) -> list[tuple[str, dict[str, Any]]]:
    """``[(node name, {parameter: value})]`` of a ROS 2 parameter YAML file, in file order.

    rcl's ``--params-file`` reading: node names are absolute (``talker`` -> ``/talker``;
    nested namespace keys are joined); nested parameter mappings are flattened with ``.``;
    values are typed by rcl's rules (see the module docstring). Raises :class:`RCLError`.
    """
    import yaml

    p = Path(path)
    try:
        root = compose_parameter_file(p)
    except OSError as exc:
        raise RCLError(f"Error opening YAML file '{p}': {exc.strerror or exc}") from None
    except yaml.YAMLError as exc:
        raise RCLError(f"{p} is not YAML: {exc}") from None
    entries: dict[str, dict[str, Any]] = {}
    if root is None:
        return []
    if not isinstance(root, yaml.MappingNode):
        raise RCLError(f"{p}: the top level must map node names to their parameters")

    def typed(node: Any, name: str) -> Any:
        return _node_value(node, f"{p}: parameter '{name}'")

    def nodes(mapping: Any, ns: str) -> None:
        for key_node, value_node in mapping.value:
            key = str(key_node.value)
            if key == "ros__parameters":
                if not ns:
                    raise RCLError(f"{p}: ros__parameters needs a node name above it")
                if not isinstance(value_node, yaml.MappingNode):
                    raise RCLError(f"{p}: ros__parameters of '{ns}' must be a mapping")
                entries.setdefault(ns, {}).update(flatten_parameters(value_node, typed))
                continue
            if not isinstance(value_node, yaml.MappingNode):
                raise RCLError(f"{p}: '{key}' is not under a node's ros__parameters "
                               "(expected NODE: ros__parameters: ...)")
            nodes(value_node, (ns.rstrip("/") + "/" + key.strip("/")) if ns else
                  "/" + key.strip("/"))

    nodes(root, "")
    return list(entries.items())


def node_name_matches(pattern: str, fully_qualified_name: str) -> bool:
    """Whether a parameter entry's node name applies to a node.

    ``*`` matches one token, ``**`` any number of tokens, ``/**`` every node.
    """
    if not pattern.startswith("/"):
        pattern = "/" + pattern
    if pattern == fully_qualified_name or pattern == "/**":
        return True
    parts = []
    for token in pattern.strip("/").split("/"):
        if token == "**":
            parts.append(r"(?:/[^/]+)*")
        else:
            parts.append("/" + re.escape(token).replace(r"\*", "[^/]*"))
    return re.fullmatch("".join(parts), fully_qualified_name) is not None


# ---------------------------------------------------------------------------- arguments
@dataclass
class RosArguments:
    """What one argument list said.

    ``parameters`` as ``(node name pattern, {name: value})`` in order, ``remaps``,
    ``log_levels`` (``""`` = the default level), ``enclave``, ``unparsed`` (the program's own
    arguments) and the ROS argument ranges found.
    """

    parameters: list[tuple[str, dict[str, Any]]] = field(default_factory=list)
    remaps: list[RemapRule] = field(default_factory=list)
    log_levels: list[tuple[str, LoggingSeverity]] = field(default_factory=list)
    enclave: str | None = None
    unparsed: list[str] = field(default_factory=list)

    def add_parameters(self, node: str, values: Mapping[str, Any]) -> None:
        """Add overrides for the nodes ``node`` names (a pattern, ``/**`` for every node).

        rcl's merge, as for one more ``--params-file`` entry: values for a pattern already
        present update it in place (keeping its place in the order), a new pattern goes last.
        """
        for pattern, known in self.parameters:
            if pattern == node:
                known.update(values)
                return
        self.parameters.append((node, dict(values)))

    def parameters_for(self, fully_qualified_name: str) -> dict[str, Any]:
        """The overrides for the node ``/ns/name`` (entries applied in order)."""
        out: dict[str, Any] = {}
        for pattern, values in self.parameters:
            if node_name_matches(pattern, fully_qualified_name):
                out.update(values)
        return out

    def apply_log_levels(self) -> None:
        """Set the logger levels these arguments ask for (what ``init`` does)."""
        for name, level in self.log_levels:
            set_logger_level(name, level)


def _parse_level(spec: str) -> tuple[str, LoggingSeverity]:
    name, sep, level = spec.rpartition(":=")
    if sep and not name:
        raise RCLError("empty logger name")
    key = level.strip()
    if key.upper() == "WARNING":  # rcl's --log-level takes it; rcutils' name lookup does not
        key = "WARN"
    try:
        return name, get_logging_severity_from_string(key)
    except RuntimeError:
        raise RCLError("Argument does not use a valid severity level (unset, debug, info, "
                       "warn, error, fatal)") from None


def _parse_remap(spec: str) -> RemapRule:
    lhs, sep, rhs = spec.partition(":=")
    if not sep or not lhs or not rhs:
        raise RCLError("expected [node:]from:=to")
    node: str | None = None
    match = re.fullmatch(r"([A-Za-z_][A-Za-z0-9_]*):(?!//)(.+)", lhs)
    if match and not lhs.startswith(("rostopic://", "rosservice://")):
        node, lhs = match.group(1), match.group(2)
    kind: str | None = None
    for scheme in ("rostopic://", "rosservice://"):
        if lhs.startswith(scheme):
            lhs, kind = lhs[len(scheme):], scheme[3:-3]
    try:
        if lhs in ("__node", "__name"):
            validate_node_name(rhs)
        elif lhs == "__ns":
            validate_namespace(rhs)
        else:
            validate_topic_name(lhs)
            validate_topic_name(rhs)
    except NameValidationError as exc:
        raise RCLError(exc.reason) from None
    return RemapRule(lhs, rhs, node, kind)


def _parse_param(spec: str, out: RosArguments) -> None:
    lhs, sep, value = spec.partition(":=")
    if not sep:
        raise RCLError("expected [node:]name:=value")
    node = "/**"
    if ":" in lhs:
        node_name, lhs = lhs.split(":", 1)
        if "*" in node_name:
            raise RCLError(f"wildcards are not implemented in '{node_name}:' (use a "
                           "parameter file for them)")
        try:
            validate_node_name(node_name)
        except NameValidationError as exc:
            raise RCLError(f"'{node_name}' before ':' must be a node name: {exc.reason}") from None
        node = "/" + node_name  # as rcl: matches that name in the root namespace only
    if not lhs:
        raise RCLError("expected a parameter name before :=")
    out.add_parameters(node, {lhs: parse_parameter_value(value)})


def _apply_flag(flag: str, value: str, out: RosArguments) -> None:
    """Record one ``flag value`` pair of a ``--ros-args`` section in ``out``."""
    if flag in ("-p", "--param"):
        _parse_param(value, out)
    elif flag in ("-r", "--remap"):
        out.remaps.append(_parse_remap(value))
    elif flag == "--params-file":
        for node, values in load_parameter_file(value):
            out.add_parameters(node, values)
    elif flag == "--log-level":
        out.log_levels.append(_parse_level(value))
    elif flag in ("-e", "--enclave"):
        out.enclave = value


def parse_arguments(args: Sequence[str] | None, *, strict: bool = True) -> RosArguments:
    """Parse ``args`` (every element, ``args[0]`` included, as rcl does).

    Raises :class:`RCLError` for malformed flags and, if ``strict``,
    :class:`UnknownROSArgsError` for unknown ones (after the whole list was read, naming all
    of them; not ``strict``, they are dropped as rcl drops them).
    """
    out = RosArguments()
    unknown: list[str] = []
    in_ros = False
    items = list(args or [])
    i = 0
    while i < len(items):
        arg = items[i]
        i += 1
        if not isinstance(arg, str):
            raise TypeError(f"arguments must be strings, got {arg!r}")
        if arg == ROS_ARGS_FLAG:
            in_ros = True
            continue
        if not in_ros:
            out.unparsed.append(arg)
            continue
        if arg == END_TOKEN:
            in_ros = False
            continue
        if arg in _SWITCHES:
            continue
        if arg not in _VALUE_FLAGS:
            unknown.append(arg)
            continue
        if i >= len(items):
            found = "provided" if arg == "--params-file" else "found"
            raise RCLError(f"Couldn't parse trailing {arg} flag. No {_WHAT[arg]} {found}.")
        value = items[i]
        i += 1
        try:
            _apply_flag(arg, value, out)
        except RCLError as exc:
            raise RCLError(
                f"Couldn't parse {_KIND.get(arg, arg)}: '{arg} {value}'. Error: {exc}"
            ) from None
    if unknown and strict:
        raise UnknownROSArgsError(unknown)
    return out


def remove_ros_args(args: Sequence[str] | None = None) -> list[str]:
    """``args`` (default ``sys.argv``) without the ROS arguments (rclpy.utilities).

    Raises like :func:`parse_arguments` (unknown flags inside ``--ros-args`` included).
    """
    return parse_arguments(sys.argv if args is None else args).unparsed
