"""Service calls over the network transports (Zenoh and DDS), two contexts in one process.

Oracles: the responses the server computes from each request (every call gets its own),
the thread that runs the server's callback (the spinning one), and a blocking call made
from a response's done-callback, which can only return its response if that callback does
not hold the transport's receive thread (which must deliver the nested call's response).
"""

from __future__ import annotations

import threading
import time
from typing import Any

import pytest

from _support.network import network_contexts
from _support.waiting import wait_for
from posekit.msgs.std_srvs import SetBool
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node

pytestmark = pytest.mark.slow

TRANSPORTS = ["zenoh", "dds"]


def _flip_server(node: Node, served_on: set[int] | None = None,
                 release: threading.Event | None = None) -> None:
    def serve(request: Any, response: Any) -> Any:
        if served_on is not None:
            served_on.add(threading.get_ident())
        if release is not None:
            assert release.wait(10)
        response.success = request.data
        response.message = f"got {request.data}"
        return response

    node.create_service(SetBool, "/flip", serve)


@pytest.mark.parametrize("transport", TRANSPORTS)
def test_a_blocking_call_in_a_callback_is_served_by_the_same_executor(
    transport: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``Client.call`` inside a timer callback, its server on another node of the same
    executor: the request goes out over the transport and comes back as network work,
    which the calling executor takes while it waits."""
    with network_contexts(transport, monkeypatch) as (_, context):
        server_node, client_node = Node("server", context=context), Node("client", context=context)
        served_on: set[int] = set()
        _flip_server(server_node, served_on)
        client = client_node.create_client(SetBool, "/flip")
        assert client.wait_for_service(timeout_sec=10)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(server_node)
        executor.add_node(client_node)
        answers: list[Any] = []

        def tick() -> None:
            answers.append(client.call(SetBool.Request(data=len(answers) % 2 == 0),
                                       timeout_sec=10))
            if len(answers) == 6:
                timer.cancel()

        timer = client_node.create_timer(0.01, tick)
        spinner = threading.Thread(target=executor.spin, daemon=True)
        spinner.start()
        try:
            assert wait_for(lambda: len(answers) >= 6, 60)
        finally:
            executor.shutdown()
            spinner.join(timeout=5)
        assert [(a.success, a.message) for a in answers] == [
            (i % 2 == 0, f"got {i % 2 == 0}") for i in range(6)
        ]
        assert served_on == {spinner.ident}


@pytest.mark.parametrize("transport", TRANSPORTS)
def test_a_done_callback_of_a_node_without_executor_may_make_a_blocking_call(
    transport: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Without an executor a response completes its future where it arrives; the future's
    done-callbacks (user code) still run off the transport's receive thread, so one may
    call the service again and wait for that response."""
    with network_contexts(transport, monkeypatch) as (client_context, server_context):
        server_node = Node("server", context=server_context)
        release = threading.Event()  # the first response waits for the done-callback
        _flip_server(server_node, release=release)
        executor = SingleThreadedExecutor(context=server_context)
        executor.add_node(server_node)
        spinner = threading.Thread(target=executor.spin, daemon=True)
        spinner.start()
        try:
            client = Node("client", context=client_context).create_client(SetBool, "/flip")
            assert client.wait_for_service(timeout_sec=10)
            nested: list[Any] = []
            callback_threads: list[int] = []

            def on_done(_future: Any) -> None:
                callback_threads.append(threading.get_ident())
                started = time.monotonic()
                nested.append(client.call(SetBool.Request(data=False), timeout_sec=5))
                nested.append(time.monotonic() - started)

            future = client.call_async(SetBool.Request(data=True))
            future.add_done_callback(on_done)
            release.set()
            assert wait_for(lambda: len(nested) == 2, 20)
            assert callback_threads != [threading.get_ident()]  # run where the response came
            assert future.result().message == "got True"
            assert nested[0] is not None, f"the nested call timed out after {nested[1]:.1f} s"
            assert (nested[0].success, nested[0].message) == (False, "got False")
        finally:
            executor.shutdown()
            spinner.join(timeout=5)
