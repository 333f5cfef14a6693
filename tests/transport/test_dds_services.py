"""Services over the DDS transport: rmw_cyclonedds's request/reply mapping between posekit
participants (two contexts, and processes), the graph, and rejections.

Oracles (none of them posekit's service code): the payload layout written out here from
rmw_cyclonedds's source (CDR encapsulation, ``uint64`` client id, ``int64`` sequence number,
then the message's own fields) with rosbags' CDR serializer for the message bytes; hand-made
``cyclonedds`` readers and writers (their own IDL structs) playing an rmw_cyclonedds client
and server; the responses the callbacks compute from their requests; DDS's own matching
status; and, across processes, the parameter value the other process reports.
"""

from __future__ import annotations

import struct
import subprocess
import sys
import textwrap
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import pytest

from _support.dds import dds_context, dds_domain, posekit_env, spin_until, two_dds_contexts
from _support.procs import Proc
from _support.waiting import wait_for
from posekit.msgs.rcl_interfaces import (
    GetParameters,
    Parameter,
    ParameterValue,
    SetParameters,
)
from posekit.msgs.std_srvs import SetBool
from posekit.runtime.context import Context
from posekit.runtime.executors import MultiThreadedExecutor, SingleThreadedExecutor
from posekit.runtime.logging import LogRecord
from posekit.runtime.node import Node
from posekit.runtime.qos import QoSProfile

pytestmark = pytest.mark.slow


@pytest.fixture
def two(monkeypatch: pytest.MonkeyPatch) -> Iterator[tuple[Context, Context]]:
    with two_dds_contexts(monkeypatch) as pair:
        yield pair


class Spinner:
    """Spin an executor on a thread of its own until stopped."""

    def __init__(self, executor: Any) -> None:
        self.executor = executor
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.is_set():
            self.executor.spin_once(timeout_sec=0.05)

    def stop(self) -> None:
        self._stop.set()
        self._thread.join(5)


def both_directions_matched(client: Any) -> bool:
    """DDS's own view: the request writer has a reader and the reply reader a writer."""
    entities = client._endpoint.entities
    return bool(entities.writer.get_matched_subscriptions()) and bool(
        entities.reader.get_matched_publications())


def test_setbool_round_trip_wait_for_service_and_graph(two: tuple[Context, Context]) -> None:
    a, b = two
    server_node = Node("flag_server", context=a)
    client_node = Node("flag_client", namespace="/ui", context=b)
    client = client_node.create_client(SetBool, "/flip")
    # no server yet: not ready, and wait_for_service gives up after its timeout
    assert client.wait_for_service(timeout_sec=0.3) is False
    callers: list[tuple[bytes, int]] = []

    def flip(request: SetBool.Request, response: SetBool.Response) -> SetBool.Response:
        response.success = not request.data
        response.message = f"was {request.data}"
        return response

    service = server_node.create_service(SetBool, "/flip", flip)
    endpoint = service._endpoint
    original = endpoint._sink  # type: ignore[union-attr]

    def record(request: Any, respond: Any, header: Any) -> None:
        callers.append((header.client_gid, header.sequence_number))
        original(request, respond, header)

    endpoint._sink = record  # type: ignore[union-attr]
    server_exec = SingleThreadedExecutor(context=a)
    server_exec.add_node(server_node)
    spinner = Spinner(server_exec)
    try:
        deadline = time.monotonic() + 15
        while not client.service_is_ready():
            assert time.monotonic() < deadline, "the server never became available"
            time.sleep(0.005)
        # ready implies DDS matched the request writer and the reply reader to the server
        assert both_directions_matched(client)
        first = client.call(SetBool.Request(data=True), timeout_sec=10)
        second = client.call(SetBool.Request(data=False), timeout_sec=10)
    finally:
        spinner.stop()
    assert (first.success, first.message) == (False, "was True")
    assert (second.success, second.message) == (True, "was False")
    # the server learns the calling client's id and the request numbers from the header
    assert callers == [(client._gid, 1), (client._gid, 2)]
    assert len(client._gid) == 16
    assert client._gid[8:] == bytes(8)
    # the graph, derived from the rq/rr endpoints, seen from the client's participant
    client_node.transport.sync_graph(3.0)  # type: ignore[attr-defined]
    assert ("/flip", ["std_srvs/srv/SetBool"]) in client_node.get_service_names_and_types()
    transport = client_node.transport
    served = transport.get_service_names_and_types_by_node("flag_server", "/")
    assert ("/flip", ["std_srvs/srv/SetBool"]) in served
    assert ("/flag_server/set_parameters", ["rcl_interfaces/srv/SetParameters"]) in served
    assert ("/flip", ["std_srvs/srv/SetBool"]) not in \
        transport.get_service_names_and_types_by_node("flag_client", "/ui")
    assert transport.get_client_names_and_types_by_node("flag_client", "/ui") == [
        ("/flip", ["std_srvs/srv/SetBool"])]
    assert transport.count_services("/flip") == 1
    assert transport.count_clients("/flip") == 1
    # a destroyed server leaves: not ready any more, and off the graph
    server_node.destroy_service(service)
    assert wait_for(lambda: not client.service_is_ready(), 10)
    assert wait_for(lambda: transport.count_services("/flip") == 0, 10)


