"""Topic, node and namespace names: validation, expansion and remapping (rcl's rules).

* A **node name** is ``[A-Za-z_][A-Za-z0-9_]*``.
* A **namespace** is ``/`` or an absolute path of tokens (``/robot1/sensors``); a relative
  namespace given to a node gets a leading ``/`` (rclpy does the same).
* A **topic name** is absolute (``/tf``), relative (``cmd_vel`` -> ``<ns>/cmd_vel``) or private
  (``~`` -> ``<ns>/<node>``, ``~/debug`` -> ``<ns>/<node>/debug``); ``{node}`` and ``{ns}`` /
  ``{namespace}`` are substituted. Tokens are ``[A-Za-z0-9_]`` and must not start with a
  digit; no ``//``, no trailing ``/``, ``~`` only at the start.
* **Remapping** rules ``from:=to`` (or a mapping) are matched against the fully expanded name;
  both sides are expanded in the node's namespace. ``node_name:from:=to`` applies to one node
  only; ``__node:=name`` and ``__ns:=/ns`` rename the node / change its namespace.

Bad names raise :class:`InvalidTopicNameException`, :class:`InvalidNodeNameException` or
:class:`InvalidNamespaceException` (all :class:`NameValidationError`, a ValueError) with the
offending name, the reason and the character index.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

__all__ = [
    "InvalidNamespaceException",
    "InvalidNodeNameException",
    "InvalidServiceNameException",
    "InvalidTopicNameException",
    "NameValidationError",
    "RemapRule",
    "apply_remappings",
    "expand_topic_name",
    "is_hidden_name",
    "normalize_namespace",
    "parse_remap_rules",
    "remap_node_name",
    "remap_node_namespace",
    "resolve_service_name",
    "resolve_topic_name",
    "validate_full_topic_name",
    "validate_namespace",
    "validate_node_name",
    "validate_topic_name",
]

_TOKEN_OK = re.compile(r"[A-Za-z0-9_]")
_NODE_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_SUBSTITUTION = re.compile(r"\{([^{}]*)\}")


class NameValidationError(ValueError):
    """A name broke ROS's naming rules. ``name``, ``reason`` and ``index`` say where."""

    kind = "name"

    def __init__(self, name: str, reason: str, index: int) -> None:
        self.name = name
        self.reason = reason
        self.index = index
        pointer = " " * index + "^"
        super().__init__(f"Invalid {self.kind} '{name}': {reason} (at index {index})\n  "
                         f"{name}\n  {pointer}")


class InvalidTopicNameException(NameValidationError):  # noqa: N818 - rclpy name
    """A topic name is not valid (rclpy.exceptions.InvalidTopicNameException)."""

    kind = "topic name"


class InvalidServiceNameException(NameValidationError):  # noqa: N818 - rclpy name
    """A service name is not valid (rclpy.exceptions.InvalidServiceNameException)."""

    kind = "service name"


class InvalidNodeNameException(NameValidationError):  # noqa: N818 - rclpy name
    """A node name is not valid (rclpy.exceptions.InvalidNodeNameException)."""

    kind = "node name"


class InvalidNamespaceException(NameValidationError):  # noqa: N818 - rclpy name
    """A namespace is not valid (rclpy.exceptions.InvalidNamespaceException)."""

    kind = "namespace"


def validate_node_name(name: str) -> str:
    """Return ``name`` if it is a valid node name, else raise InvalidNodeNameException."""
    if not isinstance(name, str):
        raise TypeError(f"node name must be a str, got {type(name).__name__}")
    if not name:
        raise InvalidNodeNameException(name, "node name must not be empty", 0)
    if name[0].isdigit():
        raise InvalidNodeNameException(name, "node name must not start with a number", 0)
    for i, ch in enumerate(name):
        if not _TOKEN_OK.fullmatch(ch):
            raise InvalidNodeNameException(
                name, f"node name must only contain alphanumerics and '_', found {ch!r}", i
            )
    return name


def _check_tokens(name: str, start: int, exc: type[NameValidationError], what: str) -> None:
    """Validate the '/'-separated tokens of ``name[start:]`` (substitutions already removed)."""
    if name.endswith("/") and len(name) > 1:
        raise exc(name, f"{what} must not end with a forward slash", len(name) - 1)
    if "//" in name:
        raise exc(name, f"{what} must not contain repeated forward slashes", name.index("//"))
    pos = start
    for token in name[start:].split("/"):
        if token and token[0].isdigit():
            raise exc(name, f"{what} tokens must not start with a number", pos)
        for j, ch in enumerate(token):
            if not _TOKEN_OK.fullmatch(ch):
                raise exc(
                    name,
                    f"{what} must only contain alphanumerics, '_' and '/', found {ch!r}",
                    pos + j,
                )
        pos += len(token) + 1


