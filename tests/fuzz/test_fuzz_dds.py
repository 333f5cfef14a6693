"""Bounded, seeded fuzzer: what a DDS peer controls, i.e. sample payloads on a topic, service
requests, the ``ros_discovery_info`` announcements and an endpoint's USER_DATA.

Oracles: rosbags' CDR decoder for each payload sent over a real Cyclone DDS writer on
loopback (a payload it decodes must arrive as that message, in order; one it refuses must be
dropped and counted, never reach the callback), and the exception contracts of
``posekit.transport.dds_wire`` (``CdrError`` and nothing else for a discovery payload; no
exception at all for USER_DATA).
"""

from __future__ import annotations

import random
from collections.abc import Iterator
from typing import Any

import pytest

pytest.importorskip("cyclonedds")

from _support.dds import dds_context, dds_domain, spin_until, two_dds_contexts
from posekit.msgs.cdr import CdrError, get_typestore, to_cdr
from posekit.msgs.std_msgs import String
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.logging import get_logger
from posekit.runtime.node import Node
from posekit.runtime.qos import QoSProfile
from posekit.runtime.transport import EndpointInfo
from posekit.transport.dds_wire import (
    NodeEntities,
    ParticipantEntities,
    decode_participant_entities,
    encode_participant_entities,
    parse_user_data,
)

pytestmark = pytest.mark.slow

SEED = 20261124
DEPTH = 1000  # KEEP_LAST deep enough that nothing sent here is replaced before it is read


def _mutate(rng: random.Random, data: bytes) -> bytes:
    """One malformation of ``data``: truncated, bits flipped, extended, a huge length field,
    another encapsulation, or plain random bytes."""
    kind = rng.randrange(6)
    if kind == 0:
        return data[: rng.randrange(len(data))]
    if kind == 1:
        out = bytearray(data)
        for _ in range(rng.randint(1, 4)):
            out[rng.randrange(len(out))] ^= 1 << rng.randrange(8)
        return bytes(out)
    if kind == 2:
        return data + rng.randbytes(rng.randint(1, 16))
    if kind == 3 and len(data) >= 8:  # the first length field (after the 4-byte header)
        return data[:4] + rng.choice([0xFFFFFFFF, 0x7FFFFFF0, 4096]).to_bytes(4, "little") \
            + data[8:]
    if kind == 4:
        return bytes([0, rng.choice([2, 3, 0x10, 0xFF])]) + data[2:]
    return rng.randbytes(rng.randint(4, 64))


def _rosbags_decodes(data: bytes) -> str | None:
    """The string rosbags reads from ``data``, or None when it refuses the payload."""
    try:
        msg = get_typestore().deserialize_cdr(data, "std_msgs/msg/String")
    except Exception:  # rosbags raises several types for malformed input
        return None
    return str(msg.data)


@pytest.fixture
def two(monkeypatch: pytest.MonkeyPatch) -> Iterator[tuple[Context, Context]]:
    with two_dds_contexts(monkeypatch) as pair:
        yield pair


def test_malformed_samples_from_a_peer_are_dropped_and_the_rest_arrive_in_order(
        two: tuple[Context, Context]) -> None:
    sender, receiver = two
    rng = random.Random(SEED)
    qos = QoSProfile(depth=DEPTH)
    writer = sender.transport().advertise(EndpointInfo(
        "/fuzz", String, qos, "fuzzer", "/", get_logger("fuzzer")))
    node = Node("fuzz_listener", context=receiver)
    got: list[str] = []
    sub = node.create_subscription(String, "/fuzz", lambda m: got.append(m.data), qos)
    executor = SingleThreadedExecutor(context=receiver)
    executor.add_node(node)
    probe = to_cdr(String(data="probe"), "std_msgs/msg/String")
    # matched: the probe arrives (a sample written before matching would be lost)
    assert spin_until(executor, lambda: "probe" in got, 20,
                      lambda: writer.publish_serialized(probe))  # type: ignore[attr-defined]
    got.clear()
    endpoint = sub.endpoint
    assert endpoint is not None
    received_before, dropped_before = endpoint.received, endpoint.dropped  # type: ignore[attr-defined]

    candidates: list[bytes] = []
    for i in range(150):
        good = to_cdr(String(data=f"good {i}"), "std_msgs/msg/String")
        candidates += [good, _mutate(rng, good)]
    candidates += [rng.randbytes(rng.randint(4, 200)) for _ in range(50)]
    sent: list[bytes] = []
    for data in candidates:
        try:
            writer.publish_serialized(data)  # type: ignore[attr-defined]
        except RuntimeError:  # Cyclone's writer refuses some (a length past the end)
            continue
        sent.append(data)
    expected = [text for text in map(_rosbags_decodes, sent) if text is not None]
    refused = sum(_rosbags_decodes(data) is None for data in sent)
    assert refused >= 20, (len(sent), refused)  # malformed payloads did go out
    assert spin_until(executor, lambda: len(got) >= len(expected)
                      and endpoint.received + endpoint.dropped  # type: ignore[attr-defined]
                      >= received_before + dropped_before + len(sent), 30)
    spin_until(executor, lambda: False, 0.3)  # nothing more arrives
    assert got == expected
    assert endpoint.dropped - dropped_before == refused  # type: ignore[attr-defined]
    writer.destroy()


