"""Flat little-endian CDR decoders: one generated function per message type.

rosbags generates one deserializer per type, and a message field calls its type's own
deserializer, which reads each primitive with its own ``unpack`` call. A
``geometry_msgs/TransformStamped`` thus runs six functions and eleven ``unpack`` calls;
here it runs one function and three ``struct`` reads (``sec, nanosec, len(frame_id)``,
``len(child_frame_id)``, the seven doubles), 2.8x faster warm and about 7 us less per
message received alone at 1 kHz, in caches gone cold (docs/performance.md).

The decoders give exactly rosbags' results: the same classes, built positionally; numeric
arrays as zero-copy ``numpy.frombuffer`` views; the same alignment decisions (rosbags'
``align`` / ``align_after`` bookkeeping, replayed at generation time: where rosbags aligns at
run time and the alignment of ``pos`` is known, the padding becomes a constant offset); the
same string and sequence-length checks. What is not covered (``wstring``, ``float128``,
fixed-size arrays of strings) has no flat decoder, and :mod:`posekit.msgs.cdr` keeps
rosbags' for that type. Big-endian input always goes to rosbags.

Oracle: ``tests/msgs/test_cdr_flat.py`` decodes random messages of every ROS 2 Jazzy type,
and mutated bytes, with both and requires the same message or both to fail.
"""

from __future__ import annotations

import struct
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["make_flat_decoder"]

#: ``struct`` codes of rosbags' primitives (``byte`` is signed there, ``char`` unsigned).
_CODES = {
    "bool": "?", "byte": "b", "char": "B", "int8": "b", "uint8": "B", "int16": "h",
    "uint16": "H", "int32": "i", "uint32": "I", "int64": "q", "uint64": "Q", "float32": "f",
    "float64": "d",
}
_SIZES = {name: struct.calcsize(code) for name, code in _CODES.items()}
#: numpy dtype names of array elements, as rosbags' ``ndtype``.
_DTYPES = {name: np.dtype({"bool": "bool_", "char": "uint8", "byte": "int8"}.get(name, name))
           for name in _CODES}
#: What ``pos`` is known to be a multiple of at the body's start (relative to the body).
_START = 8


class _UnsupportedFieldError(Exception):
    """A field kind this generator leaves to rosbags."""


def _string_error(length: int, pos: int) -> ValueError:
    return ValueError(f"invalid string length {length} at byte {pos - 4}")


def _sequence_error(size: int, pos: int) -> ValueError:
    return ValueError(f"invalid sequence length {size} at byte {pos - 4}")


def _align_code(alignment: int) -> str:
    """Code moving ``pos`` to the body's next multiple of ``alignment``.

    ``pos`` is an offset into the whole CDR buffer; the body starts at byte 4.
    """
    if alignment <= 4:
        return f"pos = (pos + {alignment - 1}) & -{alignment}"
    return f"pos = ((pos + {alignment - 5}) & -{alignment}) + 4"