def test_concurrent_requests_of_two_clients_each_get_their_own_response(
        two: tuple[Context, Context]) -> None:
    """Both clients number their requests 1, 2, ...; only the client id tells them apart."""
    a, b = two
    deep = QoSProfile(depth=100)
    server_node = Node("echo_server", context=a)

    def echo(request: GetParameters.Request,
             response: GetParameters.Response) -> GetParameters.Response:
        response.values = [ParameterValue(type=4, string_value=f"echo:{n}")
                           for n in request.names]
        return response

    server_node.create_service(GetParameters, "/echo", echo, qos_profile=deep)
    clients_node = Node("callers", context=b)
    first = clients_node.create_client(GetParameters, "/echo", qos_profile=deep)
    second = clients_node.create_client(GetParameters, "/echo", qos_profile=deep)
    server_exec = MultiThreadedExecutor(num_threads=2, context=a)
    server_exec.add_node(server_node)
    spinner = Spinner(server_exec)
    client_exec = SingleThreadedExecutor(context=b)
    client_exec.add_node(clients_node)
    try:
        assert first.wait_for_service(15)
        assert second.wait_for_service(15)
        futures = []
        for i in range(20):
            for tag, client in (("A", first), ("B", second)):
                name = f"{tag}{i}"
                futures.append((name, client.call_async(GetParameters.Request(names=[name]))))
        assert spin_until(client_exec, lambda: all(f.done() for _, f in futures), 20), \
            f"{sum(not f.done() for _, f in futures)} of {len(futures)} requests unanswered"
    finally:
        spinner.stop()
    for name, future in futures:
        assert [v.string_value for v in future.result().values] == [f"echo:{name}"]
    assert first._gid != second._gid


def test_a_raising_server_answers_nothing_and_keeps_serving(
        two: tuple[Context, Context], logs: list[LogRecord]) -> None:
    a, b = two
    server_node = Node("moody", context=a)

    def moody(request: SetBool.Request, response: SetBool.Response) -> SetBool.Response:
        if not request.data:
            raise RuntimeError("refusing false")
        response.success = True
        return response

    server_node.create_service(SetBool, "/moody", moody)
    client = Node("asker", context=b).create_client(SetBool, "/moody")
    server_exec = SingleThreadedExecutor(context=a)
    server_exec.add_node(server_node)
    spinner = Spinner(server_exec)
    try:
        assert client.wait_for_service(15)
        assert client.call(SetBool.Request(data=False), timeout_sec=1.0) is None
        answer = client.call(SetBool.Request(data=True), timeout_sec=10)
    finally:
        spinner.stop()
    assert answer is not None
    assert answer.success is True
    assert any("refusing false" in r.message for r in logs)


