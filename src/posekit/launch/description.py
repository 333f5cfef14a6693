"""Launch descriptions: which node classes/factories to run, and how.

With what names, parameters and remappings (a Python subset of ROS 2 ``launch`` /
``launch_ros``).

A node entry names something that *creates* posekit nodes: a Node subclass, a function
returning a node (or a list of nodes), or a ``"package.module:attr"`` string. Name,
namespace, parameters and remappings are applied to every node the factory creates, the way
ROS passes ``--ros-args`` to a process, so node classes that hard-code
``super().__init__("name")`` can be renamed and configured from the launch file.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from posekit.runtime.arguments import RosArguments

__all__ = [
    "CLOCK_SOURCE",
    "DeclareLaunchArgument",
    "LaunchConfiguration",
    "LaunchDescription",
    "LaunchDescriptionError",
    "Node",
    "register_executable",
    "resolve_factory",
]


class LaunchDescriptionError(ValueError):
    """A launch description or launch file is malformed."""


#: The class attribute (set True) of a node class that simulates the world, posekit's
#: ``WorldSimulation``: a launch that runs one steps simulated time itself and owns
#: ``/clock``, the role Gazebo has in ROS. A launch of other nodes only can follow the
#: ``/clock`` of a simulation already running (:meth:`LaunchDescription.has_clock_source`).
CLOCK_SOURCE = "posekit_clock_source"


_executables: dict[tuple[str, str], Callable[[], Any] | str] = {}


def register_executable(package: str, executable: str, factory: Callable[[], Any] | str) -> None:
    """Make ``Node(package=..., executable=...)`` resolvable.

    This is how ``ros2 run`` names map to posekit node factories.
    """
    _executables[(package, executable)] = factory


def _load_file_module(path: Path) -> Any:
    """The module of a Python file (a node script next to a launch file), loaded once."""
    path = path.resolve()
    name = f"posekit_launch_node_{path.stem}_{abs(hash(str(path))):x}"
    if name in sys.modules:
        return sys.modules[name]
    if not path.is_file():
        raise LaunchDescriptionError(f"node file {path} does not exist")
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise LaunchDescriptionError(f"cannot load {path} as Python")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[name]
        raise
    return module


def resolve_factory(target: Callable[[], Any] | str) -> Callable[[], Any]:
    """A callable from a callable, a ``"module:attr"`` string, or ``"path/file.py:attr"``.

    The last form is a node script that is not an installed module, e.g. one next to the launch
    file: ``f"{Path(__file__).with_name('my_node.py')}:MyNode"``.
    """
    if callable(target):
        return target
    if isinstance(target, str) and ":" in target:
        module_name, _, attr = target.rpartition(":")
        obj: Any
        if module_name.endswith(".py"):
            obj = _load_file_module(Path(module_name))
        else:
            try:
                obj = importlib.import_module(module_name)
            except ImportError as exc:
                raise LaunchDescriptionError(f"cannot import {module_name!r}: {exc}") from exc
        for part in attr.split("."):
            obj = getattr(obj, part, None)
            if obj is None:
                raise LaunchDescriptionError(f"{target!r}: no attribute {part!r}")
        if not callable(obj):
            raise LaunchDescriptionError(f"{target!r} is not callable")
        return obj  # type: ignore[no-any-return]
    raise LaunchDescriptionError(
        f"expected a node class, a factory or 'module:attr', got {target!r}"
    )


@dataclass(frozen=True)
class LaunchConfiguration:
    """The value of a launch argument, resolved when the description runs."""

    name: str
    default: Any = None


@dataclass(frozen=True)
class DeclareLaunchArgument:
    """Declare a launch argument ``name:=value`` with an optional default."""

    name: str
    default_value: Any = None
    description: str = ""


def _parameter_entries(item: Mapping[str, Any] | str | Path,
                       dict_key: str) -> list[tuple[str, dict[str, Any]]]:
    """``(node name pattern, {name: value})`` entries of one ``parameters=`` item.

    A dict is one entry under ``dict_key`` (nested mappings flattened to ``a.b``). A file is
    read as rcl reads ``--params-file`` (what launch_ros passes): sections by node name,
    made absolute and matched against each node's fully qualified name with wildcards when
    the node is created, values typed by rcl's rules.
    """
    if isinstance(item, Mapping):
        return [(dict_key, _flatten(item))]
    from posekit.runtime.arguments import RCLError, load_parameter_file

    try:
        return load_parameter_file(item)
    except RCLError as exc:  # its text names the file
        raise LaunchDescriptionError(str(exc)) from None


def _flatten(params: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    out: dict[str, Any] = {}
    for k, v in params.items():
        key = f"{prefix}{k}"
        if isinstance(v, Mapping):
            out.update(_flatten(v, key + "."))
        else:
            out[key] = v
    return out


@dataclass
class Node:
    """One node (or node factory) to run.

    Args:
        package_or_callable: node class / factory / ``"module:attr"``; or use
            ``package=``/``executable=`` for a registered executable.
        name: overrides the node name(s) the factory chooses.
        namespace: namespace for the node(s).
        parameters: dicts and/or YAML parameter files (``node: ros__parameters: ...``),
            applied in order; a dict reaches the entry's node(s), a file's sections the nodes
            whose fully qualified name they match (``/**``, ``/*``, ``/ns/*``, ``/ns/name``;
            ``name`` is ``/name``), as ``--params-file`` does; values may be
            :class:`LaunchConfiguration`.
        remappings: ``[("from", "to"), ...]`` or ``["from:=to"]``.
    """

    package_or_callable: Callable[[], Any] | str | None = None
    name: str | None = None
    namespace: str | None = None
    parameters: Sequence[Mapping[str, Any] | str | Path] | Mapping[str, Any] = field(
        default_factory=list
    )
    remappings: Sequence[tuple[str, str] | str] = field(default_factory=list)
    package: str | None = None
    executable: str | None = None
    output: str = "screen"

    def factory(self) -> Callable[[], Any]:
        """The callable creating the node(s)."""
        if self.package_or_callable is not None:
            return resolve_factory(self.package_or_callable)
        if self.package and self.executable:
            target = _executables.get((self.package, self.executable))
            if target is None:
                raise LaunchDescriptionError(
                    f"no executable '{self.executable}' registered for package '{self.package}'"
                )
            return resolve_factory(target)
        raise LaunchDescriptionError("Node needs package_or_callable or package+executable")

    def is_clock_source(self) -> bool:
        """Whether this entry runs a node class marked as a clock source (:data:`CLOCK_SOURCE`).

        A factory that is not such a class (a function, a class without the mark) is not;
        an entry that does not resolve is not either (creating its node reports that).
        """
        try:
            factory = self.factory()
        except LaunchDescriptionError:
            return False
        return getattr(factory, CLOCK_SOURCE, False) is True

    def resolved_parameters(self, arguments: Mapping[str, Any]) -> RosArguments:
        """The parameter entries of ``parameters``, launch configurations substituted.

        In order, merged as rcl merges several ``--params-file`` (launch_ros passes each item
        as one): ``RosArguments.parameters_for(fqn)`` gives a node's values. As launch_ros
        writes a dict into its file, a dict's section is the node's fully qualified name when
        both ``name`` and ``namespace`` are given, else ``/**``.
        """
        from posekit.runtime.arguments import RosArguments
        from posekit.runtime.names import normalize_namespace

        items: Iterable[Mapping[str, Any] | str | Path]
        items = [self.parameters] if isinstance(self.parameters, Mapping) else self.parameters
        dict_key = "/**"
        if self.name and self.namespace:
            dict_key = f"{normalize_namespace(self.namespace).rstrip('/')}/{self.name}"
        out = RosArguments()
        for item in items:
            for pattern, values in _parameter_entries(item, dict_key):
                out.add_parameters(pattern, {k: _substitute(v, arguments)
                                             for k, v in values.items()})
        return out


def _substitute(value: Any, arguments: Mapping[str, Any]) -> Any:
    if isinstance(value, LaunchConfiguration):
        if value.name in arguments:
            return arguments[value.name]
        if value.default is not None:
            return value.default
        raise LaunchDescriptionError(f"launch argument '{value.name}' has no value")
    return value


class LaunchDescription:
    """An ordered list of :class:`Node` and :class:`DeclareLaunchArgument` entries."""

    def __init__(self, entities: Iterable[Node | DeclareLaunchArgument] = ()) -> None:
        self.entities: list[Node | DeclareLaunchArgument] = []
        for e in entities:
            self.add_action(e)

    def add_action(self, entity: Node | DeclareLaunchArgument) -> None:
        """Append an entry."""
        if not isinstance(entity, Node | DeclareLaunchArgument):
            raise LaunchDescriptionError(
                f"launch entries must be posekit.launch Node or DeclareLaunchArgument, "
                f"got {entity!r}"
            )
        self.entities.append(entity)

    add_entity = add_action

    @property
    def nodes(self) -> list[Node]:
        """The node entries."""
        return [e for e in self.entities if isinstance(e, Node)]

    def has_clock_source(self) -> bool:
        """Whether the description runs a world of its own (see :data:`CLOCK_SOURCE`)."""
        return any(entry.is_clock_source() for entry in self.nodes)

    def arguments(self, given: Mapping[str, Any] | None = None) -> dict[str, Any]:
        """Declared defaults overridden by ``given``."""
        out = {
            e.name: e.default_value
            for e in self.entities
            if isinstance(e, DeclareLaunchArgument) and e.default_value is not None
        }
        out.update(given or {})
        return out
