"""Node parameters as rclpy has them: declare, get, set, descriptors, callbacks, events.

The rules are rclpy's (Jazzy), checked by the differential suite in tests/rclpy:

* ``declare_parameter(name, value)`` fixes the parameter's type from ``value`` (static
  typing); ``declare_parameter(name, Parameter.Type.INTEGER)`` declares a typed parameter
  without a value (``get_parameter`` then raises :class:`ParameterUninitializedException`);
  ``ParameterDescriptor(dynamic_typing=True)`` lets the type change. A launch /
  ``parameter_overrides`` value for that name wins over the default unless
  ``ignore_override=True``.
* ``set_parameters([...])`` returns one ``SetParametersResult`` per parameter; a value of
  another type, a read-only parameter, a value outside the descriptor's integer or floating
  point range and a veto of an on-set callback are refused with rclpy's reason strings.
  Setting a value of ``None`` (type NOT_SET) undeclares a dynamically typed parameter and is
  refused for a statically typed one ("Static parameter cannot be undeclared").
* Every successful declare/set is published as an ``rcl_interfaces/msg/ParameterEvent``
  through the hook the node installs (``/parameter_events``).

An override of another type than the declared one (an integer from a launch file,
``--ros-args -p`` or ``parameter_overrides`` for a DOUBLE parameter included) raises
:class:`InvalidParameterTypeException` with rclpy's text, as rclpy does.

posekit deviation (listed in docs/runtime.md): numpy scalars and arrays are accepted as
values and stored as Python numbers and lists.
"""

from __future__ import annotations

import array
import enum
import math
import warnings
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from posekit.msgs.rcl_interfaces import (
    FloatingPointRange,
    IntegerRange,
    ListParametersResult,
    ParameterDescriptor,
    ParameterEvent,
    ParameterType,
    ParameterValue,
    SetParametersResult,
)
from posekit.msgs.rcl_interfaces import Parameter as ParameterMsg
from posekit.runtime.arguments import (
    compose_parameter_file,
    flatten_parameters,
    parse_parameter_value,
)

if TYPE_CHECKING:
    from posekit.runtime.node import Node

__all__ = [
    "PARAMETER_SEPARATOR_STRING",
    "InvalidParameterException",
    "InvalidParameterTypeException",
    "InvalidParameterValueException",
    "Parameter",
    "ParameterAlreadyDeclaredException",
    "ParameterDescriptor",
    "ParameterException",
    "ParameterImmutableException",
    "ParameterNotDeclaredException",
    "ParameterStore",
    "ParameterUninitializedException",
    "SetParametersResult",
    "declare_value",
    "get_parameter_value",
    "parameter_dict_from_yaml_file",
    "parameter_value_to_python",
    "parse_parameter_value",
    "validate_parameter_name",
]

#: Separates the parts of a nested parameter name (``robot.wheel.radius``).
PARAMETER_SEPARATOR_STRING = "."
#: Relative tolerance of floating point range checks (rclpy's ``Node.PARAM_REL_TOL``).
PARAM_REL_TOL = 1e-6


# -- exceptions (rclpy.exceptions' classes and messages) -------------------------------------
class ParameterException(Exception):  # noqa: N818 - rclpy name
    """Base of the parameter errors: ``"<what>: <parameter name(s)>"``."""

    def __init__(self, error_msg: str, parameters: str | list[str]) -> None:
        super().__init__(f"{error_msg}: {parameters}")


class ParameterNotDeclaredException(ParameterException):
    """Get/set of a parameter that was never declared (undeclared ones not allowed)."""

    def __init__(self, parameters: str | list[str]) -> None:
        super().__init__("Invalid access to undeclared parameter(s)", parameters)
        self.name = parameters


class ParameterAlreadyDeclaredException(ParameterException):
    """declare_parameter for a name that is already declared."""

    def __init__(self, parameters: str | list[str]) -> None:
        super().__init__("Parameter(s) already declared", parameters)
        self.name = parameters


class InvalidParameterException(ParameterException):
    """A parameter name that cannot be declared (the empty name)."""

    def __init__(self, parameter_name: str) -> None:
        super().__init__("Invalid parameter name", parameter_name)


def validate_parameter_name(name: str) -> Literal[True]:
    """True, unless ``name`` is empty (``InvalidParameterException``): rclpy's only rule."""
    if not name:
        raise InvalidParameterException(name)
    return True


