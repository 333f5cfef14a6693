"""Services in bags: service introspection events recorded, listed, played back and replayed
as requests, as rosbag2 Jazzy does.

Oracles: the real ROS 2 Jazzy rclpy (``.venv-ros2``) deserializes every recorded event's CDR
bytes with its own ``std_srvs/srv/SetBool_Event`` type support and reports the fields;
rosbags (an independent reader) lists the bag's topics, types and counts and reads the MCAP
schema, which must be rosbag2 Jazzy's service definition text (``SRV:`` delimiter,
request ``---`` response, as rosbag2_cpp's LocalMessageDefinitionSource writes it);
``bag info``'s service lines are compared with the layout of rosbag2 Jazzy's
``format_bag_meta_data`` (rosbag2_py/src/rosbag2_py/format_bag_metadata.cpp), transcribed
below; the event sequence of one call follows rcl's service introspection (client
REQUEST_SENT, server REQUEST_RECEIVED, server RESPONSE_SENT, client RESPONSE_RECEIVED);
replayed requests are counted by the server that receives them.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest

from _support.ros2 import run_ros2_script
from posekit.bag import Player, Recorder, bag_info, format_info, read_messages
from posekit.msgs.std_srvs import SetBool
from posekit.runtime.context import Context
from posekit.runtime.node import Node
from posekit.runtime.qos import QoSProfile
from posekit.runtime.services import ServiceIntrospectionState
from posekit.runtime.sim_executor import SimulatedTimeExecutor

EVENT_TOPIC = "/toggle/_service_event"
EVENT_TYPE = "std_srvs/srv/SetBool_Event"
REQUEST_SENT, REQUEST_RECEIVED, RESPONSE_SENT, RESPONSE_RECEIVED = 0, 1, 2, 3


class Toggle(Node):
    """A SetBool server that answers ``success = data`` and ``message = "set <data>"``."""

    def __init__(self, context: Context, state: ServiceIntrospectionState | None) -> None:
        super().__init__("toggle_server", context=context)
        self.requests: list[bool] = []
        self.service = self.create_service(SetBool, "toggle", self.on_request)
        if state is not None:
            self.service.configure_introspection(self.get_clock(), QoSProfile(depth=10), state)

    def on_request(self, request: Any, response: Any) -> Any:
        self.requests.append(bool(request.data))
        response.success = bool(request.data)
        response.message = f"set {request.data}"
        return response


def record_calls(tmp_path: Path, server_state: ServiceIntrospectionState,
                 client_state: ServiceIntrospectionState, calls: int = 2,
                 **options: Any) -> Path:
    """A bag of ``calls`` SetBool calls (alternating True/False), one per 0.1 s of sim time."""
    context = Context()
    context.init(transport="inprocess")
    try:
        executor = SimulatedTimeExecutor(context=context, start_time=50.0)
        server = Toggle(context, server_state)
        caller = Node("toggle_client", context=context)
        client = caller.create_client(SetBool, "toggle")
        client.configure_introspection(caller.get_clock(), QoSProfile(depth=10), client_state)
        executor.add_node(server)
        executor.add_node(caller)
        recorder = Recorder(tmp_path / "svc", context=context, **options)
        executor.add_node(recorder.node)
        futures = []
        for k in range(calls):
            futures.append(client.call_async(SetBool.Request(data=k % 2 == 0)))
            executor.run_for(0.1)
        assert all(f.done() for f in futures)
        recorder.close()
    finally:
        context.try_shutdown()
    return tmp_path / "svc"


def rclpy_decode(datas: list[bytes]) -> list[dict[str, Any]]:
    """Every event decoded by the real rclpy's type support."""
    source = """
        import json
        HEX = json.loads(%r)
        from rclpy.serialization import deserialize_message
        from std_srvs.srv import SetBool
        out = []
        for hexdata in HEX:
            e = deserialize_message(bytes.fromhex(hexdata), SetBool.Event)
            out.append({
                "event_type": e.info.event_type,
                "stamp": [e.info.stamp.sec, e.info.stamp.nanosec],
                "client_gid": [int(b) for b in e.info.client_gid],
                "sequence_number": e.info.sequence_number,
                "request": [r.data for r in e.request],
                "response": [[r.success, r.message] for r in e.response],
            })
        print(json.dumps(out))
    """ % json.dumps([d.hex() for d in datas])  # noqa: UP031 - a script's text
    result = run_ros2_script(source, domain_id=0)
    assert result.returncode == 0, result.stderr
    decoded: list[dict[str, Any]] = json.loads(result.stdout.strip().splitlines()[-1])
    return decoded