def validate_namespace(namespace: str) -> str:
    """Return ``namespace`` if it is a valid absolute namespace, else raise."""
    if not isinstance(namespace, str):
        raise TypeError(f"namespace must be a str, got {type(namespace).__name__}")
    if not namespace:
        raise InvalidNamespaceException(namespace, "namespace must not be empty", 0)
    if not namespace.startswith("/"):
        raise InvalidNamespaceException(namespace, "namespace must be absolute", 0)
    if namespace == "/":
        return namespace
    _check_tokens(namespace, 1, InvalidNamespaceException, "namespace")
    return namespace


def normalize_namespace(namespace: str | None) -> str:
    """'' / None -> '/', 'robot1' -> '/robot1'; then validated."""
    if not namespace:
        return "/"
    if not namespace.startswith("/"):
        namespace = "/" + namespace
    return validate_namespace(namespace)


def _without_substitutions(name: str) -> str:
    """``name`` with each ``{...}`` substitution replaced by as many ``s``: a plain name.

    Raises InvalidTopicNameException unless the braces are balanced, unnested and hold a
    valid name.
    """
    depth = 0
    for i, ch in enumerate(name):
        if ch == "{":
            if depth:
                raise InvalidTopicNameException(name, "nested '{' in substitution", i)
            depth = 1
        elif ch == "}":
            if not depth:
                raise InvalidTopicNameException(name, "unmatched '}'", i)
            depth = 0
    if depth:
        raise InvalidTopicNameException(name, "unmatched '{'", name.rindex("{"))
    for m in _SUBSTITUTION.finditer(name):
        if not _NODE_NAME.fullmatch(m.group(1)):
            raise InvalidTopicNameException(
                name, f"substitution '{{{m.group(1)}}}' is not a valid name", m.start()
            )
    return _SUBSTITUTION.sub(lambda m: "s" * len(m.group(0)), name)


def validate_topic_name(name: str) -> str:
    """Validate a topic name as written by the user (before expansion)."""
    if not isinstance(name, str):
        raise TypeError(f"topic name must be a str, got {type(name).__name__}")
    if not name:
        raise InvalidTopicNameException(name, "topic name must not be empty", 0)
    plain = _without_substitutions(name)
    if "~" in plain[1:]:
        raise InvalidTopicNameException(
            name, "'~' is only allowed as the first character", plain.index("~", 1)
        )
    start = 0
    if plain.startswith("~"):
        if len(plain) > 1 and plain[1] != "/":
            raise InvalidTopicNameException(name, "'~' must be followed by '/'", 1)
        start = 1
    if plain == "/":
        raise InvalidTopicNameException(name, "topic name must not be just '/'", 0)
    if plain.startswith("/"):
        start = 1
    elif start == 1:
        start = 2 if len(plain) > 1 else 1
    _check_tokens(plain, start, InvalidTopicNameException, "topic name")
    return name


def validate_full_topic_name(name: str) -> str:
    """Validate an expanded (absolute, substitution-free) topic name."""
    if not name.startswith("/"):
        raise InvalidTopicNameException(name, "fully qualified topic name must be absolute", 0)
    if "{" in name or "}" in name or "~" in name:
        i = min(name.find(c) for c in "{}~" if c in name)
        raise InvalidTopicNameException(name, "fully qualified name has unexpanded parts", i)
    if name == "/":
        raise InvalidTopicNameException(name, "topic name must not be just '/'", 0)
    _check_tokens(name, 1, InvalidTopicNameException, "topic name")
    return name


def is_hidden_name(name: str) -> bool:
    """ROS's hidden names: a token starting with ``_`` (``/robot/_action/feedback``)."""
    return any(token.startswith("_") for token in name.split("/"))


