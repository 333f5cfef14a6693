"""ROS 2 CDR (XCDR1, little endian, 4-byte encapsulation header ``00 01 00 00``) for messages.

``to_cdr(msg)`` produces exactly the bytes that rmw (Fast-CDR) and rosbags emit;
``from_cdr(data, msg_type)`` decodes them into posekit's message dataclasses. The
definitions and the generated (de)serializers are rosbags' (``Stores.ROS2_JAZZY``), loaded
lazily the first time a CDR function runs, so ``import posekit.msgs`` needs numpy only.

How the two libraries meet (no per-message conversion step):

* serialization reads fields by attribute name, so posekit messages, rosbags messages and
  any duck-typed object with the ROS field names serialize directly. Array fields are
  checked first (dtype, length, contiguity); a list, ``bytes`` or wrongly typed array is
  converted on a private proxy, never by mutating the caller's message.
* deserialization builds posekit's classes directly: the private typestore's class table
  points at posekit's dataclasses, whose positional field order equals the ROS order.
  Types posekit does not define (any other Jazzy type) decode to rosbags' classes.
* a message whose last field is a byte sequence (``sensor_msgs/Image``), or whose byte
  sequence is followed only by one-byte fields (``sensor_msgs/PointCloud2``'s ``is_dense``),
  is serialized as the rosbags encoding of the rest plus one ``bytes.join`` with the
  payload: a single copy of it (measured in ``benchmarks/runtime_cdr.py``).

Decoded array fields (``Image.data``, covariances, ``CameraInfo.k``...) are zero-copy
numpy views into ``data``: read-only when ``data`` is ``bytes``. Copy them to modify.
Errors raise :class:`posekit.msgs.errors.CdrError` with the reason.
"""

from __future__ import annotations

import dataclasses
import functools
import struct
import threading
from dataclasses import dataclass
from types import SimpleNamespace
from typing import TYPE_CHECKING, Any

import numpy as np

from posekit.msgs.errors import CdrError, UnknownMessageTypeError
from posekit.msgs.registry import MESSAGE_CLASSES, normalize_type_name

if TYPE_CHECKING:
    from collections.abc import Callable

__all__ = [
    "CDR_HEADER_LE",
    "cdr_decoder",
    "from_cdr",
    "get_typestore",
    "serializable_type",
    "to_cdr",
    "type_hash_rihs01",
]

#: Encapsulation header of every CDR payload posekit emits (CDR_LE, options 0).
CDR_HEADER_LE = b"\x00\x01\x00\x00"

_EMPTY_U8 = np.zeros(0, dtype=np.uint8)
#: ROS base types of exactly one byte (CDR alignment 1).
_ONE_BYTE = ("bool", "uint8", "int8", "byte", "char", "octet")
_U32 = struct.Struct("<I")
_SER_ERRORS = (struct.error, TypeError, ValueError, AttributeError, OverflowError, IndexError)
_deser_errors: tuple[type[BaseException], ...] = (
    struct.error,
    TypeError,
    ValueError,
    UnicodeDecodeError,
    IndexError,
    OverflowError,
    AttributeError,
)

_lock = threading.Lock()
_store: Any = None
_codecs: dict[str, _Codec] = {}
_class_codecs: dict[type[Any], _Codec] = {}  # fast path keyed by the message's class

# Plan entry kinds for array checking.
_ARR, _MSG, _SEQ = 0, 1, 2


@dataclass(slots=True)
class _Plan:
    """Which fields of a type (transitively) hold numeric arrays that need checking."""

    fields: tuple[str, ...]
    entries: tuple[tuple[int, str, Any, int | None], ...]


@dataclass(slots=True)
class _Codec:
    typename: str
    getsize: Callable[..., int]
    serialize: Callable[..., int]
    decode: Callable[[bytes | bytearray | memoryview], Any]  # from_cdr with the type bound
    cls: type[Any]
    plan: _Plan | None
    fast_ok: Callable[[Any], bool] | None  # True when every array field is already CDR-ready
    tail_field: str | None  # last field, when it is an unbounded uint8/byte/char sequence
    tail_after: int = 0  # one-byte fields after the tail sequence (PointCloud2.is_dense)


