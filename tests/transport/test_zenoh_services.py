"""Services over Zenoh against a hand-written peer speaking rmw_zenoh's service wire format.

Oracles (none of them posekit code): the key expression, token and attachment layouts of
the rmw_zenoh spec (``<domain>/<service>/<pkg>::srv::dds_::<Srv>_/<hash>``, ``SS``/``SC``
liveliness tokens, 33-byte attachments, reply attachment = the request's sequence number
and client GID), the SetBool type hash ROS 2 Jazzy ships in
``share/std_srvs/srv/SetBool.json``, CDR bytes written out by hand, and ``xxhash`` for GIDs.
"""

from __future__ import annotations

import struct
import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest
import xxhash
import zenoh

from _support.ports import free_port
from _support.waiting import wait_for
from posekit.msgs.std_srvs import SetBool
from posekit.transport.zenoh_session import SessionOptions, ZenohSession, open_session
from posekit.transport.zenoh_wire import WireQoS

pytestmark = pytest.mark.slow

SETBOOL_HASH = "RIHS01_abe9e4bb6b41b40e6789712c00ec8871923e089af3f667a79992a428cff2da0a"
KEY = f"0/flip/std_srvs::srv::dds_::SetBool_/{SETBOOL_HASH}"
REQUEST_TRUE = b"\x00\x01\x00\x00\x01"  # CDR_LE header + bool data=true


def response_cdr(success: bool, message: str) -> bytes:
    text = message.encode() + b"\x00"
    head = b"\x00\x01\x00\x00" + bytes([success]) + b"\x00" * 3
    return head + struct.pack("<I", len(text)) + text


def parse_response(payload: bytes) -> tuple[bool, str]:
    assert payload[:4] == b"\x00\x01\x00\x00"
    (length,) = struct.unpack_from("<I", payload, 8)
    return bool(payload[4]), payload[12:12 + length - 1].decode()


def attachment(seq: int, gid: bytes) -> bytes:
    return struct.pack("<qqB", seq, time.time_ns(), 16) + gid




@pytest.fixture
def sessions(monkeypatch: pytest.MonkeyPatch) -> Iterator[tuple[ZenohSession, ZenohSession]]:
    for var in ("ZENOH_SESSION_CONFIG_URI", "ZENOH_CONFIG_OVERRIDE", "ROS_DOMAIN_ID"):
        monkeypatch.delenv(var, raising=False)
    options = SessionOptions(router_endpoint=f"tcp/127.0.0.1:{free_port()}")
    ours, peer = open_session(options), open_session(options)
    yield ours, peer
    peer.close()
    ours.close()


def tokens(session: zenoh.Session) -> set[str]:
    return {str(r.ok.key_expr) for r in session.liveliness().get("@ros2_lv/0/**") if r.ok}


def test_posekit_server_answers_a_hand_written_rmw_zenoh_client(sessions) -> None:
    ours, peer = sessions
    node = ours.create_node("flag_server")
    requests: list[Any] = []
    callers: list[tuple[bytes, int]] = []

    def on_request(request: Any, respond: Callable[[Any], None], att: Any) -> None:
        requests.append(request)
        callers.append((att.gid, att.sequence_number))
        threading.Thread(  # answered later, from another thread, as an executor does
            target=respond, args=(SetBool.Response(success=not request.data, message="ok"),)
        ).start()

    server = ours.create_service_server(node, "/flip", SetBool, WireQoS(depth=10), on_request)
    assert server.key == KEY
    expected_token = (f"@ros2_lv/0/{ours.zid}/{node.node_id}/{server.entity_id}/SS/%/%/"
                      f"flag_server/%flip/std_srvs::srv::dds_::SetBool_/{SETBOOL_HASH}/::,10:,:,:,,")
    assert server.token_key == expected_token
    assert wait_for(lambda: expected_token in tokens(peer.session))

    client_gid = bytes(range(16))
    replies: list[tuple[str, bytes, bytes]] = []

    def query() -> bool:
        for reply in peer.session.get(
            KEY, payload=REQUEST_TRUE, attachment=attachment(41, client_gid),
            target=zenoh.QueryTarget.ALL_COMPLETE, timeout=2.0,
        ):
            if reply.ok is not None:
                replies.append((str(reply.ok.key_expr), reply.ok.payload.to_bytes(),
                                reply.ok.attachment.to_bytes()))
        return bool(replies)

    assert wait_for(query)
    key, payload, att = replies[0]
    assert key == KEY
    assert parse_response(payload) == (False, "ok")
    assert len(att) == 33
    assert struct.unpack_from("<q", att, 0)[0] == 41  # the client's sequence number
    assert att[16] == 0x10
    assert att[17:] == client_gid  # the client's GID, echoed
    assert [r.data for r in requests] == [True]
    assert callers == [(client_gid, 41)]  # the server learns who called (rmw's request id)
    # a query without an attachment is dropped (rmw_zenoh needs one), nothing crashes
    list(peer.session.get(KEY, payload=REQUEST_TRUE, timeout=0.5))
    assert wait_for(lambda: server.dropped["attachment"] == 1)
    assert len(requests) == 1