def test_a_destroyed_server_sends_no_late_answer_and_malformed_requests_are_dropped(
        two: tuple[Context, Context], logs: list[LogRecord]) -> None:
    from posekit.runtime.transport import ServiceInfo

    a, b = two
    server_node = Node("lazy", context=a)
    held: list[Any] = []
    info = ServiceInfo("/lazy", SetBool, QoSProfile(depth=10), "lazy", "/",
                       server_node.get_logger())
    server = server_node.transport.create_service_server(
        info, lambda request, respond, header: held.append(respond))
    client = Node("impatient", context=b).create_client(SetBool, "/lazy")
    assert client.wait_for_service(15)
    future = client.call_async(SetBool.Request(data=True))
    assert wait_for(lambda: bool(held), 10), "the request never reached the server"
    server.destroy()
    held[0](SetBool.Response(success=True))  # answering after destroy sends nothing
    client_exec = SingleThreadedExecutor(context=b)
    client_exec.add_node(client._node)
    assert not spin_until(client_exec, future.done, 1.0)
    assert server.entities.alive is False  # type: ignore[attr-defined]
    # malformed payloads never raise into the delivery thread; one line per reason per second
    server2 = server_node.transport.create_service_server(
        ServiceInfo("/strict", SetBool, QoSProfile(depth=10), "lazy", "/",
                    server_node.get_logger()),
        lambda request, respond, header: held.append(request))
    for _ in range(50):
        server2._on_request(b"\x00\x01\x00\x00\x01", None)  # type: ignore[attr-defined]
        server2._on_request(b"\x00\x01\x00\x00" + bytes(16) + b"\x01\x02\x03\x04\x05\x06",
                            None)  # type: ignore[attr-defined]
    dropped = server2.entities.dropped  # type: ignore[attr-defined]
    assert dropped == {"dropping a malformed request": 100}
    lines = [r.message for r in logs if "malformed request" in r.message]
    assert 1 <= len(lines) <= 2, lines
    assert "'/strict'" in lines[0]
    assert len(held) == 1  # only the held respond callable: no malformed request delivered


def test_an_action_between_two_participants(two: tuple[Context, Context]) -> None:
    """Actions are services plus topics: goal, feedback and result cross DDS."""
    from posekit.msgs.posekit_interfaces import NavigateToPose
    from posekit.runtime.action import ActionClient, ActionServer

    a, b = two
    server_node = Node("driver", context=a)

    def execute(goal_handle: Any) -> Any:
        left = goal_handle.request.pose.pose.position.x
        for step in (left, left / 2):
            goal_handle.publish_feedback(NavigateToPose.Feedback(distance_remaining=step))
        goal_handle.succeed()
        return NavigateToPose.Result(distance_remaining=0.125)

    server = ActionServer(server_node, NavigateToPose, "drive", execute)
    client_node = Node("commander", context=b)
    client = ActionClient(client_node, NavigateToPose, "drive")
    server_exec = SingleThreadedExecutor(context=a)
    server_exec.add_node(server_node)
    spinner = Spinner(server_exec)
    client_exec = SingleThreadedExecutor(context=b)
    client_exec.add_node(client_node)
    feedback: list[float] = []
    try:
        assert client.wait_for_server(timeout_sec=15)
        # feedback is a VOLATILE topic: send once DDS matched the client's reader to it
        assert wait_for(lambda: server._feedback_pub.get_subscription_count() == 1, 15)
        goal = NavigateToPose.Goal()
        goal.pose.pose.position.x = 3.0
        sent = client.send_goal_async(
            goal, feedback_callback=lambda m: feedback.append(m.feedback.distance_remaining))
        assert spin_until(client_exec, sent.done, 15)
        handle = sent.result()
        assert handle.accepted
        result = handle.get_result_async()
        assert spin_until(client_exec, result.done, 15)
        # (feedback and result travel on different DDS entities: either may come first)
        assert spin_until(client_exec, lambda: len(feedback) >= 2, 10)
    finally:
        spinner.stop()
    assert result.result().result.distance_remaining == 0.125
    assert result.result().status == 4  # GoalStatus.STATUS_SUCCEEDED
    assert feedback == [3.0, 1.5]