def get_typestore() -> Any:
    """Return posekit's private rosbags ``Typestore`` (ROS 2 Jazzy definitions).

    Its class table maps posekit's message types to posekit's dataclasses. Use it for
    ``hash_rihs01``, ``generate_msgdef`` and similar; do not register conflicting types.
    """
    global _store, _deser_errors
    if _store is None:
        with _lock:
            if _store is None:
                from rosbags.serde import SerdeError

                _deser_errors = (*_deser_errors, SerdeError)
                _store = _build_store()
    return _store



def serializable_type(type_name: str) -> tuple[str, type]:
    """``(normalized name, class)`` of a message type with a ROS 2 definition.

    Such a type can be serialized, recorded or advertised with a schema: posekit's class when
    posekit defines the type, else the class of rosbags' Jazzy typestore
    (``sensor_msgs/msg/PointCloud2``).

    Raises LookupError (or ValueError for a malformed name) otherwise. Types derived from
    services and actions (``pkg/srv/...``, ``pkg/action/...``, e.g. an action's feedback
    topic) are refused too: rosbags writes message-definition text for ``pkg/msg/`` names only.
    """
    from posekit.msgs.registry import find_message_class, normalize_type_name

    name = normalize_type_name(type_name)
    if name.split("/")[1] != "msg":
        raise LookupError(f"{name}: no message-definition text for service or action types")
    if name not in get_typestore().fielddefs:
        raise LookupError(f"{name}: no ROS 2 Jazzy definition known")
    return name, find_message_class(name)

def _build_store() -> Any:
    from rosbags.typesys import Stores
    from rosbags.typesys import get_typestore as rosbags_typestore
    from rosbags.typesys.base import normalize_fieldname

    from posekit.msgs._action_defs import ACTION_DEFINITIONS, action_typedefs
    from posekit.msgs._srv_defs import SERVICE_DEFINITIONS, service_typedefs

    store = rosbags_typestore(Stores.ROS2_JAZZY)  # a fresh instance: ours to modify
    for srv in SERVICE_DEFINITIONS:  # services: rosbags' store has messages only
        store.register(service_typedefs(srv))
    for action in ACTION_DEFINITIONS:
        store.register(action_typedefs(action))
    _char_as_uint8(store)
    for name, cls in MESSAGE_CLASSES.items():
        ros_fields = [normalize_fieldname(f) for f, _ in store.fielddefs[name][1]]
        ours = [f.name for f in dataclasses.fields(cls)]
        if ros_fields != ours:  # positional construction relies on the same order
            raise RuntimeError(f"{cls.__qualname__} fields {ours} differ from ROS {ros_fields}")
        store.types[name] = cls
    return store


def _char_as_uint8(store: Any) -> None:
    """Write ``char`` fields as ``uint8``, as rosidl does.

    ``.msg`` char is an alias of uint8 in IDL and in type descriptions. Same CDR; fixes the
    RIHS01 hash of types with char fields (``service_msgs/msg/ServiceEventInfo``, hence every
    service type).
    """
    from rosbags.interfaces import Nodetype

    def fix(desc: Any) -> Any:
        kind, info = desc
        if kind == Nodetype.BASE and info[0] == "char":
            return (kind, ("uint8", info[1]))
        if kind in (Nodetype.ARRAY, Nodetype.SEQUENCE):
            (subkind, subinfo), count = info
            if subkind == Nodetype.BASE and subinfo[0] == "char":
                return (kind, ((subkind, ("uint8", subinfo[1])), count))
        return desc

    for name, (consts, fields) in list(store.fielddefs.items()):
        fixed = [(fname, fix(desc)) for fname, desc in fields]
        if fixed != fields:
            store.fielddefs[name] = (consts, fixed)