@pytest.mark.slow  # runs the ROS 2 reference interpreter
def test_recorded_service_events_decode_with_ros2s_own_type_support(tmp_path: Path) -> None:
    bag = record_calls(tmp_path, ServiceIntrospectionState.CONTENTS,
                       ServiceIntrospectionState.CONTENTS, services=["toggle"])
    messages = list(read_messages(bag))
    assert {m.topic for m in messages} == {EVENT_TOPIC}
    assert {m.msgtype for m in messages} == {EVENT_TYPE}
    events = rclpy_decode([m.data for m in messages])
    assert [e["event_type"] for e in events] == [
        REQUEST_SENT, REQUEST_RECEIVED, RESPONSE_SENT, RESPONSE_RECEIVED] * 2
    assert [e["request"] for e in events] == [[True], [True], [], [], [False], [False], [], []]
    assert [e["response"] for e in events] == [
        [], [], [[True, "set True"]], [[True, "set True"]],
        [], [], [[False, "set False"]], [[False, "set False"]],
    ]
    client_events = [e for e in events if e["event_type"] in (REQUEST_SENT, RESPONSE_RECEIVED)]
    assert [e["sequence_number"] for e in client_events] == [1, 1, 2, 2]
    assert len({tuple(e["client_gid"]) for e in client_events}) == 1
    assert any(client_events[0]["client_gid"])  # a client id, not zeros
    server_events = [e for e in events if e["event_type"] in (REQUEST_RECEIVED, RESPONSE_SENT)]
    assert [e["sequence_number"] for e in server_events] == [1, 1, 2, 2]
    caller = tuple(client_events[0]["client_gid"])
    assert {tuple(e["client_gid"]) for e in server_events} == {caller}
    # Sim time: the first call at 50.0 s, the second 0.1 s later.
    assert events[0]["stamp"] == [50, 0]
    assert events[4]["stamp"] == [50, 100_000_000]
    assert [m.timestamp_ns for m in messages][::4] == [50_000_000_000, 50_100_000_000]


def test_rosbags_reads_the_service_topic_and_jazzys_schema(tmp_path: Path) -> None:
    from rosbags.rosbag2 import Reader

    bag = record_calls(tmp_path, ServiceIntrospectionState.METADATA,
                       ServiceIntrospectionState.OFF, services=["/toggle"])
    with Reader(bag) as reader:
        connections = {c.topic: c for c in reader.connections}
        assert set(connections) == {EVENT_TOPIC}
        conn = connections[EVENT_TOPIC]
        assert conn.msgtype == EVENT_TYPE
        assert conn.msgcount == 4  # server only: REQUEST_RECEIVED + RESPONSE_SENT per call
        assert conn.msgdef.data == (
            "=" * 80 + "\nSRV: std_srvs/srv/SetBool\n"
            "bool data\n---\nbool success\nstring message\n"
        )
        assert str(conn.digest).startswith("RIHS01_")
        raw = [bytes(data) for _, _, data in reader.messages()]
    from posekit.msgs.cdr import from_cdr

    decoded = [from_cdr(data, EVENT_TYPE) for data in raw]
    assert [int(e.info.event_type) for e in decoded] == [
        REQUEST_RECEIVED, RESPONSE_SENT] * 2
    assert all(len(e.request) == 0 and len(e.response) == 0 for e in decoded)  # METADATA