def expand_topic_name(name: str, node_name: str, namespace: str) -> str:
    """Expand a (validated) topic name to its absolute form for a node in ``namespace``."""
    validate_topic_name(name)
    namespace = normalize_namespace(namespace)
    ns_prefix = "" if namespace == "/" else namespace

    def substitute(m: re.Match[str]) -> str:
        key = m.group(1)
        if key == "node":
            return node_name
        if key in ("ns", "namespace"):
            return namespace
        raise InvalidTopicNameException(name, f"unknown substitution '{{{key}}}'", m.start())

    expanded = _SUBSTITUTION.sub(substitute, name)
    if expanded.startswith("~"):
        expanded = f"{ns_prefix}/{node_name}" + expanded[1:]
    elif not expanded.startswith("/"):
        expanded = f"{ns_prefix}/{expanded}"
    # as rcl: ``{ns}/x`` in the root namespace is ``//x``, which the full check refuses
    return validate_full_topic_name(expanded)


@dataclass(frozen=True, slots=True)
class RemapRule:
    """One ``[node:]from:=to`` rule.

    ``node`` None means every node; ``kind`` ``"topic"`` or ``"service"`` limits it to names of
    that kind (``rostopic://`` / ``rosservice://`` prefixes on the command line), None applies
    to both.
    """

    from_name: str
    to_name: str
    node: str | None = None
    kind: str | None = None


def parse_remap_rules(
    remappings: Iterable[str | tuple[str, str]] | Mapping[str, str] | None,
) -> list[RemapRule]:
    """Parse ``["a:=b", "talker:x:=y"]``, ``[("a", "b")]`` or ``{"a": "b"}`` into rules."""
    if remappings is None:
        return []
    items: Iterable[str | tuple[str, str]]
    items = list(remappings.items()) if isinstance(remappings, Mapping) else remappings
    rules: list[RemapRule] = []
    for item in items:
        if isinstance(item, str):
            if ":=" not in item:
                raise ValueError(f"remapping rule {item!r} must look like 'from:=to'")
            lhs, to_name = item.split(":=", 1)
            node: str | None = None
            if ":" in lhs:
                node, lhs = lhs.split(":", 1)
                validate_node_name(node)
            rules.append(RemapRule(lhs, to_name, node))
        else:
            lhs, to_name = item
            rules.append(RemapRule(str(lhs), str(to_name)))
    for rule in rules:
        if not rule.from_name or not rule.to_name:
            raise ValueError(f"remapping rule {rule} has an empty side")
    return rules


def _first_special(rules: Iterable[RemapRule], keys: tuple[str, ...],
                   node_name: str) -> str | None:
    for rule in rules:
        if rule.from_name in keys and rule.node in (None, node_name):
            return rule.to_name
    return None


def remap_node_name(rules: Iterable[RemapRule], node_name: str) -> str | None:
    """The new name a ``__node:=`` / ``__name:=`` rule gives ``node_name``, or None.

    The first rule that applies to the node wins (a ``node:`` prefix must be its name as
    created), as rcl's ``rcl_remap_node_name``.
    """
    return _first_special(rules, ("__node", "__name"), node_name)


def remap_node_namespace(rules: Iterable[RemapRule], node_name: str) -> str | None:
    """The namespace a ``__ns:=`` rule gives the node ``node_name``, or None.

    ``node_name`` is the node's name *after* :func:`remap_node_name`: rcl remaps the
    namespace with rules for the new name (``-r __node:=n2 -r n2:__ns:=/foo`` moves the node
    to ``/foo``; a ``talker:__ns:=`` rule no longer applies to it).
    """
    return _first_special(rules, ("__ns",), node_name)


def apply_remappings(
    full_name: str, rules: Iterable[RemapRule], node_name: str, namespace: str
) -> str:
    """The first matching rule wins (rcl). Both sides are expanded in the node's namespace."""
    for rule in rules:
        if rule.from_name.startswith("__"):
            continue
        if rule.node is not None and rule.node != node_name:
            continue
        if expand_topic_name(rule.from_name, node_name, namespace) == full_name:
            return expand_topic_name(rule.to_name, node_name, namespace)
    return full_name


def resolve_topic_name(
    name: str, node_name: str, namespace: str, rules: Iterable[RemapRule] = ()
) -> str:
    """Validate, expand and remap a topic name as a node would."""
    full = expand_topic_name(name, node_name, namespace)
    return apply_remappings(full, rules, node_name, namespace)


def resolve_service_name(
    name: str, node_name: str, namespace: str, rules: Iterable[RemapRule] = ()
) -> str:
    """Validate, expand and remap a service name.

    A topic name's rules; errors raise :class:`InvalidServiceNameException`.
    """
    try:
        return resolve_topic_name(name, node_name, namespace, rules)
    except InvalidTopicNameException as exc:
        raise InvalidServiceNameException(
            exc.name, exc.reason.replace("topic name", "service name"), exc.index
        ) from None
