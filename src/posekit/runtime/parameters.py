"""Node parameters as rclpy has them: declare, get, set, overrides, on-set callbacks.

* ``declare_parameter(name, value)`` fixes the parameter's type from ``value`` (static typing,
  as rclpy since Humble); a launch/``parameter_overrides`` value for that name wins over the
  default (unless ``ignore_override=True``).
* ``get_parameter(name).value``; undeclared names raise :class:`ParameterNotDeclaredException`
  (unless the node allows undeclared parameters).
* ``set_parameters([...])`` returns one :class:`SetParametersResult` per parameter; a value
  of another type is refused (``successful=False`` with the reason), as are read-only ones;
  ``add_on_set_parameters_callback`` callbacks may veto.

posekit deviation: an ``int`` given for a DOUBLE parameter is accepted as ``float`` (rclpy
refuses ``k_rho: 1`` when the default is ``0.5``; launch files written with integers are common).
"""

from __future__ import annotations

import enum
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from posekit.runtime.arguments import parse_parameter_value

__all__ = [
    "InvalidParameterTypeException",
    "InvalidParameterValueException",
    "Parameter",
    "ParameterAlreadyDeclaredException",
    "ParameterDescriptor",
    "ParameterException",
    "ParameterImmutableException",
    "ParameterNotDeclaredException",
    "ParameterStore",
    "SetParametersResult",
    "parse_parameter_value",
]


class ParameterException(Exception):  # noqa: N818 - rclpy name
    """Base of the parameter errors."""


class ParameterNotDeclaredException(ParameterException):
    """Get/set of a parameter that was never declared."""

    def __init__(self, name: str) -> None:
        super().__init__(f"Parameter '{name}' has not been declared (declare_parameter first)")
        self.name = name


class ParameterAlreadyDeclaredException(ParameterException):
    """declare_parameter twice for the same name."""

    def __init__(self, name: str) -> None:
        super().__init__(f"Parameter '{name}' has already been declared")
        self.name = name


class InvalidParameterTypeException(ParameterException, TypeError):  # noqa: N818 - rclpy name
    """A value whose type differs from the declared type."""


class InvalidParameterValueException(ParameterException, ValueError):  # noqa: N818 - rclpy name
    """A value that cannot be a parameter, or one an on-set callback refused at declare time."""


class ParameterImmutableException(ParameterException):
    """Setting a read-only parameter."""


class _Type(enum.IntEnum):
    NOT_SET = 0
    BOOL = 1
    INTEGER = 2
    DOUBLE = 3
    STRING = 4
    BYTE_ARRAY = 5
    BOOL_ARRAY = 6
    INTEGER_ARRAY = 7
    DOUBLE_ARRAY = 8
    STRING_ARRAY = 9

    @classmethod
    def from_parameter_value(cls, value: Any) -> _Type:
        """The parameter type of a Python value (rclpy's rules); unsupported -> TypeError."""
        if value is None:
            return cls.NOT_SET
        if isinstance(value, bool | np.bool_):
            return cls.BOOL
        if isinstance(value, int | np.integer):
            return cls.INTEGER
        if isinstance(value, float | np.floating):
            return cls.DOUBLE
        if isinstance(value, str):
            return cls.STRING
        if isinstance(value, bytes | bytearray):
            return cls.BYTE_ARRAY
        if isinstance(value, list | tuple | np.ndarray):
            items = list(value)
            if all(isinstance(v, bytes) and len(v) == 1 for v in items) and items:
                return cls.BYTE_ARRAY
            if all(isinstance(v, bool | np.bool_) for v in items):
                return cls.BOOL_ARRAY
            if all(isinstance(v, int | np.integer) and not isinstance(v, bool) for v in items):
                return cls.INTEGER_ARRAY
            if all(isinstance(v, float | np.floating) for v in items):
                return cls.DOUBLE_ARRAY
            if all(isinstance(v, str) for v in items):
                return cls.STRING_ARRAY
            raise TypeError(f"parameter arrays must hold one type, got {value!r}")
        raise TypeError(f"type {type(value).__name__} is not a parameter type ({value!r})")


