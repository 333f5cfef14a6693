"""rosidl's introspection API on posekit's message classes.

Every class in :data:`posekit.msgs.registry.MESSAGE_CLASSES` gets, as rosidl-generated Python
classes have them:

* ``get_fields_and_field_types()`` (classmethod): ``{field name: IDL type string}`` in field
  order, with rosidl's spellings: ``double``/``float`` for float64/float32, ``boolean``,
  ``octet`` for ``byte``, ``uint8`` for ``char``, ``string<N>`` for bounded strings,
  ``double[36]`` for arrays, ``sequence<uint8>`` / ``sequence<T, N>`` for (bounded)
  sequences, and ``pkg/Type`` for nested messages (``std_msgs/Header``); an empty message
  (``std_srvs/srv/Empty_Request``) has none;
* ``_fields_and_field_types``: the same mapping as a class attribute.

The field types come from the ROS 2 Jazzy definitions in posekit's typestore
(:func:`posekit.msgs.cdr.get_typestore`, rosbags), loaded the first time one is asked for.
"""

from __future__ import annotations

from typing import Any

__all__ = ["fields_and_field_types", "install_introspection"]

# .msg primitive -> rosidl IDL spelling (rosidl_adapter's mapping).
_IDL_NAMES = {
    "bool": "boolean",
    "byte": "octet",
    "char": "uint8",
    "float32": "float",
    "float64": "double",
}

# The member the .msg -> IDL step adds to an empty message; rosidl does not list it.
_PLACEHOLDER = "structure_needs_at_least_one_member"

_cache: dict[str, dict[str, str]] = {}


def _idl_type(desc: tuple[Any, ...]) -> str:
    from rosbags.interfaces import Nodetype

    kind = desc[0]
    if kind == Nodetype.BASE:
        base, bound = desc[1]
        name = _IDL_NAMES.get(base, base)
        return f"{name}<{bound}>" if bound else name
    if kind == Nodetype.NAME:
        pkg, _, typ = str(desc[1]).split("/")
        return f"{pkg}/{typ}"
    element, count = desc[1]
    inner = _idl_type(element)
    if kind == Nodetype.ARRAY:
        return f"{inner}[{count}]"
    return f"sequence<{inner}, {count}>" if count else f"sequence<{inner}>"


def fields_and_field_types(type_name: str) -> dict[str, str]:
    """``{field: IDL type}`` of the ROS 2 type ``type_name`` (``pkg/msg/Type``), in order.

    Raises:
        UnknownMessageTypeError: the typestore has no definition of ``type_name``.
    """
    cached = _cache.get(type_name)
    if cached is None:
        from posekit.msgs.cdr import get_typestore
        from posekit.msgs.errors import UnknownMessageTypeError

        store = get_typestore()
        if type_name not in store.fielddefs:
            raise UnknownMessageTypeError(f"no ROS 2 definition of {type_name!r}")
        cached = {name: _idl_type(desc) for name, desc in store.fielddefs[type_name][1]
                  if name != _PLACEHOLDER}
        _cache[type_name] = cached
    return dict(cached)


class _FieldsAttribute:
    """``cls._fields_and_field_types``, computed on first access (it needs the typestore)."""

    def __get__(self, obj: object, owner: type[Any]) -> dict[str, str]:
        return fields_and_field_types(owner.__msgtype__)


def _get_fields_and_field_types(cls: type[Any]) -> dict[str, str]:
    return fields_and_field_types(cls.__msgtype__)


def install_introspection(cls: type[Any]) -> None:
    """Give the message class ``cls`` rosidl's introspection attributes (module docstring)."""
    cls.get_fields_and_field_types = classmethod(_get_fields_and_field_types)
    cls._fields_and_field_types = _FieldsAttribute()