class InvalidParameterTypeException(ParameterException):
    """A declared default or override of another type than the declared one."""

    def __init__(self, desired_parameter: Parameter, expected_type: Any) -> None:
        found = Type.from_parameter_value(desired_parameter.value).name
        super().__init__(
            f"Trying to set parameter '{desired_parameter.name}' to "
            f"'{desired_parameter.value}' of type '{found}', expecting type '{expected_type}'",
            desired_parameter.name,
        )


class InvalidParameterValueException(ParameterException):
    """A value refused at declare time (by a descriptor's range or an on-set callback)."""

    def __init__(self, parameter: str, value: Any, reason: str) -> None:
        super().__init__(
            f"Invalid parameter value ({value}) for parameter. Reason: {reason}", parameter
        )


class ParameterImmutableException(ParameterException):
    """Undeclaring a read-only parameter."""

    def __init__(self, parameter_name: str) -> None:
        super().__init__("Attempted to modify read-only parameter", parameter_name)


class ParameterUninitializedException(ParameterException):
    """get_parameter of a statically typed parameter declared without a value."""

    def __init__(self, parameter_name: str) -> None:
        super().__init__(f"The parameter '{parameter_name}' is not initialized", parameter_name)


# -- values ------------------------------------------------------------------------------
def _plain(value: Any) -> Any:
    """numpy scalars and arrays as Python numbers and lists (a posekit extension)."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, list | tuple) and any(isinstance(v, np.generic) for v in value):
        return type(value)(v.item() if isinstance(v, np.generic) else v for v in value)
    return value


class Type(enum.Enum):
    """rclpy's ``Parameter.Type``: the ParameterType constants as an enum."""

    NOT_SET = ParameterType.PARAMETER_NOT_SET
    BOOL = ParameterType.PARAMETER_BOOL
    INTEGER = ParameterType.PARAMETER_INTEGER
    DOUBLE = ParameterType.PARAMETER_DOUBLE
    STRING = ParameterType.PARAMETER_STRING
    BYTE_ARRAY = ParameterType.PARAMETER_BYTE_ARRAY
    BOOL_ARRAY = ParameterType.PARAMETER_BOOL_ARRAY
    INTEGER_ARRAY = ParameterType.PARAMETER_INTEGER_ARRAY
    DOUBLE_ARRAY = ParameterType.PARAMETER_DOUBLE_ARRAY
    STRING_ARRAY = ParameterType.PARAMETER_STRING_ARRAY

    @classmethod
    def from_parameter_value(cls, parameter_value: Any) -> Type:
        """The type of a Python value (TypeError for values no parameter can hold).

        An empty list is a BYTE_ARRAY, as in rclpy.
        """
        value = _plain(parameter_value)
        if value is None:
            return cls.NOT_SET
        if isinstance(value, bool):
            return cls.BOOL
        if isinstance(value, int):
            return cls.INTEGER
        if isinstance(value, float):
            return cls.DOUBLE
        if isinstance(value, str):
            return cls.STRING
        if isinstance(value, list | tuple | array.array):
            for kind, python_type in (
                (cls.BYTE_ARRAY, bytes), (cls.BOOL_ARRAY, bool), (cls.INTEGER_ARRAY, int),
                (cls.DOUBLE_ARRAY, float), (cls.STRING_ARRAY, str),
            ):
                if all(isinstance(v, python_type) for v in value):
                    return kind
            raise TypeError(
                f"The given value is not a list of one of the allowed types '{value}'."
            )
        raise TypeError(f"The given value is not one of the allowed types '{value}'.")

    def check(self, parameter_value: Any) -> bool:
        """Whether ``parameter_value`` is a value of this type."""
        value = _plain(parameter_value)
        sequence = (list, tuple)
        numeric_sequence = (list, tuple, array.array)
        if self is Type.NOT_SET:
            return value is None
        if self is Type.BOOL:
            return isinstance(value, bool)
        if self is Type.INTEGER:
            return isinstance(value, int)
        if self is Type.DOUBLE:
            return isinstance(value, float)
        if self is Type.STRING:
            return isinstance(value, str)
        if self is Type.BYTE_ARRAY:
            return isinstance(value, sequence) and all(
                isinstance(v, bytes) and len(v) == 1 for v in value
            )
        if self is Type.BOOL_ARRAY:
            return isinstance(value, sequence) and all(isinstance(v, bool) for v in value)
        if self is Type.INTEGER_ARRAY:
            return isinstance(value, numeric_sequence) and all(isinstance(v, int) for v in value)
        if self is Type.DOUBLE_ARRAY:
            return isinstance(value, numeric_sequence) and all(
                isinstance(v, float) for v in value
            )
        return isinstance(value, sequence) and all(isinstance(v, str) for v in value)