def _normalise(value: Any, type_: _Type) -> Any:
    """Plain Python value for a type (numpy scalars -> Python, arrays -> lists)."""
    if type_ == _Type.BOOL:
        return bool(value)
    if type_ == _Type.INTEGER:
        return int(value)
    if type_ == _Type.DOUBLE:
        return float(value)
    if type_ == _Type.BOOL_ARRAY:
        return [bool(v) for v in value]
    if type_ == _Type.INTEGER_ARRAY:
        return [int(v) for v in value]
    if type_ == _Type.DOUBLE_ARRAY:
        return [float(v) for v in value]
    if type_ == _Type.STRING_ARRAY:
        return [str(v) for v in value]
    if type_ == _Type.BYTE_ARRAY:
        return bytes(value) if isinstance(value, bytes | bytearray) else [bytes(v) for v in value]
    return value


class Parameter:
    """A named, typed value (rclpy.parameter.Parameter)."""

    Type = _Type

    __slots__ = ("_name", "_type", "_value")

    def __init__(self, name: str, type_: _Type | None = None, value: Any = None) -> None:
        if not isinstance(name, str) or not name:
            raise ValueError(f"parameter name must be a non-empty str, got {name!r}")
        if type_ is None:
            type_ = _Type.from_parameter_value(value)
        type_ = _Type(type_)
        found = _Type.from_parameter_value(value)
        widening = {(_Type.DOUBLE, _Type.INTEGER), (_Type.DOUBLE_ARRAY, _Type.INTEGER_ARRAY)}
        if value is not None and type_ != found and (type_, found) not in widening:
            raise InvalidParameterTypeException(
                f"Parameter '{name}': value {value!r} is not of type {type_.name}"
            )
        self._name = name
        self._type = type_
        self._value = None if value is None else _normalise(value, type_)

    @property
    def name(self) -> str:
        """The parameter's name."""
        return self._name

    @property
    def type_(self) -> _Type:
        """The parameter's type."""
        return self._type

    @property
    def value(self) -> Any:
        """The value (None when NOT_SET)."""
        return self._value

    def __repr__(self) -> str:
        return f"Parameter({self._name!r}, {self._type.name}, {self._value!r})"

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Parameter):
            return NotImplemented
        return (self._name, self._type, self._value) == (other._name, other._type, other._value)

    def __hash__(self) -> int:
        return hash((self._name, self._type))


@dataclass(slots=True)
class ParameterDescriptor:
    """rcl_interfaces/msg/ParameterDescriptor (the fields posekit uses)."""

    name: str = ""
    type: int = 0
    description: str = ""
    additional_constraints: str = ""
    read_only: bool = False
    dynamic_typing: bool = False


@dataclass(slots=True)
class SetParametersResult:
    """rcl_interfaces/msg/SetParametersResult."""

    successful: bool = True
    reason: str = ""


