"""Transport selection (node option, init option, POSEKIT_TRANSPORT) and the registry."""

from __future__ import annotations

import pytest

from posekit.runtime.bus import InProcessBus
from posekit.runtime.context import Context
from posekit.runtime.node import Node
from posekit.runtime.transport import (
    ENV_TRANSPORT,
    UnknownTransportError,
    register_transport,
    selected_transport_name,
)


class RecordingBus(InProcessBus):
    """A distinguishable transport: the in-process bus under another name."""

    name = "recording"


register_transport("recording", RecordingBus)


def test_default_is_inprocess_and_shared_per_context(ctx, monkeypatch) -> None:
    monkeypatch.delenv(ENV_TRANSPORT, raising=False)
    a, b = Node("a", context=ctx), Node("b", context=ctx)
    assert type(a.transport) is InProcessBus
    assert a.transport is b.transport
    other = Context()
    other.init()
    try:
        assert Node("c", context=other).transport is not a.transport  # contexts are isolated
    finally:
        other.shutdown()


def test_env_and_options_select(monkeypatch) -> None:
    monkeypatch.setenv(ENV_TRANSPORT, "recording")
    assert selected_transport_name() == "recording"
    assert selected_transport_name("inprocess") == "inprocess"
    context = Context()
    context.init()
    try:
        assert type(Node("a", context=context).transport) is RecordingBus
        assert type(Node("b", context=context, transport="inprocess").transport) is InProcessBus
    finally:
        context.shutdown()
    monkeypatch.delenv(ENV_TRANSPORT)
    context = Context()
    context.init(transport="recording")
    try:
        assert type(Node("a", context=context).transport) is RecordingBus
    finally:
        context.shutdown()


def test_unknown_transport_is_a_clear_error(ctx, monkeypatch) -> None:
    monkeypatch.setenv(ENV_TRANSPORT, "carrier_pigeon")
    with pytest.raises(UnknownTransportError, match=r"carrier_pigeon.*known:.*inprocess"):
        Node("a", context=ctx)
