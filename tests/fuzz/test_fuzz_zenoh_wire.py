"""Bounded, seeded fuzzer: what a Zenoh peer controls on the wire besides the payload, i.e.
attachments and liveliness tokens (key expressions).

Oracle: the exception contract of posekit.transport.zenoh_wire (WireFormatError and nothing
else for any input), and the GraphCache's own bound and counters: every token is either
recorded, counted as rejected, or counted as overflow.
"""

from __future__ import annotations

import random
import string

import pytest

pytest.importorskip("zenoh")

from posekit.transport.zenoh_wire import (
    EntityKind,
    GraphCache,
    WireFormatError,
    WireQoS,
    decode_attachment,
    encode_attachment,
    endpoint_token,
    node_token,
    parse_token,
)

ALPHABET = string.ascii_letters + string.digits + "/%_:@*$#?.-~ \x00é"


def _valid_tokens() -> list[str]:
    return [
        node_token(0, "aa11", 3, "/", "talker"),
        endpoint_token(0, "aa11", 3, 4, EntityKind.PUBLISHER, "/ns", "talker", "/chatter",
                       "std_msgs/msg/String", WireQoS(depth=7)),
        endpoint_token(5, "bb22", 1, 9, EntityKind.SUBSCRIPTION, "/", "listener", "/tf",
                       "tf2_msgs/msg/TFMessage", WireQoS(durability=1, depth=100)),
    ]


def _mutate_token(rng: random.Random, token: str) -> str:
    chunks = token.split("/")
    kind = rng.randrange(5)
    if kind == 0:
        chunks[rng.randrange(len(chunks))] = "".join(
            rng.choice(ALPHABET) for _ in range(rng.randint(0, 12)))
    elif kind == 1:
        del chunks[rng.randrange(len(chunks))]
    elif kind == 2:
        chunks.insert(rng.randrange(len(chunks) + 1), rng.choice(["", "x", "%", "NN", "MP"]))
    elif kind == 3:
        pos = rng.randrange(len(token))
        return token[:pos] + rng.choice(ALPHABET) + token[pos + 1:]
    else:
        return "".join(rng.choice(ALPHABET) for _ in range(rng.randint(0, 80)))
    return "/".join(chunks)


def test_mutated_liveliness_tokens_parse_or_raise_wire_format_error() -> None:
    rng = random.Random(11)
    cache = GraphCache(max_tokens=500)
    tokens = _valid_tokens()
    parsed = refused = 0
    stored: set[str] = set()
    for i in range(6000):
        key = _mutate_token(rng, tokens[i % len(tokens)])
        try:
            parse_token(key)
            parsed += 1
        except WireFormatError:
            refused += 1
        before = len(cache.entities()) + cache.rejected + cache.overflowed
        if cache.add(key) is not None:
            stored.add(key)
        after = len(cache.entities()) + cache.rejected + cache.overflowed
        # each token is stored, rejected or counted as overflow (or was stored already)
        assert after == before + 1 or key in stored
        assert len(cache.entities()) <= 500
        if i % 100 == 0:
            cache.node_names()
            cache.topic_names_and_types()
    assert parsed > 0
    assert refused > 0


def test_random_attachments_decode_or_raise_wire_format_error() -> None:
    rng = random.Random(12)
    valid = encode_attachment(5, 123, bytes(range(16)))
    decoded = refused = 0
    for _ in range(5000):
        if rng.random() < 0.5:
            blob = rng.randbytes(rng.randint(0, 100))
        else:
            buf = bytearray(valid)
            for _ in range(rng.randint(1, 4)):
                buf[rng.randrange(len(buf))] = rng.randrange(256)
            blob = bytes(buf[: rng.randint(0, len(buf) + 8)])
        try:
            att = decode_attachment(blob)
        except WireFormatError:
            refused += 1
            continue
        assert len(att.gid) == 16
        decoded += 1
    assert decoded > 0
    assert refused > 0


@pytest.mark.slow
def test_mutated_tokens_over_real_liveliness(monkeypatch: pytest.MonkeyPatch) -> None:
    """The same mutations declared as real Zenoh liveliness tokens by a peer session: the
    victim's graph records, rejects or bounds each one in zenoh's callback thread, and no
    exception escapes into that thread (threading.excepthook sees nothing)."""
    import threading
    import time

    from _support.ports import free_port
    from posekit.transport.zenoh_session import SessionOptions, open_session

    escaped: list[object] = []
    monkeypatch.setattr(threading, "excepthook", lambda args: escaped.append(args.exc_value))
    for var in ("ZENOH_SESSION_CONFIG_URI", "ZENOH_CONFIG_OVERRIDE", "ROS_DOMAIN_ID"):
        monkeypatch.delenv(var, raising=False)
    options = SessionOptions(router_endpoint=f"tcp/127.0.0.1:{free_port()}")
    victim = open_session(options)
    peer = open_session(options)
    rng = random.Random(13)
    tokens = _valid_tokens()
    declared = []
    keys: set[str] = set()
    try:
        for i in range(400):
            key = _mutate_token(rng, tokens[i % len(tokens)])
            if not key.startswith("@ros2_lv/0/"):
                key = "@ros2_lv/0/" + key.lstrip("@/")
            try:
                declared.append(peer.session.liveliness().declare_token(key))
            except Exception:  # zenoh refuses key expressions that are not well formed
                continue
            if "*" not in key and "$" not in key:  # wildcards are zenoh's to interpret
                keys.add(key)
        graph = victim.graph
        cache = graph.cache
        # Zenoh canonicalises some key expressions (two declared keys may arrive as one),
        # so most, not necessarily all, distinct keys show up as distinct tokens.
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline:
            seen = len(graph.entities()) + cache.rejected + cache.overflowed
            if seen >= 0.9 * len(keys):
                break
            time.sleep(0.05)
        assert len(keys) > 100
        assert seen >= 0.9 * len(keys), (seen, len(keys))
        assert cache.rejected > 0
        graph.node_names()
        graph.topic_names_and_types()
        for token in declared:
            token.undeclare()
    finally:
        peer.close()
        victim.close()
    assert escaped == []