@dataclass
class _Writer:
    """The generated function's lines, and the run of fixed-offset reads not yet emitted.

    ``pos`` (generated code) is the offset the run starts at; ``known`` is a power of two
    that ``pos - 4`` (the offset in the body) is known to be a multiple of; ``offset`` is
    where the next field starts, relative to ``pos``. ``codes`` and ``targets`` make the
    run's one ``unpack_from``.
    """

    store: Any
    names: dict[str, Any] = field(default_factory=dict)  # global name -> object
    lines: list[str] = field(default_factory=list)
    counter: int = 0
    codes: str = ""
    targets: list[str] = field(default_factory=list)
    offset: int = 0
    known: int = _START

    def var(self, prefix: str) -> str:
        self.counter += 1
        return f"{prefix}{self.counter}"

    def constant(self, prefix: str, value: Any) -> str:
        for name, existing in self.names.items():
            if existing is value:
                return name
        name = self.var(prefix)
        self.names[name] = value
        return name

    # -- the run of reads at constant offsets -------------------------------------------
    def read(self, base: str) -> str:
        """A primitive at the run's next offset (already aligned): its variable."""
        target = self.var("v")
        self.codes += _CODES[base]
        self.targets.append(target)
        self.offset += _SIZES[base]
        return target

    def skip(self, size: int) -> None:
        if size:
            self.codes += f"{size}x"
            self.offset += size

    def flush(self, indent: str) -> None:
        """Emit the run's read and move ``pos`` to its end."""
        if self.targets:
            unpack = self.constant("S", struct.Struct("<" + self.codes).unpack_from)
            self.lines.append(f"{indent}{', '.join(self.targets)}, = {unpack}(rawdata, pos)")
        if self.offset:
            self.lines.append(f"{indent}pos += {self.offset}")
            self.known = _gcd_power(self.known, self.offset)
        self.codes, self.targets, self.offset = "", [], 0

    def align(self, alignment: int, indent: str) -> None:
        """rosbags' ``pos = (pos + a - 1) & -a`` at this point of the stream."""
        if alignment <= self.known:  # pos is a multiple of it: the padding is a constant
            self.skip(-self.offset % alignment)
            return
        self.flush(indent)
        self.lines.append(f"{indent}{_align_code(alignment)}")
        self.known = alignment

    def unknown(self) -> None:
        """``pos`` moved by a length read at run time."""
        self.known = 1


def _gcd_power(known: int, offset: int) -> int:
    """The largest power of two dividing both ``known`` (a power of two) and ``offset``."""
    low = offset & -offset
    return min(known, low) if low else known


def _message(w: _Writer, typename: str, indent: str) -> str:
    """Code for one message's fields (``pos`` aligned for its first); its constructor call.

    The alignment bookkeeping is rosbags': ``aligned`` starts at 8 in each message (a
    nested message's first field was aligned by its parent) and is ``align_after`` of the
    field just read.
    """
    from rosbags.interfaces import Nodetype
    from rosbags.serde.utils import align, align_after

    store = w.store
    msgdef = store.get_msgdef(typename)
    fields = list(msgdef.fields)
    values: list[str] = []
    aligned = 8
    for index, (_, desc) in enumerate(fields):
        kind = desc[0]
        if kind == Nodetype.NAME:
            values.append(_message(w, desc[1], indent))
        elif kind == Nodetype.BASE:
            base = desc[1][0]
            if base == "string":
                values.append(_string(w, indent))
            elif base in _CODES:
                values.append(w.read(base))
            else:
                raise _UnsupportedFieldError(base)
        elif kind == Nodetype.ARRAY:
            (subkind, subinfo), length = desc[1]
            if subkind == Nodetype.BASE:
                values.append(_array(w, subinfo[0], length, indent))
            else:  # unrolled, as rosbags does; the elements' fields join the run
                before, after = align(desc[1][0], store), align_after(desc[1][0], store)
                items = []
                for _ in range(length):
                    if before > after:
                        w.align(before, indent)
                    items.append(_message(w, subinfo, indent))
                values.append(f"[{', '.join(items)}]")
        else:
            values.append(_sequence(w, desc, indent))
        aligned = align_after(desc, store)
        if index + 1 < len(fields):
            following = align(fields[index + 1][1], store)
            if aligned < following:
                w.align(following, indent)
                aligned = following
    cls = w.constant("C", msgdef.cls)
    return f"{cls}({', '.join(values)})"


def _array(w: _Writer, base: str, length: int, indent: str) -> str:
    """A fixed-size array of a primitive type at the run's next offset: its variable."""
    if base not in _CODES:
        raise _UnsupportedFieldError(base)
    target = w.var("a")
    dtype = w.constant("D", _DTYPES[base])
    w.lines.append(f"{indent}{target} = frombuffer(rawdata, dtype={dtype}, count={length}, "
                   f"offset=pos + {w.offset})")
    w.skip(length * _SIZES[base])
    return target


