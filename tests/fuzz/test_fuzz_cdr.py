"""Bounded, seeded fuzzer: CDR bytes from a peer, per message type.

For every ROS 2 type posekit has a class for, mutated encodings (flipped bytes, random
lengths, truncation, appended bytes, random bodies behind a valid header) either decode to an
instance of that class or raise CdrError: nothing else, whatever the bytes. Oracle: the
exception contract of ``posekit.msgs.from_cdr``, and for every accepted blob that
re-encoding the decoded message is stable (encode -> decode -> encode gives the same bytes).
"""

from __future__ import annotations

import random

import pytest

from posekit.msgs import from_cdr, to_cdr
from posekit.msgs.errors import CdrError
from posekit.msgs.registry import MESSAGE_CLASSES

PER_TYPE = 120


def _mutate(rng: random.Random, data: bytes) -> bytes:
    kind = rng.randrange(5)
    buf = bytearray(data)
    if kind == 0 and buf:
        for _ in range(rng.randint(1, 6)):
            buf[rng.randrange(len(buf))] = rng.randrange(256)
    elif kind == 1:  # a random little-endian length or count somewhere past the header
        pos = rng.randrange(4, max(5, len(buf)))
        buf[pos:pos + 4] = rng.choice([0, 1, 2**31 - 1, 2**32 - 1, rng.randrange(2**32)]
                                      ).to_bytes(4, "little")
    elif kind == 2:
        buf = buf[: rng.randrange(len(buf) + 1)]
    elif kind == 3:
        buf += rng.randbytes(rng.randint(1, 64))
    else:
        buf = bytearray(b"\x00\x01\x00\x00" + rng.randbytes(rng.randint(0, 200)))
    return bytes(buf)


@pytest.mark.parametrize("type_name", sorted(MESSAGE_CLASSES))
def test_mutated_cdr_decodes_or_raises_cdr_error(type_name: str) -> None:
    cls = MESSAGE_CLASSES[type_name]
    rng = random.Random(type_name)
    valid = to_cdr(cls(), type_name)
    for _ in range(PER_TYPE):
        blob = _mutate(rng, valid)
        try:
            msg = from_cdr(blob, type_name)
        except CdrError:
            continue
        assert type(msg) is cls
        again = to_cdr(msg, type_name)
        assert to_cdr(from_cdr(again, type_name), type_name) == again