# --- the wire format, against hand-written rmw_cyclonedds endpoints -------------------------


@dataclass
class RawEndpoints:
    """A hand-made rmw_cyclonedds peer: plain cyclonedds entities, their own IDL structs."""

    reader: Any
    writer: Any


def _raw_types() -> tuple[type, type]:
    """As rmw_cyclonedds's typesupport lays them out: request header, then the fields."""
    from cyclonedds.idl import make_idl_struct
    from cyclonedds.idl.types import int64, uint64

    header = {"request_header_client_id": uint64, "request_header_sequence_number": int64}
    request = make_idl_struct("SetBoolRequest", "std_srvs.srv.dds_.SetBool_Request_",
                              {**header, "data": bool})
    response = make_idl_struct("SetBoolResponse", "std_srvs.srv.dds_.SetBool_Response_",
                               {**header, "success": bool, "message": str})
    return request, response


def _raw_peer(participant: Any, service: str, *, server: bool, ident: str) -> RawEndpoints:
    from cyclonedds.pub import DataWriter
    from cyclonedds.qos import Policy, Qos
    from cyclonedds.sub import DataReader
    from cyclonedds.topic import Topic
    from cyclonedds.util import duration

    request_type, response_type = _raw_types()
    qos = Qos(Policy.Reliability.Reliable(duration(seconds=1)), Policy.History.KeepLast(10),
              Policy.Durability.Volatile,
              Policy.DataRepresentation(use_cdrv0_representation=True),
              Policy.Userdata(f"{'serviceid' if server else 'clientid'}={ident};".encode()))
    rq = Topic(participant, f"rq{service}Request", request_type)
    rr = Topic(participant, f"rr{service}Reply", response_type)
    if server:
        return RawEndpoints(DataReader(participant, rq, qos), DataWriter(participant, rr, qos))
    return RawEndpoints(DataReader(participant, rr, qos), DataWriter(participant, rq, qos))


def _take_raw(reader: Any, timeout: float) -> bytes:
    from cyclonedds._clayer import ddspy_take
    from cyclonedds.core import InstanceState, SampleState, ViewState

    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        for data, info in ddspy_take(reader._ref, SampleState.Any | ViewState.Any
                                     | InstanceState.Any, 1) or []:
            if info.valid_data:
                return bytes(data)
        time.sleep(0.01)
    raise AssertionError("no sample arrived")


#: The request and response halves of the .srv files, as rosidl splits them.
SRV_HALVES = {
    "std_srvs/srv/SetBool_Request": "bool data\n",
    "std_srvs/srv/SetBool_Response": "bool success\nstring message\n",
    "rcl_interfaces/srv/SetParameters_Request": "rcl_interfaces/Parameter[] parameters\n",
}


def _rosbags_store() -> Any:
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    # rosbags names every parsed type pkg/msg/Name; the CDR bytes do not depend on the name
    store = get_typestore(Stores.ROS2_JAZZY)
    store.register({name: fields for srv, text in SRV_HALVES.items()
                    for name, fields in get_types_from_msg(text, _as_msg(srv)).items()})
    return store


def _as_msg(srv_half: str) -> str:
    return srv_half.replace("/srv/", "/msg/")


def _rosbags_cdr(msg_type: str, **fields: Any) -> bytes:
    store = _rosbags_store()
    name = _as_msg(msg_type)
    return bytes(store.serialize_cdr(store.types[name](**fields), name))


