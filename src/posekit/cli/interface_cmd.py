"""``posekit interface list|packages|package|show|proto``: ``ros2 interface``'s verbs.

The interfaces are what posekit can (de)serialize: every ROS 2 Jazzy message type of the
typestore (:func:`posekit.msgs.cdr.get_typestore`, rosbags), posekit's service types and its
action types. Output formats are ros2interface's (Jazzy):

* ``list [-m] [-s] [-a]``: ``Messages:`` / ``Services:`` / ``Actions:`` headings with the
  sorted names indented by four spaces;
* ``packages [-m|-s|-a]``: package names, sorted; ``package PKG``: ``pkg/kind/Name`` lines;
* ``show TYPE [--no-comments|--all-comments]``: the definition, with nested message
  definitions expanded below their field, indented by one tab per level; services show
  request ``---`` response, actions goal ``---`` result ``---`` feedback;
* ``proto TYPE [--no-quotes]``: a YAML prototype of the (goal/request/) message with its
  default values, in double quotes, as ``ros2 interface proto`` prints it.

Deviation: posekit does not ship ROS's ``.msg`` files, so ``show`` prints the definition as
the typestore holds it: one ``type name`` line per field (nested types of the same package
unqualified, as .msg files write them), ``type NAME=value`` constants first, and no
comments, blank lines or default values; ``--no-comments``/``--all-comments`` are accepted
and change nothing.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from typing import Any, TextIO

from posekit.msgs.yaml_io import default_message

__all__ = ["definition_lines", "interfaces", "main", "prototype"]

_PLACEHOLDER = "structure_needs_at_least_one_member"


def _store() -> Any:
    from posekit.msgs.cdr import get_typestore

    return get_typestore()


def _action_types() -> dict[str, Any]:
    from posekit.msgs.registry import ACTION_CLASSES

    return dict(ACTION_CLASSES)


def interfaces() -> dict[str, dict[str, list[str]]]:
    """``{"msg"|"srv"|"action": {package: [names]}}`` of every interface posekit knows."""
    from posekit.msgs.registry import SERVICE_CLASSES

    found: dict[str, dict[str, list[str]]] = {"msg": {}, "srv": {}, "action": {}}
    names = [n for n in _store().fielddefs if n.split("/")[1] == "msg"]
    names += [n for n in SERVICE_CLASSES if n.split("/")[1] == "srv"]  # not actions' parts
    names += list(_action_types())
    for full in names:
        pkg, kind, name = full.split("/")
        found[kind].setdefault(pkg, []).append(name)
    for by_pkg in found.values():
        for items in by_pkg.values():
            items.sort()
    return found


def _type_text(desc: Any, package: str) -> tuple[str, str | None]:
    """(.msg spelling of a field type, nested message type name or None)."""
    from rosbags.interfaces import Nodetype

    kind, info = desc
    if kind == Nodetype.BASE:
        base, bound = info
        return (f"{base}<={bound}" if bound else base), None
    if kind == Nodetype.NAME:
        pkg, _, name = info.split("/")
        return (name if pkg == package else f"{pkg}/{name}"), info
    element, count = info
    inner, nested = _type_text(element, package)
    if kind == Nodetype.ARRAY:
        return f"{inner}[{count}]", nested
    return (f"{inner}[<={count}]" if count else f"{inner}[]"), nested


def _constant_text(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


def definition_lines(type_name: str) -> list[tuple[str, str | None]]:
    """The lines of a message definition: ``(text, nested type to expand or None)``."""
    store = _store()
    if type_name not in store.fielddefs:
        raise LookupError(f"Unknown interface '{type_name}'")
    package = type_name.split("/")[0]
    consts, fields = store.fielddefs[type_name]
    lines: list[tuple[str, str | None]] = [
        (f"{ctype} {cname}={_constant_text(value)}", None) for cname, ctype, value in consts
    ]
    for fname, desc in fields:
        if fname == _PLACEHOLDER and len(fields) == 1:
            continue
        text, nested = _type_text(desc, package)
        lines.append((f"{text} {fname}", nested))
    return lines


def _parts(type_name: str) -> list[str]:
    """The message types whose definitions make up ``type_name``, in display order."""
    parts = type_name.split("/")
    if len(parts) != 3 or not all(parts):
        raise ValueError(f"Invalid name '{type_name}'. Expected three parts separated by '/'")
    kind = parts[1]
    if kind == "srv":
        return [f"{type_name}_Request", f"{type_name}_Response"]
    if kind == "action":
        return [f"{type_name}_Goal", f"{type_name}_Result", f"{type_name}_Feedback"]
    return [type_name]


def _show(type_name: str, indent: int, out: list[str]) -> None:
    for text, nested in definition_lines(type_name):
        out.append("\t" * indent + text)
        if nested is not None:
            _show(nested, indent + 1, out)


def show_text(type_name: str) -> str:
    """What ``show`` prints for ``type_name``."""
    lines: list[str] = []
    for i, part in enumerate(_parts(type_name)):
        if i:
            lines.append("---")
        _show(part, 0, lines)
    return "".join(f"{line}\n" for line in lines)


def prototype(type_name: str) -> str:
    """The YAML prototype ``proto`` prints (without quotes)."""
    from posekit.cli.topic_cmd import message_to_yaml

    first = _parts(type_name)[0]
    if first not in _store().fielddefs:
        raise LookupError(f"Unknown interface '{type_name}'")
    return message_to_yaml(default_message(first), truncate_length=None)


def _kind_args(parser: argparse.ArgumentParser, *, count: bool = False) -> None:
    action = "count" if count else "store_true"
    parser.add_argument("-m", "--only-msgs", action=action,
                        help="Print out only the message types")
    parser.add_argument("-s", "--only-srvs", action=action,
                        help="Print out only the service types")
    parser.add_argument("-a", "--only-actions", action=action,
                        help="Print out only the action types")


def _selected(ns: argparse.Namespace) -> list[str]:
    chosen = [k for k, flag in (("msg", ns.only_msgs), ("srv", ns.only_srvs),
                                ("action", ns.only_actions)) if flag]
    return chosen or ["msg", "srv", "action"]


_HEADINGS = {"msg": "Messages:", "srv": "Services:", "action": "Actions:"}


def main(argv: Sequence[str], *, out: TextIO | None = None, err: TextIO | None = None) -> int:
    """``posekit interface VERB ...``; returns the exit code."""
    out = out or sys.stdout
    err = err or sys.stderr
    parser = argparse.ArgumentParser(prog="posekit interface")
    verbs = parser.add_subparsers(dest="verb", metavar="VERB")
    _kind_args(verbs.add_parser("list", help="List all interface types available"))
    package = verbs.add_parser("package", help="Output a list of interface types in a package")
    _kind_args(package)
    package.add_argument("package_name")
    _kind_args(verbs.add_parser("packages", help="List packages that provide interfaces"),
               count=True)
    show = verbs.add_parser("show", help="Output the interface definition")
    comments = show.add_mutually_exclusive_group()
    comments.add_argument("--all-comments", action="store_true")
    comments.add_argument("--no-comments", action="store_true")
    show.add_argument("type")
    proto = verbs.add_parser("proto", help="Output an interface prototype")
    proto.add_argument("type")
    proto.add_argument("--no-quotes", action="store_true")
    ns = parser.parse_args(list(argv))
    if ns.verb is None:  # as ros2 interface: the verbs, and success
        parser.print_help(out)
        return 0
    try:
        if ns.verb == "show":
            text = sys.stdin.readline().strip() if ns.type == "-" else ns.type
            out.write(show_text(text))
        elif ns.verb == "proto":
            yaml_text = prototype(ns.type)
            out.write(yaml_text + "\n" if ns.no_quotes else f'"{yaml_text}"\n')
        else:
            out.write(_listing(ns))
    except (LookupError, ValueError) as exc:
        err.write(f"{str(exc).strip(chr(39)) if isinstance(exc, KeyError) else exc}\n")
        return 1
    out.flush()
    return 0


def _listing(ns: argparse.Namespace) -> str:
    known = interfaces()
    lines: list[str] = []
    if ns.verb == "list":
        for kind in _selected(ns):
            lines.append(_HEADINGS[kind])
            for pkg in sorted(known[kind]):
                lines.extend(f"    {pkg}/{kind}/{name}" for name in known[kind][pkg])
    elif ns.verb == "packages":
        kinds = _selected(ns)[:1] if (ns.only_msgs or ns.only_srvs or ns.only_actions) else (
            _selected(ns))
        lines.extend(sorted({pkg for kind in kinds for pkg in known[kind]}))
    else:
        pkg = ns.package_name
        if not any(pkg in known[kind] for kind in known):
            raise LookupError(f"Unknown package '{pkg}'")
        for kind in _selected(ns):
            lines.extend(f"{pkg}/{kind}/{name}" for name in known[kind].get(pkg, []))
    return "".join(f"{line}\n" for line in lines)
