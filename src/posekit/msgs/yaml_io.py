"""Messages <-> YAML and Python text, as rosidl_runtime_py does it for the ROS 2 tools.

* :func:`message_to_yaml` / :func:`message_to_ordered`: what ``ros2 topic echo`` prints (block
  YAML as PyYAML's ``yaml.dump(..., allow_unicode=True, sort_keys=False)`` writes it, arrays
  and strings truncated to ``truncate_length`` items / characters followed by ``...``), without
  needing PyYAML.
* ``message_to_yaml(..., flow_style=True)``: the same data in YAML flow style.
* :func:`message_to_csv`: ``ros2 topic echo --csv``'s one line per message.
* :func:`ros_repr`: rclpy's generated ``__repr__`` (``geometry_msgs.msg.Vector3(x=1.0, ...)``).
* :func:`set_message_fields` / :func:`parse_values`: YAML VALUES -> a message, as
  ``ros2 topic pub`` fills one (``header: auto``, ``stamp: now``).
* :func:`message_class`: posekit's class for a type name, else rosbags' (any Jazzy type).
* :func:`default_message`: a default-valued instance of any type (what ``ros2 interface
  proto`` shows, what ``set_message_fields`` fills).
* :func:`get_field`: a dotted field path (``pose.position.x``) of a message.
* :func:`message_field_names`: a message object's ROS fields (a rosbags class's constants
  left out).

Used by the CLI tools (``topic echo/pub``, ``bag info``, plots) and the viewer.
"""

from __future__ import annotations

import dataclasses
import math
import re
import time
import typing
from collections.abc import Callable
from typing import Any

import numpy as np

from posekit.msgs.errors import MessageError

__all__ = [
    "TRUNCATE_LENGTH",
    "MessageFieldError",
    "default_message",
    "get_field",
    "message_class",
    "message_field_names",
    "message_to_csv",
    "message_to_ordered",
    "message_to_yaml",
    "ordered_to_yaml",
    "parse_values",
    "ros_repr",
    "set_message_fields",
    "yaml_scalar",
]

#: ``ros2 topic echo``'s default truncation of arrays, bytes and strings.
TRUNCATE_LENGTH = 128


class MessageFieldError(MessageError):
    """VALUES of ``topic pub`` do not fit the message type (the text says which field)."""


# ---------------------------------------------------------------------------------------
# Messages -> YAML (what rosidl_runtime_py.message_to_yaml prints, without PyYAML)


def _is_message(value: Any) -> bool:
    return dataclasses.is_dataclass(value) and not isinstance(value, type)


_FIELD_NAMES: dict[type, tuple[str, ...]] = {}


def message_field_names(msg: Any) -> tuple[str, ...]:
    """The ROS fields of a message object (a dataclass), in order.

    A rosbags class (a type posekit has no class for) also carries its constants and
    ``__msgtype__`` as dataclass fields: they are left out, as ROS prints no constants.
    """
    cls = type(msg)
    names = _FIELD_NAMES.get(cls)
    if names is None:
        fields = [f.name for f in dataclasses.fields(cls)]
        constants: set[str] = set()
        if "__msgtype__" in fields:  # rosbags' class
            from posekit.msgs.cdr import get_typestore

            defs = get_typestore().fielddefs.get(getattr(cls, "__msgtype__", ""))
            constants = {const[0] for const in defs[0]} if defs else set()
        names = _FIELD_NAMES[cls] = tuple(
            name for name in fields if not name.startswith("_") and name not in constants)
    return names


def message_to_ordered(value: Any, truncate_length: int | None = TRUNCATE_LENGTH, *,
                       no_arr: bool = False, no_str: bool = False) -> Any:
    """A message as nested dicts (field order kept), lists and Python scalars.

    Sequences longer than ``truncate_length`` keep their first items plus ``'...'``;
    strings keep their first characters plus ``...`` (rosidl_runtime_py's convention).
    ``no_arr`` replaces array and sequence fields by ``<array type: double[36]>`` /
    ``<sequence type: uint8, length: 3>``; ``no_str`` strings by ``<string length: <N>>``.
    """
    if _is_message(value):
        arrays = _array_descriptions(value) if no_arr else {}
        out: dict[str, Any] = {}
        for name in message_field_names(value):
            field_value = getattr(value, name)
            if no_arr and _is_sequence(field_value):
                out[name] = _abbreviated(name, field_value, arrays)
            else:
                out[name] = message_to_ordered(field_value, truncate_length,
                                               no_arr=no_arr, no_str=no_str)
        return out
    if isinstance(value, np.ndarray):
        items: list[Any] = value.tolist()
        return _truncate_list(items, truncate_length)
    if isinstance(value, (bytes, bytearray)):
        return _truncate_list(list(value), truncate_length)
    if isinstance(value, (list, tuple)):
        converted = [message_to_ordered(v, truncate_length, no_arr=no_arr, no_str=no_str)
                     for v in value]
        return _truncate_list(converted, truncate_length)
    if isinstance(value, str):
        return _string_value(value, truncate_length, no_str)
    if isinstance(value, np.generic):
        return value.item()
    return value