def _make_plan(store: Any, typename: str, cache: dict[str, _Plan | None]) -> _Plan | None:
    from rosbags.interfaces import Nodetype
    from rosbags.serde.utils import ndtype
    from rosbags.typesys.base import normalize_fieldname

    if typename in cache:
        return cache[typename]
    cache[typename] = None  # recursion guard
    entries: list[tuple[int, str, Any, int | None]] = []
    names: list[str] = []
    for raw_name, desc in store.fielddefs[typename][1]:
        fname = normalize_fieldname(raw_name)
        names.append(fname)
        kind = desc[0]
        if kind == Nodetype.NAME:
            sub = _make_plan(store, desc[1], cache)
            if sub is not None:
                entries.append((_MSG, fname, sub, None))
        elif kind in (Nodetype.ARRAY, Nodetype.SEQUENCE):
            (subkind, subinfo), count = desc[1]
            if subkind == Nodetype.BASE:
                if subinfo[0] != "string":
                    dtype = np.dtype(ndtype(subinfo[0]))
                    length = count if kind == Nodetype.ARRAY else None
                    entries.append((_ARR, fname, dtype, length))
            else:
                sub = _make_plan(store, subinfo, cache)
                if sub is not None:
                    entries.append((_SEQ, fname, sub, None))
    plan = _Plan(tuple(names), tuple(entries)) if entries else None
    cache[typename] = plan
    return plan


def _codec(typename: str) -> _Codec:
    codec = _codecs.get(typename)
    if codec is not None:
        return codec
    from rosbags.interfaces import Nodetype

    store = get_typestore()
    if typename not in store.fielddefs:
        raise UnknownMessageTypeError(f"unknown message type {typename!r} (not in ROS 2 Jazzy)")
    with _lock:
        msgdef = store.get_msgdef(typename)
        plan = _make_plan(store, typename, {})
        tail: str | None = None
        after = 0
        fields = list(msgdef.fields)
        # Trailing one-byte scalars (alignment 1, no padding) may follow the byte sequence.
        while fields and fields[-1][1][0] == Nodetype.BASE and fields[-1][1][1][0] in _ONE_BYTE:
            fields.pop()
            after += 1
        if fields:
            name, desc = fields[-1]
            if (
                desc[0] == Nodetype.SEQUENCE
                and desc[1][0][0] == Nodetype.BASE
                and desc[1][0][1][0] in ("uint8", "byte", "char")
                and desc[1][1] == 0
            ):
                tail = name
        codec = _Codec(
            typename,
            msgdef.getsize_cdr,
            msgdef.serialize_cdr_le,
            _make_decoder(typename, msgdef, store),
            msgdef.cls,
            plan,
            _compile_fast_check(plan) if plan is not None else None,
            tail,
            after if tail is not None else 0,
        )
        _codecs[typename] = codec
    return codec


def _compile_fast_check(plan: _Plan) -> Callable[[Any], bool] | None:
    """Compile ``plan`` into one flat function of attribute-path checks.

    None if it has sequences of messages, which :func:`_checked` walks instead.
    """
    lines = ["def fast_ok(msg):"]
    env: dict[str, Any] = {"ndarray": np.ndarray}

    def walk(p: _Plan, path: str) -> bool:
        for kind, fname, info, length in p.entries:
            if kind == _SEQ:
                return False
            if kind == _MSG:
                if not walk(info, f"{path}.{fname}"):
                    return False
                continue
            k = len(env)
            env[f"dt{k}"] = info
            shape = f"v.shape[0] == {length}" if length is not None else "True"
            lines.append(f"    v = {path}.{fname}")
            lines.append(
                f"    if not (type(v) is ndarray and v.ndim == 1 and v.dtype == dt{k} "
                f"and {shape} and v.flags.c_contiguous):"
            )
            lines.append("        return False")
        return True

    if not walk(plan, "msg"):
        return None
    lines.append("    return True")
    exec("\n".join(lines), env)  # generated from ROS field names only
    fn: Callable[[Any], bool] = env["fast_ok"]
    return fn


