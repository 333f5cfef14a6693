"""``posekit service echo``: a service's introspection events as ``ros2 service echo`` prints them.

Oracle: ros2cli's ros2service echo verb (Jazzy): each event as block YAML, the event type by
name (``REQUEST_SENT``...), then ``---``; a warning line while nobody publishes events. The
events themselves are the service's and client's (rclpy's service introspection, compared
with the real rclpy in tests/runtime/test_service_introspection.py).
"""

from __future__ import annotations

import io
import threading
import time

import yaml

from posekit.cli import service_cmd
from posekit.msgs.std_srvs import SetBool
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.qos import qos_profile_services_default
from posekit.runtime.services import ServiceIntrospectionState


def test_echo_prints_the_four_events_of_a_call(ctx) -> None:
    server_node, client_node = Node("server", context=ctx), Node("client", context=ctx)
    service = server_node.create_service(
        SetBool, "/flag", lambda q, r: SetBool.Response(success=q.data, message="done"))
    client = client_node.create_client(SetBool, "/flag")
    for entity in (service, client):
        entity.configure_introspection(client_node.get_clock(), qos_profile_services_default,
                                       ServiceIntrospectionState.CONTENTS)
    executor = SingleThreadedExecutor(context=ctx)
    executor.add_node(server_node)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    out, err = io.StringIO(), io.StringIO()
    codes: list[int] = []
    echo = threading.Thread(target=lambda: codes.append(service_cmd.main_echo(
        ["/flag", "--count", "4", "--timeout", "20"], context=ctx, out=out, err=err)))
    echo.start()
    try:
        deadline = time.monotonic() + 10
        while client_node.count_subscribers("/flag/_service_event") < 1:
            assert time.monotonic() < deadline, "echo never subscribed"
            time.sleep(0.01)
        assert client.call(SetBool.Request(data=True), timeout_sec=5.0).success
        echo.join(25)
    finally:
        executor.shutdown()
        spinner.join(5)
    assert codes == [0], err.getvalue()
    blocks = [b for b in out.getvalue().split("---\n") if b.strip()]
    assert len(blocks) == 4, out.getvalue()
    events = [yaml.safe_load(b) for b in blocks]
    assert sorted(e["info"]["event_type"] for e in events) == [
        "REQUEST_RECEIVED", "REQUEST_SENT", "RESPONSE_RECEIVED", "RESPONSE_SENT"]
    assert list(events[0]) == ["info", "request", "response"]
    assert list(events[0]["info"]) == ["event_type", "stamp", "client_gid", "sequence_number"]
    for event in events:
        assert event["info"]["sequence_number"] == 1
        if event["info"]["event_type"].startswith("REQUEST"):
            assert (event["request"], event["response"]) == ([{"data": True}], [])
        else:
            assert event["response"] == [{"success": True, "message": "done"}]


def test_echo_says_when_nobody_publishes_events_and_refuses_unknown_services(ctx) -> None:
    node = Node("quiet_server", context=ctx)
    node.create_service(SetBool, "/quiet", lambda q, r: r)
    out = io.StringIO()
    assert service_cmd.main_echo(["/quiet", "--timeout", "0.3"], context=ctx, out=out) == 0
    assert out.getvalue() == ("No publishers on topic '/quiet/_service_event'; is service "
                              "introspection on the client or server enabled?\n")
    err = io.StringIO()
    assert service_cmd.main_echo(["/nowhere", "--timeout", "0.3"], context=ctx,
                                 out=io.StringIO(), err=err) == 1
    assert err.getvalue().count("\n") == 1
    assert "Could not load the type for the passed service" in err.getvalue()