def _string_value(value: str, truncate_length: int | None, no_str: bool) -> str:
    """A string field as rosidl_runtime_py shows it.

    ``<string length: <N>>`` with ``no_str``, else cut to ``truncate_length`` characters plus
    ``...``.
    """
    if no_str:
        return f"<string length: <{len(value)}>>"
    if truncate_length is not None and len(value) > truncate_length:
        return value[:truncate_length] + "..."
    return value


def _is_sequence(value: Any) -> bool:
    return isinstance(value, (np.ndarray, bytes, bytearray, list, tuple))


# rosidl_parser's names for the basic types, as ``--no-arr`` prints them
_IDL_TYPE_NAMES = {"float64": "double", "float32": "float", "bool": "boolean", "byte": "octet",
                   "char": "uint8"}


def _array_descriptions(msg: Any) -> dict[str, tuple[str, int | None, bool]]:
    """field -> (element type, size or bound, fixed?) for the array fields of ``msg``'s type."""
    name = getattr(msg, "__msgtype__", None)
    if not isinstance(name, str):
        return {}
    try:
        from rosbags.interfaces import Nodetype
        from rosbags.typesys.base import normalize_fieldname

        from posekit.msgs.cdr import get_typestore

        fields = get_typestore().fielddefs[name][1]
    except (ImportError, KeyError):
        return {}
    out: dict[str, tuple[str, int | None, bool]] = {}
    for raw_name, desc in fields:
        if desc[0] not in (Nodetype.ARRAY, Nodetype.SEQUENCE):
            continue
        (subkind, subinfo), count = desc[1]
        if subkind == Nodetype.BASE:
            element = _IDL_TYPE_NAMES.get(subinfo[0], subinfo[0])
        else:
            element = str(subinfo)
        out[normalize_fieldname(raw_name)] = (element, count or None, desc[0] == Nodetype.ARRAY)
    return out


def _abbreviated(field: str, value: Any,
                 arrays: dict[str, tuple[str, int | None, bool]]) -> str:
    element, size, fixed = arrays.get(field, ("unknown", None, False))
    if fixed:
        return f"<array type: {element}[{size}]>"
    if size is not None:
        return f"<sequence type: {element}[{size}], length: {len(value)}>"
    return f"<sequence type: {element}, length: {len(value)}>"


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
        return _yaml_float(value)
    text = str(value)
    style = _string_style(text)
    if style == "":
        return text
    if style == "'":
        return "'" + text.replace("'", "''") + "'"
    return _double_quoted(text)


def _yaml_float(value: float) -> str:
    """A float as PyYAML writes it: ``.nan``, ``.inf``, ``-.inf``, or repr with a ``.0e``."""
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


def _double_quoted(text: str) -> str:
    """``text`` as a double-quoted YAML scalar with PyYAML's escapes."""
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


def message_to_yaml(msg: Any, *, truncate_length: int | None = TRUNCATE_LENGTH,
                    no_arr: bool = False, no_str: bool = False,
                    flow_style: bool = False) -> str:
    """``msg`` as ``ros2 topic echo`` prints it (before its ``---`` separator line).

    ``flow_style`` gives PyYAML's flow style (``{x: 1.0, y: 0.0}``) on one line, as
    ``ros2 topic echo --flow-style`` prints it.
    """
    data = message_to_ordered(msg, truncate_length, no_arr=no_arr, no_str=no_str)
    return ordered_to_yaml(data, flow_style=flow_style)


def ordered_to_yaml(data: Any, *, flow_style: bool = False) -> str:
    """:func:`message_to_ordered`'s data as :func:`message_to_yaml` prints it."""
    if flow_style:
        import sys

        import yaml  # type: ignore[import-untyped,unused-ignore]

        text: str = yaml.dump(data, allow_unicode=True, width=sys.maxsize,
                              default_flow_style=True, sort_keys=False)
        return text
    if not isinstance(data, dict):
        return yaml_scalar(data) + "\n"
    if not data:
        return "{}\n"
    lines: list[str] = []
    _emit_mapping(data, 0, lines)
    return "\n".join(lines) + "\n"


def message_to_csv(msg: Any, *, truncate_length: int | None = None, no_arr: bool = False,
                   no_str: bool = False) -> str:
    """All leaf values of ``msg`` comma-separated, as rosidl_runtime_py's ``message_to_csv``.

    Values print with Python's ``str`` (``1.0``, ``True``); sequences longer than
    ``truncate_length`` end with ``...``.
    """
    arrays = _array_descriptions(msg) if no_arr else {}
    parts: list[str] = []
    for name in message_field_names(msg):
        value = getattr(msg, name)
        if no_arr and _is_sequence(value) and not isinstance(value, str):
            parts.append(_abbreviated(name, value, arrays))
        else:
            parts.append(_csv_value(value, truncate_length, no_arr, no_str))
    return ",".join(parts)