_TypeEnum = Type  # for annotations inside classes that have a ``Type`` attribute

_VALUE_FIELDS = {
    Type.BOOL: "bool_value",
    Type.INTEGER: "integer_value",
    Type.DOUBLE: "double_value",
    Type.STRING: "string_value",
    Type.BYTE_ARRAY: "byte_array_value",
    Type.BOOL_ARRAY: "bool_array_value",
    Type.INTEGER_ARRAY: "integer_array_value",
    Type.DOUBLE_ARRAY: "double_array_value",
    Type.STRING_ARRAY: "string_array_value",
}


def parameter_value_to_python(parameter_value: ParameterValue) -> Any:
    """The Python value of a ``ParameterValue`` message (None for NOT_SET).

    Array fields come back as lists (``byte_array_value`` as a list of 1-byte ``bytes``,
    rclpy's form) whether the message holds lists or numpy arrays.
    """
    try:
        kind = Type(parameter_value.type)
    except ValueError:
        raise RuntimeError(f"unexpected parameter type {parameter_value.type}") from None
    if kind is Type.NOT_SET:
        return None
    value = getattr(parameter_value, _VALUE_FIELDS[kind])
    if kind is Type.BYTE_ARRAY:
        if isinstance(value, bytes | bytearray):
            return [bytes([b]) for b in value]
        return [v if isinstance(v, bytes) else bytes([int(v) & 0xFF]) for v in value]
    if kind is Type.BOOL_ARRAY:
        return [bool(v) for v in value]
    if kind is Type.INTEGER_ARRAY:
        return [int(v) for v in value]
    if kind is Type.DOUBLE_ARRAY:
        return [float(v) for v in value]
    if kind is Type.STRING_ARRAY:
        return [str(v) for v in value]
    if kind is Type.BOOL:
        return bool(value)
    if kind is Type.INTEGER:
        return int(value)
    if kind is Type.DOUBLE:
        return float(value)
    return str(value)


class Parameter:
    """A named, typed value (rclpy.parameter.Parameter)."""

    Type = Type

    __slots__ = ("_name", "_type_", "_value")

    def __init__(self, name: str, type_: _TypeEnum | None = None, value: Any = None) -> None:
        value = _plain(value)
        if type_ is None:
            type_ = Type.from_parameter_value(value)
        if not isinstance(type_, Type):
            raise TypeError(f"type must be an instance of '{Type!r}'")
        if not type_.check(value):
            raise ValueError(f"Type '{type_}' and value '{value}' do not agree")
        self._name = name
        self._type_ = type_
        self._value = value

    @classmethod
    def from_parameter_msg(cls, param_msg: ParameterMsg) -> Parameter:
        """The Parameter an ``rcl_interfaces/msg/Parameter`` carries."""
        value = parameter_value_to_python(param_msg.value)
        return cls(param_msg.name, Type(param_msg.value.type), value)

    @property
    def name(self) -> str:
        """The parameter's name."""
        return self._name

    @property
    def type_(self) -> _TypeEnum:
        """The parameter's type."""
        return self._type_

    @property
    def value(self) -> Any:
        """The value (None when NOT_SET)."""
        return self._value

    def get_parameter_value(self) -> ParameterValue:
        """The value as an ``rcl_interfaces/msg/ParameterValue``."""
        msg = ParameterValue(type=self._type_.value)
        if self._type_ is not Type.NOT_SET:
            value = self._value
            if isinstance(value, tuple | array.array):
                value = list(value)
            setattr(msg, _VALUE_FIELDS[self._type_], value)
        return msg

    def to_parameter_msg(self) -> ParameterMsg:
        """The parameter as an ``rcl_interfaces/msg/Parameter``."""
        return ParameterMsg(name=self._name, value=self.get_parameter_value())

    def __repr__(self) -> str:
        return f"Parameter({self._name!r}, {self._type_}, {self._value!r})"

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Parameter):
            return NotImplemented
        return (self._name, self._type_, self._value) == (other._name, other._type_, other._value)

    def __hash__(self) -> int:
        return hash((self._name, self._type_))