def test_posekit_client_queries_a_hand_written_rmw_zenoh_server(sessions) -> None:
    ours, peer = sessions
    seen: list[tuple[bytes, bytes]] = []

    def serve(q: zenoh.Query) -> None:
        att = q.attachment.to_bytes()
        seen.append((q.payload.to_bytes(), att))
        seq = struct.unpack_from("<q", att, 0)[0]
        if seq == 2:  # first a reply for another request: the client must ignore it
            q.reply(KEY, response_cdr(True, "stray"), attachment=attachment(99, att[17:33]))
        q.reply(KEY, response_cdr(seq % 2 == 1, f"seq {seq}"),
                attachment=attachment(seq, att[17:33]))

    queryable = peer.session.declare_queryable(KEY, serve, complete=True)
    # A real rmw_zenoh server announces itself with an SS token after its queryable; a client
    # waits for it (wait_for_service): declarations arrive in order, so the queryable is
    # reachable once the token is seen.
    server_token = (f"@ros2_lv/0/{peer.zid}/0/1/SS/%/%/flag_server/%flip/"
                    f"std_srvs::srv::dds_::SetBool_/{SETBOOL_HASH}/::,10:,:,:,,")
    token = peer.session.liveliness().declare_token(server_token)
    assert wait_for(lambda: server_token in tokens(ours.session))
    node = ours.create_node("flag_client")
    client = ours.create_service_client(node, "/flip", SetBool, WireQoS(depth=10))
    assert client.token_key.split("/")[5] == "SC"
    expected_gid = xxhash.xxh3_128(client.token_key.encode()).intdigest().to_bytes(16, "little")
    assert client.gid == expected_gid
    got: list[Any] = []
    for _ in range(2):
        done = threading.Event()
        client.send_request(SetBool.Request(data=True),
                            lambda r, done=done: (got.append(r), done.set()))
        assert done.wait(10), "no response"
    assert [(r.success, r.message) for r in got] == [(True, "seq 1"), (False, "seq 2")]
    assert [p for p, _ in seen] == [REQUEST_TRUE, REQUEST_TRUE]
    for i, (_, att) in enumerate(seen, start=1):
        assert len(att) == 33
        assert struct.unpack_from("<q", att, 0)[0] == i  # sequence numbers from 1
        assert att[17:] == client.gid
    token.undeclare()
    queryable.undeclare()


def test_a_server_of_another_type_definition_is_not_counted(sessions, logs) -> None:
    """A server announced with another type hash (another definition of SetBool) cannot
    receive our requests (the hash is part of the key): the client does not count it and
    says why, once."""
    from posekit.runtime.context import Context
    from posekit.runtime.node import Node
    from posekit.transport.zenoh_transport import ZenohTransport

    ours, peer = sessions
    ctx = Context()
    ctx.init()
    try:
        transport = ZenohTransport(session=ours)
        node = Node("flag_client", context=ctx, transport=transport,
                    start_parameter_services=False)
        client = node.create_client(SetBool, "/flip")
        other_hash = "RIHS01_" + "0" * 64
        token = peer.session.liveliness().declare_token(
            f"@ros2_lv/0/{peer.zid}/7/8/SS/%/%/other_server/%flip/"
            f"std_srvs::srv::dds_::SetBool_/{other_hash}/::,10:,:,:,,"
        )
        assert wait_for(lambda: len(transport.graph.services("/flip")) == 1)
        assert not client.service_is_ready()
        assert client.wait_for_service(timeout_sec=0.1) is False
        warned = [r.message for r in logs if "requests do not reach it" in r.message]
        assert len(warned) == 1
        assert "/other_server" in warned[0]
        assert other_hash in warned[0]
        token.undeclare()
    finally:
        ctx.shutdown()
