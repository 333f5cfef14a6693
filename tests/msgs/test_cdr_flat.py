"""Flat CDR decoders (posekit.msgs.cdr_flat) against rosbags' generated deserializers.

Oracle: rosbags' own ``deserialize_cdr_le`` for the same definition and classes. For every
type of posekit's typestore (ROS 2 Jazzy's messages, posekit's services and actions), random
messages decode to equal objects of the same classes, with arrays of the same dtype viewing
the input; and for mutated bytes (flipped bytes, random counts, truncation) both accept with
the same result and end, or both reject.
"""

from __future__ import annotations

import random
from typing import Any

import numpy as np
import pytest

from _support.cdr_values import build_message, random_values
from posekit.msgs import cdr
from posekit.msgs.cdr_flat import make_flat_decoder
from posekit.msgs.registry import MESSAGE_CLASSES

STORE = cdr.get_typestore()
TYPES = sorted(STORE.fielddefs)
MUTATIONS = 40


def _reference(typename: str, data: bytes | bytearray | memoryview) -> tuple[Any, int]:
    msgdef = STORE.get_msgdef(typename)
    message, end = msgdef.deserialize_cdr_le(memoryview(data)[4:], 0, msgdef.cls, STORE)
    return message, end + 4


def _assert_identical(a: Any, b: Any) -> None:
    """Same class, and field by field the same value (arrays: dtype, shape and bytes)."""
    assert type(a) is type(b)
    if isinstance(b, np.ndarray):
        assert a.dtype == b.dtype
        assert a.shape == b.shape
        assert a.tobytes() == b.tobytes()
        assert a.flags.writeable == b.flags.writeable
    elif isinstance(b, list):
        assert len(a) == len(b)
        for x, y in zip(a, b, strict=True):
            _assert_identical(x, y)
    elif hasattr(b, "__dataclass_fields__"):
        for name in b.__dataclass_fields__:
            _assert_identical(getattr(a, name), getattr(b, name))
    elif isinstance(b, float) and b != b:
        assert a != a
    else:
        assert a == b


def _mutate(rng: random.Random, data: bytes) -> bytes:
    buf = bytearray(data)
    kind = rng.randrange(3)
    if kind == 0:
        for _ in range(rng.randint(1, 4)):
            buf[rng.randrange(4, len(buf))] = rng.randrange(256)
    elif kind == 1:  # a count or length somewhere
        pos = rng.randrange(4, max(5, len(buf) - 3))
        value = rng.choice([0, 1, 2, 7, 2**31, 2**32 - 1, rng.randrange(64)])
        buf[pos:pos + 4] = value.to_bytes(4, "little")
    else:
        del buf[rng.randrange(4, len(buf)):]
    return bytes(buf)


def _outcome(decode: Any, data: bytes) -> tuple[str, Any]:
    try:
        return "ok", decode(data)
    except cdr._deser_errors as exc:  # what from_cdr turns into CdrError
        return "error", type(exc)


def test_every_type_and_every_posekit_class_has_a_flat_decoder() -> None:
    missing = [t for t in TYPES if make_flat_decoder(t, STORE) is None]
    assert missing == []
    assert set(MESSAGE_CLASSES) <= set(TYPES)


@pytest.mark.parametrize("typename", TYPES)
def test_flat_decoder_equals_rosbags(typename: str) -> None:
    decode = make_flat_decoder(typename, STORE)
    assert decode is not None
    rng = random.Random(typename)
    samples = []
    for seed in range(3):
        tree = random_values(rng, STORE, typename, big=seed == 2)
        data = bytes(STORE.serialize_cdr(build_message(tree, typename, STORE.types), typename))
        samples.append(data)
        got, end = decode(data)
        expected, expected_end = _reference(typename, data)
        _assert_identical(got, expected)
        assert end == expected_end
        # bytearray and memoryview inputs decode the same (arrays then view them too)
        for other in (bytearray(data), memoryview(data)):
            again, again_end = decode(other)
            assert again_end == end
            _assert_identical(again, _reference(typename, other)[0])
    for _ in range(MUTATIONS):
        blob = _mutate(rng, rng.choice(samples))
        ours = _outcome(decode, blob)
        reference = _outcome(lambda b: _reference(typename, b), blob)
        assert ours[0] == reference[0], (blob.hex(), ours, reference)
        if ours[0] == "ok":
            _assert_identical(ours[1][0], reference[1][0])
            assert ours[1][1] == reference[1][1]


def test_arrays_view_the_input() -> None:
    typename = "sensor_msgs/msg/Image"
    decode = make_flat_decoder(typename, STORE)
    assert decode is not None
    image = MESSAGE_CLASSES[typename](height=2, width=3, encoding="mono8", step=3,
                                      data=np.arange(6, dtype=np.uint8))
    data = bytes(STORE.serialize_cdr(image, typename))
    message, _ = decode(data)
    assert np.shares_memory(message.data, np.frombuffer(data, dtype=np.uint8))
    assert not message.data.flags.writeable
    writable = bytearray(data)
    message, _ = decode(writable)
    assert message.data.flags.writeable
    message.data[0] = 200
    assert writable[len(data) - 6] == 200