def get_parameter_value(string_value: str) -> ParameterValue:
    """The ParameterValue a command-line string means (rclpy's ``get_parameter_value``).

    What ``ros2 param set`` uses: the text is parsed as YAML; a bool, int, float or a list of
    one of them (or of strings) keeps that type, anything else is a STRING (the text itself).
    """
    import yaml

    msg = ParameterValue()
    try:
        parsed = yaml.safe_load(string_value)
    except yaml.YAMLError:
        parsed = string_value
    if isinstance(parsed, bool):
        msg.type, msg.bool_value = ParameterType.PARAMETER_BOOL, parsed
    elif isinstance(parsed, int):
        msg.type, msg.integer_value = ParameterType.PARAMETER_INTEGER, parsed
    elif isinstance(parsed, float):
        msg.type, msg.double_value = ParameterType.PARAMETER_DOUBLE, parsed
    elif isinstance(parsed, list) and all(isinstance(v, bool) for v in parsed):
        msg.type = ParameterType.PARAMETER_BOOL_ARRAY
        msg.bool_array_value = np.array(parsed, dtype=np.bool_)
    elif isinstance(parsed, list) and all(isinstance(v, int) for v in parsed):
        msg.type = ParameterType.PARAMETER_INTEGER_ARRAY
        msg.integer_array_value = np.array(parsed, dtype=np.int64)
    elif isinstance(parsed, list) and all(isinstance(v, float) for v in parsed):
        msg.type = ParameterType.PARAMETER_DOUBLE_ARRAY
        msg.double_array_value = np.array(parsed, dtype=np.float64)
    elif isinstance(parsed, list) and all(isinstance(v, str) for v in parsed):
        msg.type, msg.string_array_value = ParameterType.PARAMETER_STRING_ARRAY, parsed
    else:
        msg.type = ParameterType.PARAMETER_STRING
        msg.string_value = (
            parsed if isinstance(parsed, str) and not isinstance(parsed, list) else string_value
        )
    return msg


def parameter_dict_from_yaml_file(
    parameter_file: str, use_wildcard: bool = False, target_nodes: list[str] | None = None,
    namespace: str = "",
) -> dict[str, ParameterMsg]:
    """Parameters of a ROS parameter file (``node: {ros__parameters: {...}}``) by name.

    rclpy's function, with rclpy's rules where they differ from rcl's ``--params-file``
    (:func:`~posekit.runtime.arguments.load_parameter_file`, which owns the file's walk):
    the top-level keys are taken literally (no namespace nesting, no wildcard matching);
    every key's section unless ``target_nodes`` picks some, plus the ``/**`` section first
    with ``use_wildcard``; sections are merged one parameter name at a time (a later
    section's ``pid: {...}`` replaces an earlier one whole); nested mappings become dotted
    names prefixed with ``namespace``; each value is typed as YAML 1.1 reads it, then through
    :func:`get_parameter_value` of its ``str()`` (so ``'1'`` quoted is an INTEGER here, a
    STRING for rcl). ``OSError`` / ``yaml.YAMLError`` for an unreadable file; RuntimeError
    for a file that is not a parameter file or lacks a requested node.
    """
    import yaml

    root = compose_parameter_file(parameter_file)
    if not isinstance(root, yaml.MappingNode):
        raise RuntimeError(f"{parameter_file} is not a ROS parameter file (no node sections)")
    content = {str(key.value): section for key, section in root.value}  # last one wins
    keys: list[str] = []
    if use_wildcard and "/**" in content:
        keys.append("/**")
    if target_nodes:
        for node in target_nodes:
            if node not in content:
                raise RuntimeError(
                    f"Param file does not contain parameters for {node},"
                    f"only for nodes: {list(content.keys())} "
                )
            keys.append(node)
    else:
        keys.extend(key for key in content if key != "/**")
    if not keys:
        raise RuntimeError("Param file does not contain selected parameters")
    merged: dict[str, tuple[Any, Any]] = {}
    for key in keys:
        section = content[key]
        values = None
        if isinstance(section, yaml.MappingNode):
            values = {str(k.value): v for k, v in section.value}.get("ros__parameters")
        if not isinstance(values, yaml.MappingNode):
            raise RuntimeError(f"YAML file is not a valid ROS parameter file for node {key}")
        merged.update({str(k.value): (k, v) for k, v in values.value})
    constructor = yaml.constructor.SafeConstructor()

    def typed(node: Any, name: str) -> ParameterMsg:
        value = constructor.construct_object(node, deep=True)
        return ParameterMsg(name=name, value=get_parameter_value(str(value)))

    return flatten_parameters(
        yaml.MappingNode("tag:yaml.org,2002:map", list(merged.values())), typed, namespace)