OnSetCallback = Callable[[list[Parameter]], SetParametersResult]
PostSetCallback = Callable[[list[Parameter]], None]


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
    _params: dict[str, Parameter] = field(default_factory=dict)
    _descriptors: dict[str, ParameterDescriptor] = field(default_factory=dict)
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

    def _coerce(self, name: str, value: Any, declared: _Type, dynamic: bool) -> Parameter:
        try:
            found = _Type.from_parameter_value(value)
        except TypeError as exc:
            raise InvalidParameterValueException(f"Parameter '{name}': {exc}") from None
        if dynamic or declared == _Type.NOT_SET or found == _Type.NOT_SET or found == declared:
            return Parameter(name, found, value)
        if declared == _Type.DOUBLE and found == _Type.INTEGER:
            return Parameter(name, _Type.DOUBLE, float(value))
        if declared == _Type.DOUBLE_ARRAY and found == _Type.INTEGER_ARRAY:
            return Parameter(name, _Type.DOUBLE_ARRAY, [float(v) for v in value])
        if found == _Type.BOOL_ARRAY and not list(value) and declared.name.endswith("ARRAY"):
            return Parameter(name, declared, [])
        raise InvalidParameterTypeException(
            f"Trying to set parameter '{name}' to {value!r} of type '{found.name}', "
            f"expecting type '{declared.name}'"
        )

    def declare(
        self,
        name: str,
        value: Any = None,
        descriptor: ParameterDescriptor | None = None,
        ignore_override: bool = False,
    ) -> Parameter:
        """Declare ``name`` with default ``value`` (its type fixes the parameter's type)."""
        if not isinstance(name, str) or not name:
            raise InvalidParameterValueException(f"parameter name must be non-empty: {name!r}")
        if name in self._params:
            raise ParameterAlreadyDeclaredException(name)
        if isinstance(value, Parameter):
            value = value.value
        descriptor = descriptor if descriptor is not None else ParameterDescriptor()
        try:
            declared = _Type.from_parameter_value(value)
        except TypeError as exc:
            raise InvalidParameterValueException(f"Parameter '{name}': {exc}") from None
        if descriptor.type:
            declared = _Type(descriptor.type)
        param = self._coerce(name, value, declared, False)
        if not ignore_override and name in self.overrides:
            override = self.overrides[name]
            param = self._coerce(name, override.value, declared, descriptor.dynamic_typing)
        if param.type_ == _Type.NOT_SET and declared != _Type.NOT_SET:
            param = Parameter(name, declared, None)
        result = self._run_on_set([param])
        if not result.successful:
            raise InvalidParameterValueException(
                f"Parameter '{name}' refused by an on-set callback: {result.reason}"
            )
        descriptor.name = name
        descriptor.type = int(declared)
        self._descriptors[name] = descriptor
        self._params[name] = param
        for cb in list(self._post_set):
            cb([param])
        return param

    def has(self, name: str) -> bool:
        """Whether ``name`` is declared."""
        return name in self._params

    def get(self, name: str) -> Parameter:
        """The declared parameter ``name``."""
        try:
            return self._params[name]
        except KeyError:
            if self.allow_undeclared:
                override = self.overrides.get(name)
                return override if override is not None else Parameter(name, _Type.NOT_SET)
            raise ParameterNotDeclaredException(name) from None

    def names(self) -> list[str]:
        """Declared names in declaration order."""
        return list(self._params)

    def descriptor(self, name: str) -> ParameterDescriptor:
        """The descriptor of a declared parameter."""
        if name not in self._descriptors:
            raise ParameterNotDeclaredException(name)
        return self._descriptors[name]

    def _run_on_set(self, params: list[Parameter]) -> SetParametersResult:
        for cb in list(self._on_set):
            result = cb(params)
            if not result.successful:
                return result
        return SetParametersResult(True)

    def _check_one(self, param: Parameter) -> Parameter:
        if param.name not in self._params:
            if not self.allow_undeclared:
                raise ParameterNotDeclaredException(param.name)
            return param
        desc = self._descriptors[param.name]
        if desc.read_only:
            raise ParameterImmutableException(f"Parameter '{param.name}' is read-only")
        declared = self._params[param.name].type_
        if desc.type:
            declared = _Type(desc.type)
        if param.type_ == _Type.NOT_SET and declared != _Type.NOT_SET and (
            not desc.dynamic_typing
        ):
            # rclpy: a None/NOT_SET value would undeclare it, refused for a typed parameter.
            raise InvalidParameterTypeException("Static parameter cannot be undeclared")
        return self._coerce(param.name, param.value, declared, desc.dynamic_typing)

    def set(self, params: Sequence[Parameter]) -> list[SetParametersResult]:
        """Set each parameter independently; one result per parameter (never raises for
        type/read-only problems; undeclared names raise as rclpy does)."""
        results = []
        for p in params:
            results.append(self.set_atomically([p]))
        return results

    def set_atomically(self, params: Sequence[Parameter]) -> SetParametersResult:
        """All or nothing."""
        checked: list[Parameter] = []
        for p in params:
            try:
                checked.append(self._check_one(p))
            except (InvalidParameterTypeException, ParameterImmutableException) as exc:
                return SetParametersResult(False, str(exc))
        result = self._run_on_set(checked)
        if not result.successful:
            return result
        for p in checked:
            self._params[p.name] = p
        for cb in list(self._post_set):
            cb(checked)
        return SetParametersResult(True)

    def undeclare(self, name: str) -> None:
        """Remove a declared parameter."""
        if name not in self._params:
            raise ParameterNotDeclaredException(name)
        if self._descriptors[name].read_only:
            raise ParameterImmutableException(f"Parameter '{name}' is read-only")
        del self._params[name]
        del self._descriptors[name]

    def add_on_set(self, callback: OnSetCallback) -> None:
        """Register a validating callback (may veto with ``successful=False``)."""
        self._on_set.insert(0, callback)

    def remove_on_set(self, callback: OnSetCallback) -> None:
        """Remove a validating callback."""
        self._on_set.remove(callback)

    def add_post_set(self, callback: PostSetCallback) -> None:
        """Register a callback run after parameters changed."""
        self._post_set.append(callback)