def test_request_and_reply_bytes_are_rmw_cyclonedds_layout(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """A posekit client's request, read raw, and a posekit server's reply to a raw request."""
    from cyclonedds._clayer import ddspy_write
    from cyclonedds.domain import DomainParticipant

    domain = dds_domain(monkeypatch)
    context = dds_context()
    node = Node("wire", context=context)  # configures the domain (loopback discovery)
    participant = DomainParticipant(domain)
    try:
        # 1. posekit's client -> a hand-made server's request reader
        raw_server = _raw_peer(participant, "/wire_out", server=True, ident="01.2.3")
        client = node.create_client(SetBool, "/wire_out")
        assert wait_for(lambda: client.service_is_ready(), 15)
        client.call_async(SetBool.Request(data=True))
        data = _take_raw(raw_server.reader, 10)
        client_id = client._endpoint.client_id  # type: ignore[attr-defined]
        expected = (b"\x00\x01\x00\x00" + struct.pack("<Qq", client_id, 1)
                    + _rosbags_cdr("std_srvs/srv/SetBool_Request", data=True)[4:])
        assert data == expected
        # a richer request: the body's alignment (int64, float64 after strings) is unchanged
        setter = node.create_client(SetParameters, "/wire_set")
        raw_set = _raw_set_server(participant)
        assert wait_for(lambda: bool(
            setter._endpoint.entities.writer.get_matched_subscriptions()), 15)
        value = ParameterValue(type=3, double_value=1.0)
        setter.call_async(SetParameters.Request(parameters=[Parameter(name="k", value=value)]))
        data = _take_raw(raw_set, 10)
        body = _rosbags_cdr("rcl_interfaces/srv/SetParameters_Request", parameters=[
            _rosbags_parameter("k", 1.0)])
        assert data == (b"\x00\x01\x00\x00" + struct.pack(
            "<Qq", setter._endpoint.client_id, 1) + body[4:])  # type: ignore[attr-defined]
        # 2. a hand-made client's request -> posekit's server -> the reply it echoes
        node.create_service(SetBool, "/wire_in", lambda req, resp: SetBool.Response(
            success=req.data, message="seen"))
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        raw_client = _raw_peer(participant, "/wire_in", server=False, ident="0a.b.c")
        assert spin_until(executor, lambda: bool(
            raw_client.writer.get_matched_subscriptions()) and bool(
            raw_client.reader.get_matched_publications()), 15)
        guid, seq = 0x1122334455667788, 42
        request = (b"\x00\x01\x00\x00" + struct.pack("<Qq", guid, seq)
                   + _rosbags_cdr("std_srvs/srv/SetBool_Request", data=True)[4:])
        assert ddspy_write(raw_client.writer._ref, request) >= 0
        reply = b""
        deadline = time.monotonic() + 10
        while not reply and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.05)
            try:
                reply = _take_raw(raw_client.reader, 0.05)
            except AssertionError:
                continue
        assert reply == (b"\x00\x01\x00\x00" + struct.pack("<Qq", guid, seq) + _rosbags_cdr(
            "std_srvs/srv/SetBool_Response", success=True, message="seen")[4:])
    finally:
        participant.__del__()
        context.try_shutdown()


def _rosbags_parameter(name: str, value: float) -> Any:
    import numpy as np

    types = _rosbags_store().types
    pv = types["rcl_interfaces/msg/ParameterValue"]

    return types["rcl_interfaces/msg/Parameter"](name=name, value=pv(
        type=3, bool_value=False, integer_value=0, double_value=value, string_value="",
        byte_array_value=np.zeros(0, np.uint8), bool_array_value=np.zeros(0, bool),
        integer_array_value=np.zeros(0, np.int64), double_array_value=np.zeros(0, np.float64),
        string_array_value=[]))


def _raw_set_server(participant: Any) -> Any:
    """A raw reader of ``rq/wire_setRequest`` taking whatever bytes arrive."""
    from cyclonedds.qos import Policy, Qos
    from cyclonedds.sub import DataReader
    from cyclonedds.topic import Topic

    from posekit.transport.dds_types import idl_service_struct

    qos = Qos(Policy.Reliability.Reliable(0), Policy.History.KeepLast(10),
              Policy.Durability.Volatile,
              Policy.DataRepresentation(use_cdrv0_representation=True))
    topic = Topic(participant, "rq/wire_setRequest",
                  idl_service_struct("rcl_interfaces/srv/SetParameters_Request"))
    return DataReader(participant, topic, qos)


# --- across processes: the command-line tools ------------------------------------------------