def _declaration_tuple(
    namespace: str, index: int, item: tuple[Any, ...],
) -> tuple[str, Any, ParameterDescriptor]:
    """``(full name, value or Type, descriptor)`` of one ``declare_parameters`` tuple.

    rclpy's TypeErrors for a malformed one; a name alone declares a dynamically typed parameter
    (deprecated).
    """
    if not 1 <= len(item) <= 3:
        raise TypeError(
            f"Invalid parameter tuple length at index {index} in parameters list: "
            f"{item}; expecting length between 1 and 3"
        )
    name = item[0]
    if not isinstance(name, str):
        raise TypeError(
            f"First element {name} at index {index} in parameters list is not a str."
        )
    if namespace:
        name = f"{namespace}.{name}"
    validate_parameter_name(name)
    second = item[1] if len(item) > 1 else None
    descriptor = item[2] if len(item) > 2 else ParameterDescriptor()
    if not isinstance(descriptor, ParameterDescriptor):
        raise TypeError(
            f"Third element {descriptor} at index {index} in parameters list "
            "is not a ParameterDescriptor."
        )
    if len(item) == 1:
        warnings.warn(
            f"when declaring parameter named '{name}', declaring a parameter only "
            "providing its name is deprecated; pass a default value, a parameter "
            "type or a descriptor with dynamic_typing=True",
            stacklevel=4,
        )
        descriptor.dynamic_typing = True
    return name, second, descriptor


def _declared_default(name: str, second: Any, descriptor: ParameterDescriptor) -> Any:
    """The default value a declaration gives (None for a ``Parameter.Type``).

    Fixes the descriptor's type unless it is dynamically typed. ValueError as rclpy's.
    """
    if isinstance(second, Type):
        if second is Type.NOT_SET:
            raise ValueError(
                f"Cannot declare parameter {{{name}}} as statically typed of type NOT_SET"
            )
        if descriptor.dynamic_typing:
            raise ValueError(
                f"When declaring parameter {{{name}}} passing a descriptor with"
                "`dynamic_typing=True` is not allowed when the parameter type is provided"
            )
        descriptor.type = second.value
        return None
    value = second.value if isinstance(second, Parameter) else second
    if isinstance(value, ParameterValue):
        value = parameter_value_to_python(value)
    if not descriptor.dynamic_typing:
        descriptor.type = Type.from_parameter_value(value).value
        if descriptor.type == ParameterType.PARAMETER_NOT_SET:
            raise ValueError(
                "Cannot declare a statically typed parameter with default value "
                "of type PARAMETER_NOT_SET"
            )
    return value


OnSetCallback = Callable[[list[Parameter]], SetParametersResult]
PreSetCallback = Callable[[list[Parameter]], list[Parameter]]
PostSetCallback = Callable[[list[Parameter]], None]
EventSink = Callable[[ParameterEvent], None]


def _as_overrides(
    overrides: Iterable[Parameter] | Mapping[str, Any] | None,
) -> dict[str, Parameter]:
    if overrides is None:
        return {}
    if isinstance(overrides, Mapping):
        return {str(k): Parameter(str(k), value=v) for k, v in overrides.items()}
    return {p.name: p for p in overrides}


