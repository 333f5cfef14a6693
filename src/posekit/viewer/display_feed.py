"""Messages of any topic for the page's displays, as JSON (the ``display`` channel).

A page adds a display for a topic (``{"op": "display_subscribe", "topic", "type",
"queue"}``); the server then sends that client the topic's messages converted to JSON by
:func:`message_to_json`: a message becomes an object of its fields in definition order
(nested messages as objects, strings and numbers as they are), as
:func:`posekit.msgs.yaml_io.message_to_ordered` gives them, but with nothing truncated and
with large numeric arrays packed:

* a numeric array (numpy array, ``bytes``) of more than :data:`PACK_MIN` elements becomes
  ``{"$bin": BASE64, "dtype": NAME, "shape": [...]}`` (little-endian raw bytes; ``NAME`` one
  of ``int8 uint8 int16 uint16 int32 uint32 int64 uint64 float32 float64``); the page turns
  it back into the matching JavaScript TypedArray (``BigInt64Array`` for 64-bit integers);
* shorter arrays (a covariance, a few points) stay JSON lists;
* non-finite floats become ``null`` (JSON has no inf/NaN);
* a ``sensor_msgs/PointCloud2`` is sent as :class:`posekit.viewer.cloud_feed.CompactCloud`
  (its finite points as float32 x, y, z, intensity and rgb bytes, at most
  :data:`posekit.viewer.cloud_feed.MAX_CLOUD_POINTS`), not as its raw ``data``.

:class:`MessageQueue` holds the newest messages of one topic for the displays (a sequence
number per message, so each client gets each message at most once).
"""

from __future__ import annotations

import base64
import dataclasses
import threading
from collections import deque
from typing import Any

import numpy as np

from posekit.msgs.sensor_msgs import PointCloud2
from posekit.msgs.yaml_io import message_field_names, message_to_ordered
from posekit.viewer.cloud_feed import compact_point_cloud

__all__ = ["MAX_QUEUE", "PACK_MIN", "MessageQueue", "message_to_json"]

#: Arrays with more elements than this are sent packed (base64 of the raw bytes).
PACK_MIN = 64
#: Messages a display may ask to be kept per topic between two sends.
MAX_QUEUE = 1000

_PACKABLE = {"i1": "int8", "u1": "uint8", "i2": "int16", "u2": "uint16", "i4": "int32",
             "u4": "uint32", "i8": "int64", "u8": "uint64", "f4": "float32",
             "f8": "float64"}


def _packed(array: np.ndarray) -> dict[str, Any] | None:
    name = _PACKABLE.get(array.dtype.kind + str(array.dtype.itemsize))
    if name is None or array.size <= PACK_MIN:
        return None
    data = np.ascontiguousarray(array, dtype=array.dtype.newbyteorder("<"))
    return {"$bin": base64.b64encode(data.tobytes()).decode("ascii"), "dtype": name,
            "shape": list(array.shape)}


def message_to_json(value: Any) -> Any:
    """``value`` (a message, or any field of one) as JSON-ready data (see the module docstring)."""
    if isinstance(value, PointCloud2):
        value = compact_point_cloud(value)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {name: message_to_json(getattr(value, name))
                for name in message_field_names(value)}
    if isinstance(value, np.ndarray):
        packed = _packed(value)
        return packed if packed is not None else value.tolist()
    if isinstance(value, (bytes, bytearray, memoryview)):
        raw = np.frombuffer(bytes(value), np.uint8)
        packed = _packed(raw)
        return packed if packed is not None else raw.tolist()
    if isinstance(value, (list, tuple)):
        return [message_to_json(v) for v in value]
    return message_to_ordered(value, None)


class MessageQueue:
    """The newest ``depth`` messages of one topic, numbered from 1.

    Thread-safe: the sink appends on the transport's thread, the server reads on its own.
    """

    def __init__(self, depth: int = 1) -> None:
        self._lock = threading.Lock()
        self._items: deque[tuple[int, Any]] = deque(maxlen=max(1, min(depth, MAX_QUEUE)))
        self._seq = 0

    @property
    def depth(self) -> int:
        """Messages kept."""
        return self._items.maxlen or 1

    def resize(self, depth: int) -> None:
        """Keep ``depth`` messages from now on (the newest ones are kept)."""
        depth = max(1, min(depth, MAX_QUEUE))
        with self._lock:
            if depth != self._items.maxlen:
                self._items = deque(self._items, maxlen=depth)

    def append(self, msg: Any) -> None:
        """Store ``msg`` as the newest message."""
        with self._lock:
            self._seq += 1
            self._items.append((self._seq, msg))

    @property
    def seq(self) -> int:
        """Number of the newest message (0: none yet)."""
        return self._seq

    def after(self, seq: int) -> list[tuple[int, Any]]:
        """``(number, message)`` of the kept messages newer than ``seq``, oldest first."""
        with self._lock:
            return [item for item in self._items if item[0] > seq]