def _as_array(val: Any, dtype: np.dtype[Any], length: int | None, fname: str) -> Any:
    if isinstance(val, list | tuple) and dtype.itemsize == 1 and val and all(
        isinstance(v, bytes) for v in val
    ):
        val = b"".join(val)  # rclpy's byte[] form: a list of 1-byte bytes objects
    if isinstance(val, list | tuple) and not val:
        val = np.zeros(0, dtype=dtype)
    elif isinstance(val, list | tuple) and dtype.kind in "iu" and all(
        type(v) is int for v in val
    ):
        try:  # Python ints into any integer width (same_kind casting refuses int64 -> uint8)
            val = np.array(val, dtype=dtype)
        except OverflowError as exc:
            raise CdrError(f"field {fname!r}: {exc}") from exc
    if isinstance(val, (bytes, bytearray, memoryview)) and dtype.itemsize == 1:
        arr = np.frombuffer(val, dtype=dtype)
    else:
        try:
            arr = np.asarray(val)
            if arr.dtype != dtype:
                arr = arr.astype(dtype, casting="same_kind")
        except TypeError as exc:
            raise CdrError(f"field {fname!r}: cannot be stored as {dtype.name}: {exc}") from exc
        arr = np.ascontiguousarray(arr).reshape(-1)
    if length is not None and arr.shape[0] != length:
        raise CdrError(f"field {fname!r}: expected {length} elements, got {arr.shape[0]}")
    return arr


def _checked(msg: Any, plan: _Plan) -> Any:
    """Return ``msg`` itself when every array field is already CDR-ready, else a proxy."""
    changes: dict[str, Any] | None = None
    for kind, fname, info, length in plan.entries:
        val = getattr(msg, fname)
        if kind == _ARR:
            if (
                type(val) is np.ndarray
                and val.dtype == info
                and val.ndim == 1
                and (length is None or val.shape[0] == length)
                and val.flags.c_contiguous
            ):
                continue
            new: Any = _as_array(val, info, length, fname)
        elif kind == _MSG:
            new = _checked(val, info)
            if new is val:
                continue
        else:
            items = [_checked(item, info) for item in val]
            if all(a is b for a, b in zip(items, val, strict=True)):
                continue
            new = items
        if changes is None:
            changes = {}
        changes[fname] = new
    if changes is None:
        return msg
    attrs = {name: getattr(msg, name) for name in plan.fields}
    attrs.update(changes)
    return SimpleNamespace(**attrs)


def _resolve_name(msg_type: str | type[Any]) -> str:
    if isinstance(msg_type, str):
        return normalize_type_name(msg_type)
    name = getattr(msg_type, "__msgtype__", None) or getattr(msg_type, "__srvtype__", None)
    if not isinstance(name, str):
        raise UnknownMessageTypeError(f"{msg_type!r} is not a message class (no __msgtype__)")
    return name


def to_cdr(msg: Any, msg_type: str | None = None) -> bytes:
    """Serialize ``msg`` to ROS 2 CDR bytes (with the ``00 01 00 00`` header).

    Args:
        msg: a posekit message, a rosbags message or any object with the ROS field names.
        msg_type: ROS type name; defaults to ``msg.__msgtype__``.

    Raises:
        CdrError: a field does not fit its ROS type (the message names which).
        UnknownMessageTypeError: the type is not a ROS 2 Jazzy message type.
    """
    # Fast paths: the message's class, or a type name already in its full form.
    codec = _class_codecs.get(type(msg)) if msg_type is None else _codecs.get(msg_type)
    if codec is None:
        name = _resolve_name(msg_type) if msg_type is not None else _resolve_name(type(msg))
        codec = _codecs.get(name) or _codec(name)
        if msg_type is None:
            _class_codecs[type(msg)] = codec
    typename = codec.typename
    store = _store
    try:
        if codec.plan is not None and (codec.fast_ok is None or not codec.fast_ok(msg)):
            msg = _checked(msg, codec.plan)
        if codec.tail_field is not None:
            return _to_cdr_tail(msg, codec, store)
        size = 4 + codec.getsize(0, msg, store)
        raw = bytearray(size)
        raw[1] = 1
        codec.serialize(memoryview(raw)[4:], 0, msg, store)
        return bytes(raw)
    except CdrError:
        raise
    except _SER_ERRORS as exc:
        where = _diagnose(msg, typename, "")
        reason = where or f"{type(exc).__name__}: {exc}"
        raise CdrError(f"cannot serialize {typename}: {reason}") from exc