@dataclass
class ParameterStore:
    """The parameters of one node (used by :class:`posekit.runtime.node.Node`)."""

    node_name: str
    overrides: dict[str, Parameter] = field(default_factory=dict)
    allow_undeclared: bool = False
    #: Receives a ParameterEvent (node and stamp left for the node to fill) per change.
    on_event: EventSink | None = None
    _params: dict[str, Parameter] = field(default_factory=dict)
    _descriptors: dict[str, ParameterDescriptor] = field(default_factory=dict)
    _pre_set: list[PreSetCallback] = field(default_factory=list)
    _on_set: list[OnSetCallback] = field(default_factory=list)
    _post_set: list[PostSetCallback] = field(default_factory=list)

    @classmethod
    def create(
        cls,
        node_name: str,
        overrides: Iterable[Parameter] | Mapping[str, Any] | None,
        allow_undeclared: bool = False,
    ) -> ParameterStore:
        """A store with overrides given as Parameters or a ``{name: value}`` mapping."""
        return cls(node_name, _as_overrides(overrides), allow_undeclared)

    # -- declare ----------------------------------------------------------------------
    def declare(
        self,
        name: str,
        value: Any = None,
        descriptor: ParameterDescriptor | None = None,
        ignore_override: bool = False,
    ) -> Parameter:
        """Declare ``name`` with default ``value`` (or a ``Parameter.Type``)."""
        if value is None and descriptor is None:
            args: tuple[Any, ...] = (name,)
        else:
            args = (name, value, descriptor if descriptor is not None else ParameterDescriptor())
        return self.declare_many("", [args], ignore_override)[0]

    def declare_many(
        self,
        namespace: str,
        parameters: Sequence[tuple[Any, ...]],
        ignore_override: bool = False,
    ) -> list[Parameter]:
        """rclpy's ``declare_parameters``: ``(name[, value or Type[, descriptor]])`` tuples."""
        declared: list[Parameter] = []
        descriptors: dict[str, ParameterDescriptor] = {}
        for index, item in enumerate(parameters):
            name, second, descriptor = _declaration_tuple(namespace, index, item)
            value = _declared_default(name, second, descriptor)
            if not ignore_override and name in self.overrides:
                value = self.overrides[name].value  # an INTEGER for a DOUBLE fails, as rclpy
            declared.append(Parameter(name, value=value))
            descriptors[name] = descriptor
        already = [p.name for p in declared if p.name in self._params]
        if already:
            raise ParameterAlreadyDeclaredException(already)
        for param in declared:
            result = self._set_common([param], descriptors, allow_not_set=True)
            if not result.successful:
                if result.reason.startswith("Wrong parameter type"):
                    raise InvalidParameterTypeException(
                        param, Type(descriptors[param.name].type).name
                    )
                raise InvalidParameterValueException(param.name, param.value, result.reason)
        return [self._params[p.name] for p in declared]

    def undeclare(self, name: str) -> None:
        """Remove a declared parameter (read-only ones refuse)."""
        if name not in self._params:
            raise ParameterNotDeclaredException(name)
        if self._descriptors[name].read_only:
            raise ParameterImmutableException(name)
        del self._params[name]
        del self._descriptors[name]

    # -- read -------------------------------------------------------------------------
    def has(self, name: str) -> bool:
        """Whether ``name`` is declared."""
        return name in self._params

    def get(self, name: str) -> Parameter:
        """The declared parameter ``name`` (rclpy's get_parameter rules)."""
        param = self._params.get(name)
        if param is not None:
            if param.type_ is not Type.NOT_SET or self._descriptors[name].dynamic_typing:
                return param
            raise ParameterUninitializedException(name)
        if self.allow_undeclared:
            return Parameter(name, Type.NOT_SET, None)
        raise ParameterNotDeclaredException(name)

    def get_or(self, name: str, alternative: Parameter | None = None) -> Parameter:
        """The parameter, or ``alternative`` (default a NOT_SET one) if undeclared or unset."""
        if alternative is None:
            alternative = Parameter(name, Type.NOT_SET)
        param = self._params.get(name)
        if param is None or param.type_ is Type.NOT_SET:
            return alternative
        return param

    def get_type(self, name: str) -> int | _TypeEnum:
        """The ParameterType constant of ``name``.

        ``Type.NOT_SET`` (the enum, as rclpy returns it) for an undeclared name when undeclared
        parameters are allowed.
        """
        if name in self._params:
            return int(self._params[name].type_.value)
        if self.allow_undeclared:
            return Type.NOT_SET
        raise ParameterNotDeclaredException(name)

    def names(self) -> list[str]:
        """Declared names in declaration order."""
        return list(self._params)

    def items(self) -> list[tuple[str, Parameter]]:
        """Declared ``(name, parameter)`` pairs in declaration order."""
        return list(self._params.items())

    def descriptor(self, name: str) -> ParameterDescriptor:
        """The descriptor of a declared parameter (a default one if undeclared is allowed)."""
        try:
            return self._descriptors[name]
        except KeyError:
            if self.allow_undeclared:
                return ParameterDescriptor()
            raise ParameterNotDeclaredException(name) from None

    def list_names(self, prefixes: list[str], depth: int) -> ListParametersResult:
        """rclpy's ``list_parameters``: names under ``prefixes`` down to ``depth`` levels."""
        if not isinstance(prefixes, list):
            raise TypeError("The prefixes argument must be a list")
        if not all(isinstance(p, str) for p in prefixes):
            raise TypeError("All prefixes must be instances of type str")
        if not isinstance(depth, int):
            raise TypeError("The depth must be instance of type int")
        if depth < 0:
            raise ValueError("The depth must be greater than or equal to zero")
        sep = PARAMETER_SEPARATOR_STRING

        def shallow(name: str) -> bool:
            return name.count(sep) < depth

        result = ListParametersResult()
        recursive = not prefixes and depth == 0
        for name in self._params:
            if not recursive and not (not prefixes and shallow(name)) and not any(
                name == prefix
                or (
                    name.startswith(prefix + sep)
                    and (depth == 0 or shallow(name[len(prefix) + 1:]))
                )
                for prefix in prefixes
            ):
                continue
            result.names.append(name)
            cut = name.rfind(sep)
            if cut != -1 and name[:cut] not in result.prefixes:
                result.prefixes.append(name[:cut])
        return result

    # -- set --------------------------------------------------------------------------
    def set(self, params: Sequence[Parameter]) -> list[SetParametersResult]:
        """Set each parameter on its own; one result each (undeclared names raise)."""
        return [self.set_atomically([p]) for p in params]

    def set_atomically(self, params: Sequence[Parameter]) -> SetParametersResult:
        """All or nothing; pre-set callbacks may rewrite the list first."""
        plist = list(params)
        if self._pre_set:
            modified: list[Parameter] = []
            for pre in self._pre_set:
                modified.extend(pre(plist))
            plist = modified
            if not plist:
                return SetParametersResult(
                    successful=False,
                    reason="parameter list cannot be empty, this might be due to "
                    "pre_set_parameters_callback modifying the original parameters list.",
                )
        if not all(isinstance(p, Parameter) for p in plist):
            raise TypeError(f"parameter must be instance of type '{Parameter!r}'")
        undeclared = [p.name for p in plist if p.name not in self._params]
        if undeclared and not self.allow_undeclared:
            # rclpy names the undeclared parameters *after* the first one (its generator is
            # consumed by the check): the same text here
            raise ParameterNotDeclaredException(undeclared[1:])
        return self._set_common(plist, None, allow_not_set=False)

    def _apply_descriptor(
        self, param: Parameter, descriptor: ParameterDescriptor, check_read_only: bool
    ) -> SetParametersResult:
        descriptor.name = param.name
        if check_read_only and descriptor.read_only:
            return SetParametersResult(
                successful=False, reason=f"Trying to set a read-only parameter: {param.name}."
            )
        if descriptor.dynamic_typing:
            descriptor.type = param.type_.value
        elif param.name in self._params and param.type_ is Type.NOT_SET:
            return SetParametersResult(
                successful=False, reason="Static parameter cannot be undeclared"
            )
        elif param.type_ is not Type.NOT_SET and param.type_.value != descriptor.type:
            return SetParametersResult(
                successful=False,
                reason=f"Wrong parameter type, expected '{Type(descriptor.type)}' "
                f"got '{param.type_}'",
            )
        if param.type_ is Type.INTEGER and descriptor.integer_range:
            return _check_integer_range(param, descriptor.integer_range[0])
        if param.type_ is Type.DOUBLE and descriptor.floating_point_range:
            return _check_floating_point_range(param, descriptor.floating_point_range[0])
        return SetParametersResult(successful=True)

    def _set_common(
        self,
        plist: list[Parameter],
        descriptors: dict[str, ParameterDescriptor] | None,
        allow_not_set: bool,
    ) -> SetParametersResult:
        table = descriptors if descriptors is not None else self._descriptors
        for param in plist:
            if param.name in table:
                result = self._apply_descriptor(
                    param, table[param.name], check_read_only=descriptors is None
                )
                if not result.successful:
                    return result
        for callback in list(self._on_set):
            result = callback(plist)
            if not isinstance(result, SetParametersResult):
                warnings.warn(
                    "Callback returned an invalid type, it should return SetParameterResult.",
                    stacklevel=4,
                )
                result = SetParametersResult(
                    successful=False, reason="Callback returned an invalid type"
                )
            if not result.successful:
                return result
        event = ParameterEvent()
        for param in plist:
            if not allow_not_set and param.type_ is Type.NOT_SET:
                event.deleted_parameters.append(param.to_parameter_msg())
                self._params.pop(param.name, None)
                self._descriptors.pop(param.name, None)
                continue
            if descriptors is not None:
                self._descriptors[param.name] = descriptors[param.name]
            elif param.name not in self._descriptors:
                self._descriptors[param.name] = ParameterDescriptor(
                    name=param.name, type=param.type_.value, dynamic_typing=True
                )
            if self.get_or(param.name).type_ is Type.NOT_SET:
                event.new_parameters.append(param.to_parameter_msg())
            else:
                event.changed_parameters.append(param.to_parameter_msg())
            self._params[param.name] = param
        if self.on_event is not None:
            self.on_event(event)
        for post in list(self._post_set):
            post(plist)
        return SetParametersResult(successful=True)

    def set_descriptor(
        self, name: str, descriptor: ParameterDescriptor,
        alternative_value: ParameterValue | None = None,
    ) -> ParameterValue:
        """rclpy's ``set_descriptor`` (see :meth:`posekit.runtime.node.Node.set_descriptor`)."""
        if name not in self._params:
            if not self.allow_undeclared:
                raise ParameterNotDeclaredException(name)
            return self.get(name).get_parameter_value()
        if self._descriptors[name].read_only:
            raise ParameterImmutableException(name)
        current = self.get(name)
        alternative = current if alternative_value is None else Parameter.from_parameter_msg(
            ParameterMsg(name=name, value=alternative_value)
        )
        if not self._apply_descriptor(current, descriptor, False).successful:
            result = self._apply_descriptor(alternative, descriptor, False)
            if not result.successful:
                raise InvalidParameterValueException(name, alternative.value, result.reason)
            self._params[name] = alternative
        self._descriptors[name] = descriptor
        return self.get(name).get_parameter_value()

    # -- callbacks --------------------------------------------------------------------
    def add_pre_set(self, callback: PreSetCallback) -> None:
        """Register a callback that may rewrite the list before validation (newest first)."""
        self._pre_set.insert(0, callback)

    def remove_pre_set(self, callback: PreSetCallback) -> None:
        """Remove a pre-set callback (ValueError if unknown)."""
        self._pre_set.remove(callback)

    def add_on_set(self, callback: OnSetCallback) -> None:
        """Register a validating callback (may veto; newest runs first)."""
        if not callable(callback):
            raise TypeError(f"Callback must be callable, got {type(callback)}")
        self._on_set.insert(0, callback)

    def remove_on_set(self, callback: OnSetCallback) -> None:
        """Remove a validating callback (ValueError if unknown)."""
        self._on_set.remove(callback)

    def add_post_set(self, callback: PostSetCallback) -> None:
        """Register a callback run after parameters changed (newest first)."""
        if not callable(callback):
            raise TypeError(f"Callback must be callable, got {type(callback)}")
        self._post_set.insert(0, callback)

    def remove_post_set(self, callback: PostSetCallback) -> None:
        """Remove a post-set callback (ValueError if unknown)."""
        self._post_set.remove(callback)