CONTROLLER = textwrap.dedent("""
    import sys, time
    import posekit.rclpy as rclpy
    from posekit.robot.nodes.p_controller import PControllerNode
    rclpy.init(transport="dds")
    node = PControllerNode()
    executor = rclpy.executors.SingleThreadedExecutor()
    executor.add_node(node)
    print("ready", node.controller.params.k_rho, flush=True)
    last = node.controller.params.k_rho
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.05)
        if node.controller.params.k_rho != last:
            last = node.controller.params.k_rho
            print("k_rho", last, flush=True)
""")


def _cli(domain: int, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "posekit.cli.main", *args, "--transport", "dds"],
                          env=posekit_env(domain), capture_output=True, text=True, timeout=60)


def test_param_set_service_list_and_call_reach_another_process(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """The lecture's k_rho retune, from one process to another, over DDS."""
    domain = dds_domain(monkeypatch)
    controller = Proc([sys.executable, "-c", CONTROLLER], env=posekit_env(domain))
    try:
        controller.wait_line(lambda line: line.startswith("ready"), 30, "the controller")
        listed = _cli(domain, "service", "list", "-t", "--include-hidden-services")
        assert listed.returncode == 0, listed.stderr
        assert "/p_controller/set_parameters [rcl_interfaces/srv/SetParameters]" in \
            listed.stdout.splitlines()
        assert ("/navigate_to_pose/_action/send_goal "
                "[posekit_interfaces/action/NavigateToPose_SendGoal]") in listed.stdout.splitlines()
        done = _cli(domain, "param", "set", "/p_controller", "k_rho", "1.0")
        assert done.returncode == 0, done.stderr
        assert done.stdout.strip() == "Set parameter successful"
        controller.wait_line(lambda line: line.strip() == "k_rho 1.0", 15,
                             "the controller's new k_rho")
        got = _cli(domain, "param", "get", "/p_controller", "k_rho")
        assert got.returncode == 0, got.stderr
        assert got.stdout.strip() == "Double value is: 1.0"
        kind = _cli(domain, "service", "type", "/p_controller/get_parameters")
        assert kind.stdout.strip() == "rcl_interfaces/srv/GetParameters"
    finally:
        controller.kill()


def test_service_call_without_a_server_times_out_in_one_line(
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    from posekit.cli.main import main

    dds_domain(monkeypatch)
    assert main(["service", "call", "/reset", "std_srvs/srv/Trigger", "--transport", "dds",
                 "--timeout", "0.5"]) == 1
    err = capsys.readouterr().err
    assert err == "service '/reset' did not become available within 0.5 s\n"


def test_readiness_stays_true_while_the_graph_churns(two: tuple[Context, Context]) -> None:
    # A client's readiness reads the matched endpoints' USER_DATA on the caller's thread
    # while the transport's graph thread reads the built-in topics; cyclonedds-python
    # converts both through shared scratch buffers, so without one lock around every
    # conversion a reading went wrong now and then (the server counted as absent, or a
    # segmentation fault). Oracle: the server never goes away, so readiness must hold.
    a, b = two
    server = Node("steady_server", context=a)
    server.create_service(SetBool, "/steady", lambda req, resp: resp)
    client_node = Node("steady_client", context=b)
    client = client_node.create_client(SetBool, "/steady")
    assert client.wait_for_service(timeout_sec=15)
    churn = Node("churn", context=a)
    stop = time.monotonic() + 3.0
    misses: list[int] = []

    def churn_graph() -> None:  # publishers come and go: the graph thread re-reads
        i = 0
        while time.monotonic() < stop:
            churn.destroy_publisher(churn.create_publisher(SetBool.Request, f"/churn_{i % 7}", 1))
            i += 1

    def ask() -> None:
        while time.monotonic() < stop:
            if not client.service_is_ready():
                misses.append(1)

    threads = [threading.Thread(target=churn_graph)] + [threading.Thread(target=ask)
                                                         for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=30)
    assert not any(t.is_alive() for t in threads)
    assert misses == []