def test_bag_info_lists_services_as_jazzy(tmp_path: Path) -> None:
    bag = record_calls(tmp_path, ServiceIntrospectionState.CONTENTS,
                       ServiceIntrospectionState.CONTENTS, calls=3, all_services=True,
                       all_topics=True)
    text = format_info(bag_info(bag))
    lines = text.splitlines()
    # format_bag_meta_data: the count line "Service:" padded to 19 columns, then
    # "Service information: " followed by "Service: <name> | Type: <srv type> | Event Count:
    # <n> | Serialization Format: <fmt>", further services indented by 19 + 2 spaces.
    assert "Service:           1" in lines
    assert ("Service information: Service: /toggle | Type: std_srvs/srv/SetBool | "
            "Event Count: 12 | Serialization Format: cdr") in lines
    # Messages and the topic lines leave service events out.
    info = bag_info(bag)
    topics_count = sum(t.message_count for t in info.topics if t.name != EVENT_TOPIC)
    assert f"Messages:          {topics_count}" in lines
    assert not any(EVENT_TOPIC in line for line in lines)
    assert info.message_count == topics_count + 12


def test_selection_follows_rosbag2s_topic_filter(tmp_path: Path) -> None:
    # A topic selection alone records no service; hidden topics stay out of --all-topics.
    bag = record_calls(tmp_path, ServiceIntrospectionState.CONTENTS,
                       ServiceIntrospectionState.OFF, topics=["/rosout"])
    assert EVENT_TOPIC not in {t.name for t in bag_info(bag).topics}
    bag2 = record_calls(tmp_path / "b", ServiceIntrospectionState.CONTENTS,
                        ServiceIntrospectionState.OFF, all_topics=True)
    assert EVENT_TOPIC not in {t.name for t in bag_info(bag2).topics}
    # A regex selects services by their service name; --exclude-services removes them.
    bag3 = record_calls(tmp_path / "c", ServiceIntrospectionState.CONTENTS,
                        ServiceIntrospectionState.OFF, regex="^/togg")
    assert EVENT_TOPIC in {t.name for t in bag_info(bag3).topics}
    bag4 = record_calls(tmp_path / "d", ServiceIntrospectionState.CONTENTS,
                        ServiceIntrospectionState.OFF, all_services=True,
                        exclude_services=["toggle"])
    assert EVENT_TOPIC not in {t.name for t in bag_info(bag4).topics}


def test_introspection_off_removes_the_event_publisher(ctx: Context) -> None:
    server = Toggle(ctx, ServiceIntrospectionState.CONTENTS)
    assert ctx.transport().count_publishers(EVENT_TOPIC) == 1
    server.service.configure_introspection(server.get_clock(), QoSProfile(depth=10),
                                           ServiceIntrospectionState.OFF)
    assert ctx.transport().count_publishers(EVENT_TOPIC) == 0
    plain = Node("plain", context=ctx)
    plain.create_service(SetBool, "quiet", lambda req, resp: resp)
    assert ctx.transport().count_publishers("/quiet/_service_event") == 0


def test_play_publishes_the_recorded_events(tmp_path: Path) -> None:
    bag = record_calls(tmp_path, ServiceIntrospectionState.CONTENTS,
                       ServiceIntrospectionState.CONTENTS, services=["/toggle"])
    recorded = [m.decode() for m in read_messages(bag)]
    context = Context()
    context.init(transport="inprocess")
    try:
        from posekit.msgs.cdr import get_typestore

        listener = Node("listener", context=context)
        got: list[Any] = []
        listener.create_subscription(get_typestore().types[EVENT_TYPE], EVENT_TOPIC,
                                     got.append, 10)
        executor = SimulatedTimeExecutor(context=context)
        executor.add_node(listener)
        with Player(bag, context=context) as player:
            executor.add_node(player.node)
            player.run_simulated(executor)
        executor.run_for(0.01)
    finally:
        context.try_shutdown()
    assert [int(e.info.event_type) for e in got] == [int(e.info.event_type) for e in recorded]
    assert [[r.data for r in e.request] for e in got] == [
        [r.data for r in e.request] for e in recorded]