def _check_integer_range(param: Parameter, rng: IntegerRange) -> SetParametersResult:
    lo, hi = min(rng.from_value, rng.to_value), max(rng.from_value, rng.to_value)
    value = param.value
    if value in (lo, hi):
        return SetParametersResult(successful=True)
    if not lo < value < hi:
        return SetParametersResult(
            successful=False,
            reason=f"Parameter {param.name} out of range. Min: {lo}, Max: {hi}, value: {value}",
        )
    if rng.step != 0 and (value - lo) % rng.step != 0:
        return SetParametersResult(
            successful=False,
            reason=f"The parameter value for {param.name} is not a valid step. "
            f"Min: {lo}, max: {hi}, value: {value}, step: {rng.step}",
        )
    return SetParametersResult(successful=True)


def _check_floating_point_range(param: Parameter, rng: FloatingPointRange) -> SetParametersResult:
    lo, hi = min(rng.from_value, rng.to_value), max(rng.from_value, rng.to_value)
    value = param.value
    if math.isclose(value, lo, rel_tol=PARAM_REL_TOL) or math.isclose(
        value, hi, rel_tol=PARAM_REL_TOL
    ):
        return SetParametersResult(successful=True)
    if not lo < value < hi:
        return SetParametersResult(
            successful=False,
            reason=f"Parameter {param.name} out of range Min: {lo}, Max: {hi}, value: {value}",
        )
    if rng.step != 0.0:
        steps = round((value - lo) / rng.step)
        if not math.isclose(lo + steps * rng.step, value, rel_tol=PARAM_REL_TOL):
            return SetParametersResult(
                successful=False,
                reason=f"The parameter value for {param.name} is not close enough to a valid "
                f"step. Min: {lo}, max: {hi}, value: {value}, step: {rng.step}",
            )
    return SetParametersResult(successful=True)


def declare_value(node: Node, name: str, default: Any) -> Any:
    """Declare parameter ``name`` on ``node`` with ``default`` and return its value.

    A launch or override value wins over ``default``: ``node.declare_parameter(name,
    default).value``, the one line a node writes for each parameter it reads once at start-up.
    """
    return node.declare_parameter(name, default).value