def _string(w: _Writer, indent: str) -> str:
    """A string at the run's next offset (aligned to 4): its variable."""
    length = w.read("uint32")
    w.flush(indent)
    target = w.var("s")
    end = w.var("e")
    w.lines += [
        f"{indent}{end} = pos + {length}",
        f"{indent}if {length} < 1 or {end} > len(rawdata) or rawdata[{end} - 1] != 0:",
        f"{indent}    raise string_error({length}, pos)",
        f"{indent}{target} = str(rawdata[pos:{end} - 1], 'utf-8')",
        f"{indent}pos = {end}",
    ]
    w.unknown()
    return target


def _sequence(w: _Writer, desc: Any, indent: str) -> str:
    """A sequence (its count at the run's next offset): its variable."""
    from rosbags.interfaces import Nodetype
    from rosbags.serde.utils import align

    store = w.store
    (subkind, subinfo), _ = desc[1]
    size = w.read("uint32")
    w.flush(indent)
    if subkind == Nodetype.BASE and subinfo[0] == "string":
        minimum = 5
    elif subkind == Nodetype.BASE:
        if subinfo[0] not in _CODES:
            raise _UnsupportedFieldError(subinfo[0])
        minimum = _SIZES[subinfo[0]]
    else:
        minimum = 1
    w.lines += [
        f"{indent}if pos + {size} * {minimum} > len(rawdata) "
        f"or {size} > {store.max_sequence_length}:",
        f"{indent}    raise sequence_error({size}, pos)",
    ]
    target = w.var("q")
    if subkind == Nodetype.BASE and subinfo[0] != "string":
        element = align(desc[1][0], store)
        if element > 4:  # rosbags' ``aligned`` is 4 after the count
            w.lines += [f"{indent}if {size}:", f"{indent}    {_align_code(element)}"]
        dtype = w.constant("D", _DTYPES[subinfo[0]])
        w.lines += [
            f"{indent}{target} = frombuffer(rawdata, dtype={dtype}, count={size}, offset=pos)",
            f"{indent}pos += {size} * {_SIZES[subinfo[0]]}",
        ]
        w.unknown()
        return target
    w.lines.append(f"{indent}{target} = []")
    w.lines.append(f"{indent}for _ in range({size}):")
    inner = indent + "    "
    if subkind == Nodetype.BASE:  # strings
        w.lines.append(f"{inner}{_align_code(4)}")
        w.known = 4
        w.lines.append(f"{inner}{target}.append({_string(w, inner)})")
    else:
        before = align(desc[1][0], store)
        w.lines.append(f"{inner}{_align_code(before)}")
        w.known = before
        expression = _message(w, subinfo, inner)
        w.flush(inner)
        w.lines.append(f"{inner}{target}.append({expression})")
    w.unknown()
    return target


def make_flat_decoder(typename: str, store: Any) -> Callable[[Any], tuple[Any, int]] | None:
    """``decode(data) -> (message, end)`` of ``typename``, or None if a field is not covered.

    The definition and classes are those of rosbags typestore ``store``. ``data`` is a
    whole little-endian CDR buffer (``bytes``, ``bytearray`` or a 1-D byte ``memoryview``)
    whose 4-byte encapsulation header the caller checked; ``end`` is the offset just past
    the message. Malformed data raises ``struct.error``, ``ValueError`` or
    ``UnicodeDecodeError``.
    """
    w = _Writer(store)
    try:
        expression = _message(w, typename, "    ")
    except _UnsupportedFieldError:
        return None
    w.flush("    ")
    source = "\n".join(["def decode(rawdata):", "    pos = 4", *w.lines,
                        f"    return {expression}, pos"])
    namespace: dict[str, Any] = {
        **w.names, "frombuffer": np.frombuffer, "string_error": _string_error,
        "sequence_error": _sequence_error,
    }
    exec(compile(source, f"<posekit cdr_flat {typename}>", "exec"), namespace)
    decode: Callable[[Any], tuple[Any, int]] = namespace["decode"]
    decode.__doc__ = source
    return decode