@pytest.mark.parametrize(("source", "server_state", "client_state"), [
    ("service_introspection", ServiceIntrospectionState.CONTENTS,
     ServiceIntrospectionState.OFF),
    ("client_introspection", ServiceIntrospectionState.OFF,
     ServiceIntrospectionState.CONTENTS),
])
def test_publish_service_requests_calls_the_service(
    tmp_path: Path, source: str, server_state: ServiceIntrospectionState,
    client_state: ServiceIntrospectionState,
) -> None:
    bag = record_calls(tmp_path, server_state, client_state, calls=3, services=["/toggle"])
    context = Context()
    context.init(transport="inprocess")
    try:
        server = Toggle(context, None)
        executor = SimulatedTimeExecutor(context=context)
        executor.add_node(server)
        with Player(bag, context=context, publish_service_requests=True,
                    service_requests_source=source) as player:
            executor.add_node(player.node)
            player.run_simulated(executor)
            executor.run_for(0.1)
            assert player.requests_sent == 3
            assert context.transport().count_publishers(EVENT_TOPIC) == 0  # no events
    finally:
        context.try_shutdown()
    assert server.requests == [True, False, True]


def test_metadata_only_events_cannot_be_replayed(tmp_path: Path, logs: list) -> None:
    bag = record_calls(tmp_path, ServiceIntrospectionState.METADATA,
                       ServiceIntrospectionState.OFF, services=["/toggle"])
    context = Context()
    context.init(transport="inprocess")
    try:
        server = Toggle(context, None)
        executor = SimulatedTimeExecutor(context=context)
        executor.add_node(server)
        with Player(bag, context=context, publish_service_requests=True) as player:
            executor.add_node(player.node)
            player.run_simulated(executor)
            assert player.requests_sent == 0
    finally:
        context.try_shutdown()
    assert server.requests == []
    assert any(re.search("metadata only on service side", r.message) for r in logs)


@pytest.mark.parametrize(("server_state", "client_state"), [
    (ServiceIntrospectionState.OFF, ServiceIntrospectionState.CONTENTS),
    (ServiceIntrospectionState.METADATA, ServiceIntrospectionState.OFF),
    # both sides: a server's events name the caller and number as the client's do (rmw_zenoh's
    # request id), so each call counts once
    (ServiceIntrospectionState.CONTENTS, ServiceIntrospectionState.METADATA),
])
def test_verbose_info_counts_requests_and_responses_as_jazzy(
    tmp_path: Path, server_state: ServiceIntrospectionState,
    client_state: ServiceIntrospectionState,
) -> None:
    """Jazzy's ``ros2 bag info --verbose`` (Info::read_service_info, format_service_info):
    distinct (client_gid, sequence_number) pairs of request and of response events, in
    ``Service: <name> | Type: <type> | Request Count: R | Response Count: S | Serialization
    Format: cdr`` after ``Service information: ``."""
    from posekit.bag.info import service_counts
    from posekit.cli.bag_cmd import info

    bag = record_calls(tmp_path, server_state, client_state, calls=3, services=["/toggle"])
    assert service_counts(bag) == {EVENT_TOPIC: (3, 3)}
    text = format_info(bag_info(bag), verbose=True, service_counts=service_counts(bag))
    assert ("Service information: Service: /toggle | Type: std_srvs/srv/SetBool | "
            "Request Count: 3 | Response Count: 3 | Serialization Format: cdr") in text
    assert "Service:           1" in text.splitlines()
    import io

    out = io.StringIO()
    assert info([str(bag), "-v", "-t"], out=out) == 0
    printed = out.getvalue()
    assert printed.startswith("Warning! You have set both the '-t' and '-v' parameters. "
                              "The '-t' parameter will be ignored.\n")
    assert "Request Count: 3 | Response Count: 3" in printed
