"""Services on the in-process bus: create_service / create_client, call_async, call,
wait_for_service, graph queries, executors (single-, multi-threaded, simulated time).

Oracle: rclpy's documented behaviour (the request reaches the callback with a fresh
Response, the future completes with what the callback returned, TypeError for a request of
another type, None from ``call`` after a timeout); the same scripts run against the real
rclpy in tests/rclpy/test_differential.py.
"""

from __future__ import annotations

import threading
from typing import Any

import pytest

from posekit.msgs.std_srvs import Empty, SetBool, Trigger
from posekit.runtime.callback_groups import ReentrantCallbackGroup
from posekit.runtime.executors import MultiThreadedExecutor, SingleThreadedExecutor
from posekit.runtime.names import InvalidServiceNameException
from posekit.runtime.node import Node
from posekit.runtime.parameters import Parameter
from posekit.runtime.sim_executor import SimulatedTimeExecutor
from posekit.runtime.transport import TopicTypeMismatchError


def _set_bool_server(node: Node, name: str = "set_flag") -> list[bool]:
    seen: list[bool] = []

    def on_request(request: SetBool.Request, response: SetBool.Response) -> SetBool.Response:
        seen.append(request.data)
        response.success = request.data
        response.message = f"set to {request.data}"
        return response

    node.create_service(SetBool, name, on_request)
    return seen


def test_call_async_completes_on_the_executor(ctx) -> None:
    server, client_node = Node("server", context=ctx), Node("client", context=ctx)
    seen = _set_bool_server(server)
    client = client_node.create_client(SetBool, "set_flag")
    assert client.wait_for_service(timeout_sec=1.0)
    assert client.service_is_ready()
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(server)
    ex.add_node(client_node)
    future = client.call_async(SetBool.Request(data=True))
    assert not future.done()  # nothing runs before the executor spins
    ex.spin_until_future_complete(future, timeout_sec=5.0)
    assert future.done()
    assert future.result() == SetBool.Response(success=True, message="set to True")
    assert seen == [True]


def test_request_of_the_wrong_type_is_a_type_error(ctx) -> None:
    client = Node("client", context=ctx).create_client(SetBool, "set_flag")
    with pytest.raises(TypeError):
        client.call_async(Trigger.Request())


def test_service_names_are_expanded_remapped_and_validated(ctx) -> None:
    node = Node("cam", namespace="/robot1", context=ctx, remappings={"reset": "/global_reset"})
    assert node.create_service(Empty, "~/enable", lambda q, r: r).service_name == (
        "/robot1/cam/enable"
    )
    assert node.create_service(Empty, "calibrate", lambda q, r: r).service_name == (
        "/robot1/calibrate"
    )
    assert node.create_client(Empty, "reset").service_name == "/global_reset"
    with pytest.raises(InvalidServiceNameException):
        node.create_service(Empty, "bad name", lambda q, r: r)
    with pytest.raises(TypeError):
        node.create_service(Empty.Request, "x", lambda q, r: r)  # a message, not a service


#: A node without the services every node offers (parameters, type descriptions).
BARE: dict[str, Any] = {"start_parameter_services": False, "parameter_overrides": [
    Parameter("start_type_description_service", value=False)]}


def test_graph_lists_services_and_who_serves_them(ctx) -> None:
    server = Node("server", namespace="/ns", context=ctx, **BARE)
    _set_bool_server(server)
    client_node = Node("client", context=ctx, **BARE)
    client_node.create_client(Trigger, "/ns/trigger_me")
    assert ("/ns/set_flag", ["std_srvs/srv/SetBool"]) in client_node.get_service_names_and_types()
    assert ("/ns/trigger_me", ["std_srvs/srv/Trigger"]) in (
        client_node.get_service_names_and_types()
    )
    assert client_node.get_service_names_and_types_by_node("server", "/ns") == [
        ("/ns/set_flag", ["std_srvs/srv/SetBool"])
    ]
    assert client_node.get_client_names_and_types_by_node("client", "/") == [
        ("/ns/trigger_me", ["std_srvs/srv/Trigger"])
    ]
    with pytest.raises(TopicTypeMismatchError):
        client_node.create_client(Trigger, "/ns/set_flag")