def test_discovery_announcements_decode_or_raise_cdr_error() -> None:
    rng = random.Random(SEED)
    valid = encode_participant_entities(ParticipantEntities(
        bytes(range(16)),
        [NodeEntities("/", "talker", [bytes([1] * 16)], [bytes([2] * 16), bytes([3] * 16)]),
         NodeEntities("/robot", "ekf_node", [], [bytes([4] * 16)])]))
    decoded = refused = 0
    for _ in range(3000):
        data = _mutate(rng, valid)
        try:
            entities = decode_participant_entities(data)
        except CdrError:
            refused += 1
            continue
        decoded += 1
        assert isinstance(entities.gid, bytes)
        for node in entities.nodes:
            assert isinstance(node.name, str)
            assert isinstance(node.namespace, str)
            assert all(isinstance(g, bytes) for g in (*node.reader_gids, *node.writer_gids))
    assert refused > 1000  # most malformations are refused, none with another exception
    assert decoded > 0


def test_user_data_of_any_bytes_parses_to_strings() -> None:
    rng = random.Random(SEED)
    for _ in range(3000):
        data = rng.randbytes(rng.randint(0, 80))
        if rng.random() < 0.5:
            data = b"enclave=/;typehash=" + data + b";"
        parsed = parse_user_data(data)
        assert all(isinstance(k, str) and isinstance(v, str) for k, v in parsed.items())


def test_service_requests_are_delivered_exactly_when_header_and_body_decode(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """What a DDS peer sends a posekit service server: mutated rmw_cyclonedds requests.

    Oracle: the layout (4-byte encapsulation, uint64 client id, int64 sequence number, body)
    split here by hand, and rosbags' decoder for the body.
    """
    import struct

    from posekit.msgs.rcl_interfaces import GetParameters
    from posekit.runtime.transport import ServiceInfo

    dds_domain(monkeypatch)
    context = dds_context()
    try:
        node = Node("fuzzed_server", context=context)
        got: list[tuple[list[str], int, int]] = []
        server: Any = node.transport.create_service_server(
            ServiceInfo("/fuzzed", GetParameters, QoSProfile(depth=10), "fuzzed_server", "/",
                        get_logger("fuzz")),
            lambda request, respond, header: got.append((
                list(request.names), int.from_bytes(header.client_gid[:8], "little"),
                header.sequence_number)))
        rng = random.Random(SEED)
        body = to_cdr(GetParameters.Request(names=["k_rho", "goal_x"]))
        valid = body[:4] + struct.pack("<Qq", 0xA1B2C3D4E5F60718, 5) + body[4:]
        expected: list[tuple[list[str], int, int]] = []
        for _ in range(1500):
            data = _mutate(rng, valid) if rng.random() < 0.9 else valid
            if len(data) >= 20 and data[0] == 0 and data[1] in (0, 1):
                order = "<" if data[1] else ">"
                client_id, seq = struct.unpack_from(order + "Qq", data, 4)
                try:
                    msg = get_typestore().deserialize_cdr(
                        data[:4] + data[20:], "rcl_interfaces/srv/GetParameters_Request")
                    expected.append(([str(n) for n in msg.names], client_id, seq))
                except Exception:  # rosbags raises several types for malformed input
                    pass
            server._on_request(data, None)  # the service delivery thread calls this
        assert got == expected
        assert 0 < len(expected) < 1500
        assert sum(server.entities.dropped.values()) == 1500 - len(expected)
    finally:
        context.try_shutdown()