def _csv_value(value: Any, truncate_length: int | None, no_arr: bool, no_str: bool) -> str:
    if isinstance(value, (np.ndarray, list, tuple, bytes, bytearray)):
        items = value.tolist() if isinstance(value, np.ndarray) else list(value)
        out: list[str] = []
        for i, item in enumerate(items):
            if truncate_length is not None and i >= truncate_length:
                out.append("...")
                break
            out.append(_csv_value(item, truncate_length, no_arr, no_str))
        return ",".join(out)
    if isinstance(value, str):
        return _string_value(value, truncate_length, no_str)
    if isinstance(value, np.generic):
        return str(value.item())
    if _is_message(value):
        return message_to_csv(value, truncate_length=truncate_length, no_arr=no_arr,
                              no_str=no_str)
    return str(value)


def get_field(msg: Any, path: str) -> Any:
    """The value at a dotted field path (``pose.pose.position.x``) of ``msg``.

    Raises :class:`MessageFieldError` naming the path when a component does not exist.
    """
    parts = [p for p in path.split(".") if p]
    if not parts:
        raise MessageFieldError(f"Invalid field value '{path}'")
    value = msg
    for part in parts:
        try:
            value = getattr(value, part)
        except AttributeError:
            raise MessageFieldError(
                f"Invalid field '{path}': '{type(value).__name__}' object has no "
                f"attribute '{part}'"
            ) from None
    return value


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
            defaults = default_message(value.__msgtype__)
        except (AttributeError, KeyError):  # not a ROS message type
            defaults = None
        args = []
        for name in message_field_names(value):
            field_value = getattr(value, name)
            if isinstance(field_value, np.ndarray):
                default = getattr(defaults, name, None)
                fixed = isinstance(default, np.ndarray) and default.size > 0
                text = repr(field_value) if fixed else repr(field_value.tolist())
            else:
                text = ros_repr(field_value)
            args.append(f"{name}={text}")
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
    names = set(message_field_names(msg))
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
            fresh = default_message(msgtype) if msgtype else type(current)()
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
            return _converted_list(owner, name, value, where, now_ns)
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


def _converted_list(owner: type, name: str, value: Any, where: str,
                    now_ns: Callable[[], int] | None) -> list[Any]:
    """``value`` for the sequence field ``name`` of ``owner``: messages built from mappings."""
    if not isinstance(value, list):
        raise MessageFieldError(f"{where}: expected a list, got {value!r}")
    elem = _list_element_class(owner, name)
    if elem is None:
        return list(value)
    out = []
    for i, item in enumerate(value):
        elem_type = getattr(elem, "__msgtype__", "")
        child = default_message(elem_type) if elem_type else elem()
        set_message_fields(child, item, path=f"{where}[{i}]", now_ns=now_ns)
        out.append(child)
    return out


def message_class(type_name: str) -> type:
    """posekit's class for a ROS type, else the rosbags class (any ROS 2 Jazzy type)."""
    from posekit.msgs.registry import find_message_class

    return find_message_class(type_name)


def _default_value(desc: Any) -> Any:
    from rosbags.interfaces import Nodetype

    kind, info = desc
    if kind == Nodetype.BASE:
        base = info[0]
        if base == "string":
            return ""
        if base == "bool":
            return False
        return 0.0 if base.startswith("float") else 0
    if kind == Nodetype.NAME:
        return default_message(info)
    element, count = info
    length = count if kind == Nodetype.ARRAY else 0
    if element[0] == Nodetype.BASE and element[1][0] != "string":
        # numbers as numpy arrays, as rosbags decodes them (and rclpy holds arrays)
        return np.zeros(length, dtype=_NUMPY_DTYPES.get(element[1][0], element[1][0]))
    return [_default_value(element) for _ in range(length)]


#: rosbags' base type names numpy does not spell the same way.
_NUMPY_DTYPES = {"bool": "bool", "byte": "uint8", "char": "uint8"}


def default_message(type_name: str) -> Any:
    """A default-valued instance of ``type_name``.

    posekit's class when it has one, else the rosbags class of ROS 2 Jazzy's definition: the
    defaults the ``.msg`` file gives (:data:`~posekit.msgs.type_description.FIELD_DEFAULTS`),
    else zeros, empty strings and sequences.

    Raises:
        KeyError: no such message type.
    """
    from posekit.msgs.cdr import get_typestore
    from posekit.msgs.registry import MESSAGE_CLASSES

    cls = MESSAGE_CLASSES.get(type_name)
    if cls is not None:
        return cls()
    from posekit.msgs.type_description import FIELD_DEFAULTS

    store = get_typestore()
    fields = store.fielddefs[type_name][1]
    given = FIELD_DEFAULTS.get(type_name, {})
    return store.types[type_name](*[
        _given_default(given[name], desc) if name in given else _default_value(desc)
        for name, desc in fields])


def _given_default(text: str, desc: Any) -> Any:
    """A default of FIELD_DEFAULTS (rosidl's text: ``True``, ``1.0``, ``-2``) as a value."""
    zero = _default_value(desc)
    return text == "True" if isinstance(zero, bool) else type(zero)(text)


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