_INT_BITS = {
    "int8": (True, 8),
    "uint8": (False, 8),
    "byte": (False, 8),
    "char": (False, 8),
    "int16": (True, 16),
    "uint16": (False, 16),
    "int32": (True, 32),
    "uint32": (False, 32),
    "int64": (True, 64),
    "uint64": (False, 64),
}


def _diagnose_scalar(val: Any, base: str, path: str) -> str | None:
    if base == "string":
        return None if isinstance(val, str) else f"field {path!r}: expected str, got {val!r}"
    if base in ("float32", "float64"):
        ok = isinstance(val, (int, float, np.integer, np.floating)) and not isinstance(val, bool)
        return None if ok else f"field {path!r}: expected a float, got {val!r}"
    if base == "bool":
        return None
    signed, bits = _INT_BITS[base]
    if not isinstance(val, (int, np.integer)):
        return f"field {path!r}: expected an integer ({base}), got {val!r}"
    lo, hi = (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if signed else (0, (1 << bits) - 1)
    if not lo <= int(val) <= hi:
        return f"field {path!r}: {int(val)} is out of {base} range [{lo}, {hi}]"
    return None


def _diagnose(msg: Any, typename: str, prefix: str) -> str | None:
    """Find the first field of ``msg`` that cannot be serialized (slow; errors only)."""
    from rosbags.interfaces import Nodetype

    for raw_name, desc in _store.fielddefs[typename][1]:
        path = f"{prefix}{raw_name}"
        try:
            val = getattr(msg, raw_name)
        except AttributeError:
            return f"field {path!r} is missing"
        kind = desc[0]
        if kind == Nodetype.BASE:
            found = _diagnose_scalar(val, desc[1][0], path)
        elif kind == Nodetype.NAME:
            found = (
                f"field {path!r}: expected {desc[1]}, got None"
                if val is None
                else _diagnose(val, desc[1], path + ".")
            )
        else:
            (subkind, subinfo), _ = desc[1]
            found = None
            try:
                items = list(val)
            except TypeError:
                return f"field {path!r}: expected a sequence, got {val!r}"
            for i, item in enumerate(items):
                if subkind == Nodetype.NAME:
                    found = _diagnose(item, subinfo, f"{path}[{i}].")
                elif subinfo[0] == "string":
                    found = _diagnose_scalar(item, "string", f"{path}[{i}]")
                if found:
                    break
        if found:
            return found
    return None


def _to_cdr_tail(msg: Any, codec: _Codec, store: Any) -> bytes:
    # Serialize everything but the trailing byte sequence with rosbags (empty sequence), then
    # patch its length and append the payload: one copy of the (large) buffer.
    assert codec.plan is not None
    assert codec.tail_field is not None
    tail = getattr(msg, codec.tail_field)
    attrs = {name: getattr(msg, name) for name in codec.plan.fields}
    attrs[codec.tail_field] = _EMPTY_U8
    head_msg = SimpleNamespace(**attrs)
    size = 4 + codec.getsize(0, head_msg, store)
    raw = bytearray(size)
    raw[1] = 1
    codec.serialize(memoryview(raw)[4:], 0, head_msg, store)
    count = tail.shape[0] if isinstance(tail, np.ndarray) else len(tail)
    split = size - codec.tail_after  # the one-byte fields after the sequence follow it
    _U32.pack_into(raw, split - 4, count)
    if codec.tail_after:
        return b"".join((memoryview(raw)[:split], tail, memoryview(raw)[split:]))
    return b"".join((raw, tail))


def from_cdr(data: bytes | bytearray | memoryview, msg_type: str | type[Any]) -> Any:
    """Decode ROS 2 CDR bytes into a message of ``msg_type`` (class or ``pkg/msg/Type``).

    Little- and big-endian encapsulations are accepted. Array fields of the result are
    zero-copy views into ``data``. For a stream of one type, :func:`cdr_decoder` resolves
    the type once.

    Raises:
        CdrError: truncated, corrupted or trailing-garbage input (the message says why).
        UnknownMessageTypeError: the type is not a ROS 2 Jazzy message type.
    """
    return _codec_of(msg_type).decode(data)


def cdr_decoder(msg_type: str | type[Any]) -> Callable[[bytes | bytearray | memoryview], Any]:
    """``from_cdr(data, msg_type)`` as a function of ``data`` alone, the type resolved now.

    What a subscription calls per message: same results and errors as :func:`from_cdr`.

    Raises:
        UnknownMessageTypeError: the type is not a ROS 2 Jazzy message type.
    """
    return _codec_of(msg_type).decode


def _codec_of(msg_type: str | type[Any]) -> _Codec:
    # (a class is looked up first: a type name is never a key of _class_codecs)
    codec = _class_codecs.get(msg_type)  # type: ignore[arg-type]
    if codec is None:
        name = _resolve_name(msg_type)
        codec = _codecs.get(name) or _codec(name)
        if not isinstance(msg_type, str):
            _class_codecs[msg_type] = codec
    return codec


def _make_decoder(
    typename: str, msgdef: Any, store: Any
) -> Callable[[bytes | bytearray | memoryview], Any]:
    """The ``decode(data)`` of one type's codec: :func:`from_cdr` with the type bound.

    Little-endian bodies go to the type's flat decoder (:mod:`posekit.msgs.cdr_flat`), which
    gives rosbags' results faster, where the type has one; otherwise to rosbags'.
    """
    from posekit.msgs.cdr_flat import make_flat_decoder

    deserialize_le, cls = msgdef.deserialize_cdr_le, msgdef.cls
    flat = make_flat_decoder(typename, store)
    if flat is None:
        def flat(data: Any) -> tuple[Any, int]:
            message, pos = deserialize_le(memoryview(data)[4:], 0, cls, store)
            return message, pos + 4

    def trailing(size: int, end: int) -> CdrError:
        return CdrError(f"cannot decode {typename}: {size - end} unexpected trailing bytes")

    def decode(data: bytes | bytearray | memoryview) -> Any:
        if type(data) is bytes and len(data) >= 4 and data[0] == 0 and data[1] == 1:
            # the common case (little endian bytes): the checks below are done
            try:
                message, end = flat(data)
            except _deser_errors as exc:
                raise CdrError(f"cannot decode {typename}: {exc}") from exc
            if end + 3 < len(data):  # up to 3 bytes of final padding are legal
                raise trailing(len(data), end)
            return message
        try:
            view = data if isinstance(data, memoryview) else memoryview(data)
        except TypeError as exc:
            raise CdrError(f"CDR input must be bytes-like, got {type(data).__name__}") from exc
        if view.ndim != 1 or view.itemsize != 1:
            view = view.cast("B")
        if len(view) < 4:
            raise CdrError(f"{typename}: {len(view)} bytes is shorter than the CDR header")
        if view[0] != 0 or view[1] > 1:
            raise CdrError(
                f"{typename}: unsupported CDR encapsulation {bytes(view[:2]).hex(' ')} "
                "(expected 00 01 little endian or 00 00 big endian)"
            )
        try:
            if view[1]:
                message, end = flat(view)
            else:
                message, end = msgdef.deserialize_cdr_be(view[4:], 0, cls, store)
                end += 4
        except _deser_errors as exc:
            raise CdrError(f"cannot decode {typename}: {exc}") from exc
        if end + 3 < len(view):
            raise trailing(len(view), end)
        return message

    return decode


def type_hash_rihs01(msg_type: str | type[Any]) -> str:
    """Return the REP-2011 type hash ``RIHS01_<64 hex>`` of a message type.

    Computed by rosbags from the ROS 2 Jazzy definitions (never a pasted table).
    """
    return _hash_of_type(_resolve_name(msg_type))


@functools.cache
def _hash_of_type(typename: str) -> str:
    """type_hash_rihs01 of a resolved name, computed once per type."""
    store = get_typestore()
    if typename not in store.fielddefs:
        raise UnknownMessageTypeError(f"unknown message type {typename!r} (not in ROS 2 Jazzy)")
    return str(store.hash_rihs01(typename))