def test_destroyed_service_is_no_longer_ready(ctx) -> None:
    server = Node("server", context=ctx, **BARE)
    client_node = Node("client", context=ctx, **BARE)
    service = server.create_service(Empty, "ping", lambda q, r: r)
    client = client_node.create_client(Empty, "ping")
    assert client.service_is_ready()
    assert server.destroy_service(service)
    assert not server.destroy_service(service)
    assert not client.service_is_ready()
    assert client.wait_for_service(timeout_sec=0.05) is False
    assert client_node.destroy_client(client)
    assert client_node.get_service_names_and_types() == []


def test_blocking_call_from_another_thread_while_the_executor_spins(ctx) -> None:
    server, client_node = Node("server", context=ctx), Node("client", context=ctx)
    _set_bool_server(server)
    client = client_node.create_client(SetBool, "set_flag")
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(server)
    ex.add_node(client_node)
    spinner = threading.Thread(target=ex.spin, daemon=True)
    spinner.start()
    try:
        response = client.call(SetBool.Request(data=True), timeout_sec=5.0)
        assert response == SetBool.Response(success=True, message="set to True")
    finally:
        ex.shutdown()
        spinner.join(timeout=5.0)
    assert not spinner.is_alive()


def test_blocking_call_inside_a_callback_does_not_deadlock(ctx) -> None:
    """rclpy's single-threaded executor would deadlock here; posekit serves the request."""
    server, client_node = Node("server", context=ctx), Node("client", context=ctx)
    _set_bool_server(server)
    client = client_node.create_client(SetBool, "set_flag")
    results: list[object] = []

    def tick() -> None:
        results.append(client.call(SetBool.Request(data=False), timeout_sec=5.0))
        timer.cancel()

    timer = client_node.create_timer(0.001, tick)
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(server)
    ex.add_node(client_node)
    for _ in range(100):
        if results:
            break
        ex.spin_once(timeout_sec=1.0)
    assert results == [SetBool.Response(success=False, message="set to False")]


def test_without_an_executor_the_response_completes_the_future_when_the_server_answers(
    ctx,
) -> None:
    """In process, the response completes the future of a client node in no executor on
    the thread that ran the server's callback, before that executor's spin_once returns."""
    server, client_node = Node("server", context=ctx), Node("client", context=ctx)
    _set_bool_server(server)
    client = client_node.create_client(SetBool, "set_flag")
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(server)
    done_on: list[int] = []
    future = client.call_async(SetBool.Request(data=True))
    future.add_done_callback(lambda _f: done_on.append(threading.get_ident()))
    ex.spin_once(timeout_sec=5.0)
    assert future.done()
    assert future.result() == SetBool.Response(success=True, message="set to True")
    assert done_on == [threading.get_ident()]


def test_blocking_call_without_any_executor_returns_none_after_the_timeout(ctx) -> None:
    server, client_node = Node("server", context=ctx), Node("client", context=ctx)
    _set_bool_server(server)  # never spun: nobody runs the server's callback
    client = client_node.create_client(SetBool, "set_flag")
    assert client.call(SetBool.Request(data=True), timeout_sec=0.05) is None


def test_multithreaded_executor_with_reentrant_group(ctx) -> None:
    node = Node("both", context=ctx)
    group = ReentrantCallbackGroup()
    node.create_service(
        SetBool, "set_flag", lambda q, r: SetBool.Response(success=not q.data), callback_group=group
    )
    client = node.create_client(SetBool, "set_flag", callback_group=group)
    ex = MultiThreadedExecutor(num_threads=2, context=ctx)
    ex.add_node(node)
    # 10 at once: the service QoS default keeps the last 10 waiting requests
    futures = [client.call_async(SetBool.Request(data=i % 2 == 0)) for i in range(10)]
    for f in futures:
        ex.spin_until_future_complete(f, timeout_sec=5.0)
    assert [f.result().success for f in futures] == [i % 2 == 1 for i in range(10)]


def test_async_service_callback_is_awaited(ctx, executor: SimulatedTimeExecutor) -> None:
    node = Node("n", context=ctx)
    inner = node.create_client(Trigger, "inner")
    node.create_service(Trigger, "inner", lambda q, r: Trigger.Response(True, "inner ok"))

    async def outer(request: Trigger.Request, response: Trigger.Response) -> Trigger.Response:
        got = await inner.call_async(Trigger.Request())
        response.success = got.success
        response.message = "outer saw " + got.message
        return response

    node.create_service(Trigger, "outer", outer, callback_group=ReentrantCallbackGroup())
    client = node.create_client(Trigger, "outer")
    executor.add_node(node)
    future = client.call_async(Trigger.Request())
    executor.spin_until_future_complete(future, timeout_sec=1.0)
    assert future.result() == Trigger.Response(True, "outer saw inner ok")


def test_wrong_response_type_is_logged_and_not_sent(ctx, logs) -> None:
    node = Node("n", context=ctx)
    node.create_service(SetBool, "bad", lambda q, r: "not a response")
    client = node.create_client(SetBool, "bad")
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(node)
    future = client.call_async(SetBool.Request())
    ex.spin_until_future_complete(future, timeout_sec=0.2)
    assert not future.done()
    assert any("returned str, expected SetBool_Response" in r.message for r in logs)


def test_simulated_time_serves_requests_deterministically(ctx) -> None:
    """Two clients calling from timers: the order of handling is the same every run."""

    def run() -> list[str]:
        from posekit.runtime.context import Context

        context = Context()
        context.init()
        try:
            ex = SimulatedTimeExecutor(context=context, publish_clock=False)
            order: list[str] = []
            server = Node("server", context=context)

            def on_request(q: SetBool.Request, r: SetBool.Response) -> SetBool.Response:
                order.append(f"serve {q.data} @{ex.now_ns}")
                r.success = q.data
                return r

            server.create_service(SetBool, "s", on_request)
            for name, flag in (("a", True), ("b", False)):
                node = Node(name, context=context)
                client = node.create_client(SetBool, "/s")

                def tick(client=client, flag=flag, name=name) -> None:
                    f = client.call_async(SetBool.Request(data=flag))
                    f.add_done_callback(
                        lambda f, name=name: order.append(f"{name} got {f.result().success}")
                    )

                node.create_timer(0.1, tick)
                ex.add_node(node)
            ex.add_node(server)
            ex.run_until(0.3)
            return order
        finally:
            context.shutdown()

    first = run()
    assert first == run()
    assert first[:4] == [
        "serve True @100000000", "serve False @100000000", "a got True", "b got False",
    ]


def test_a_transport_without_services_says_so(ctx) -> None:
    from posekit.runtime.bus import InProcessBus
    from posekit.runtime.transport import ServicesNotSupportedError, Transport

    class TopicsOnly(Transport):
        """Topics through a bus; services left at the contract's default."""

        name = "topics_only"

        def __init__(self) -> None:
            self.bus = InProcessBus()

        def advertise(self, info):
            return self.bus.advertise(info)

        def subscribe(self, info, sink):
            return self.bus.subscribe(info, sink)

        def get_topic_names_and_types(self):
            return self.bus.get_topic_names_and_types()

        def count_publishers(self, topic):
            return self.bus.count_publishers(topic)

        def count_subscribers(self, topic):
            return self.bus.count_subscribers(topic)

    node = Node("plain", context=ctx, transport=TopicsOnly())  # no parameter services: fine
    assert node.get_service_names_and_types() == []
    assert node.count_services("x") == 0
    with pytest.raises(ServicesNotSupportedError, match="'topics_only' transport does not carry"):
        node.create_service(Empty, "x", lambda q, r: r)
    with pytest.raises(ServicesNotSupportedError):
        node.create_client(Empty, "x")
    node.declare_parameter("still", 1)  # parameters work; /parameter_events is a topic
    assert node.get_parameter("still").value == 1


def test_waiting_requests_are_bounded_by_the_qos_depth(ctx) -> None:
    from posekit.runtime.qos import QoSProfile

    server = Node("server", context=ctx, start_parameter_services=False)
    seen: list[bool] = []
    server.create_service(SetBool, "s", lambda q, r: (seen.append(q.data), r)[1],
                          qos_profile=QoSProfile(depth=2))
    client_node = Node("client", context=ctx, start_parameter_services=False)
    client = client_node.create_client(SetBool, "s")
    futures = [client.call_async(SetBool.Request(data=i >= 3)) for i in range(5)]
    ex = SingleThreadedExecutor(context=ctx)  # nothing ran while the requests piled up
    ex.add_node(server)
    ex.add_node(client_node)
    ex.spin_until_future_complete(futures[-1], timeout_sec=5.0)
    ex.spin_some()
    assert seen == [True, True]  # the two newest; the three oldest were dropped
    assert [f.done() for f in futures] == [False, False, False, True, True]
