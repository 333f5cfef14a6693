"""Service introspection events name the calling client, on the client's and the server's side.

One script (the real rclpy API) runs a SetBool server and two clients, all with introspection
CONTENTS, and an observer of ``/flip/_service_event``: client A calls twice, client B once,
and the script prints every event's (event_type, client_gid, sequence_number).

Oracle: the real ROS 2 Jazzy rclpy (reference venv, Fast DDS), whose rcl fills a client's
events with the client's rmw GID and a server's with the writer GUID and sequence number of
the request header it took. Both runs must give the same structure: per call four events
(REQUEST_SENT, REQUEST_RECEIVED, RESPONSE_SENT, RESPONSE_RECEIVED), every client id non-zero,
one id per caller on each side, A's and B's different, sequence numbers 1, 2 for A and 1 for
B on both sides. Whether a server names a caller by the same bytes as the caller's own events
depends on the rmw: Fast DDS's request header holds the client's reply reader GUID (not the
same bytes; asserted on the reference run), rmw_zenoh's request attachment the client's own
GID (rmw_zenoh's sources: ``rmw_send_request`` attaches ``entity->copy_gid()``, which
``rmw_get_gid_for_client`` also returns). posekit follows rmw_zenoh: it runs the script in one
process on the in-process bus, and over Zenoh with the server in a second process (the
client's GID and number travel in the request attachment), and both must name each caller by
one id.
"""

from __future__ import annotations

import json
import os
import sys
from collections import Counter

import pytest

from _support.dds import free_domain
from _support.differential import PRELUDE
from _support.ports import free_port
from _support.procs import Proc, stop_all
from _support.ros2 import run_ros2_script

pytestmark = pytest.mark.slow  # runs the reference interpreter and child processes

SCRIPT = """
import json
import time

import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import qos_profile_system_default
from rclpy.service_introspection import ServiceIntrospectionState
from std_srvs.srv import SetBool

ROLE = {role!r}  # "all": everything here; "server": serve only; "clients": the rest
{event_class}
CONTENTS = ServiceIntrospectionState.CONTENTS
rclpy.init()
executor = SingleThreadedExecutor()
if ROLE in ("all", "server"):
    server = Node("flag_server")
    service = server.create_service(
        SetBool, "flip", lambda q, r: SetBool.Response(success=q.data, message="ok"))
    service.configure_introspection(server.get_clock(), qos_profile_system_default, CONTENTS)
    executor.add_node(server)
if ROLE == "server":
    print("server ready", flush=True)
    executor.spin()
events = []
observer = Node("observer")
observer.create_subscription(EVENT, "/flip/_service_event", lambda e: events.append(
    (int(e.info.event_type), bytes(e.info.client_gid).hex(), int(e.info.sequence_number))), 100)
executor.add_node(observer)
clients = []
for name in ("caller_a", "caller_b"):
    node = Node(name)
    executor.add_node(node)
    client = node.create_client(SetBool, "/flip")
    client.configure_introspection(node.get_clock(), qos_profile_system_default, CONTENTS)
    clients.append(client)
deadline = time.monotonic() + 30
assert all(c.wait_for_service(timeout_sec=30) for c in clients)
while observer.count_publishers("/flip/_service_event") < 3:  # server's and clients' events
    assert time.monotonic() < deadline, "event publishers not discovered"
    executor.spin_once(timeout_sec=0.05)
for client, data in ((clients[0], True), (clients[0], False), (clients[1], True)):
    future = client.call_async(SetBool.Request(data=data))
    executor.spin_until_future_complete(future, timeout_sec=30)
    assert future.result().success == data
while len(events) < 12:
    assert time.monotonic() < deadline, f"only {{len(events)}} events"
    executor.spin_once(timeout_sec=0.05)
executor.spin_once(timeout_sec=0.2)  # a 13th event would show here
print("events " + json.dumps(events), flush=True)
"""

REF_EVENT = "EVENT = SetBool.Event"
# posekit's service classes have no ``Event`` attribute; the event type comes from its registry.
OUR_EVENT = ("from posekit.msgs.registry import find_message_class\n"
             "EVENT = find_message_class('std_srvs/srv/SetBool_Event')")

REQUEST_SENT, REQUEST_RECEIVED, RESPONSE_SENT, RESPONSE_RECEIVED = range(4)
ONE_CALL = [REQUEST_SENT, REQUEST_RECEIVED, RESPONSE_SENT, RESPONSE_RECEIVED]
#: (caller, sequence number, event type), sorted: A's two calls and B's one.
EXPECTED = sorted([("A", 1, t) for t in ONE_CALL] + [("A", 2, t) for t in ONE_CALL]
                  + [("B", 1, t) for t in ONE_CALL])


def structure(stdout: str) -> tuple[list[tuple[str, int, int]], bool]:
    """The printed events with each client id replaced by its caller, and whether a server
    names a caller by the very id the caller's own events carry.

    A caller is told by its number of requests (A: two, B: one), on each side separately: a
    client's events (REQUEST_SENT, RESPONSE_RECEIVED) and a server's (REQUEST_RECEIVED,
    RESPONSE_SENT).
    """
    line = next(s for s in stdout.splitlines() if s.startswith("events "))
    events = [(int(t), str(gid), int(seq)) for t, gid, seq in json.loads(line[len("events "):])]
    for _, gid, _ in events:
        assert len(gid) == 32, gid
        assert int(gid, 16) != 0, "a zero client_gid names no client"
    callers: dict[str, dict[str, str]] = {}
    for side, first in (("client", REQUEST_SENT), ("server", REQUEST_RECEIVED)):
        counts = Counter(gid for t, gid, _ in events if t == first)
        assert sorted(counts.values()) == [1, 2], (side, counts)
        callers[side] = {gid: "A" if n == 2 else "B" for gid, n in counts.items()}
    side_of = {REQUEST_SENT: "client", RESPONSE_RECEIVED: "client",
               REQUEST_RECEIVED: "server", RESPONSE_SENT: "server"}
    labelled = sorted((callers[side_of[t]][gid], seq, t) for t, gid, seq in events)
    by_caller = [{label: gid for gid, label in callers[side].items()}
                 for side in ("client", "server")]
    return labelled, by_caller[0] == by_caller[1]


def script(role: str, event_class: str) -> str:
    return SCRIPT.format(role=role, event_class=event_class)


def posekit_env(**extra: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("ROS_", "RMW_", "POSEKIT_", "ZENOH_"))}
    env.update(PYTHONUNBUFFERED="1", **extra)
    return env


def test_rclpy_events_of_one_call_share_a_non_zero_client_gid() -> None:
    ref = run_ros2_script(script("all", REF_EVENT), domain_id=free_domain(), timeout=120)
    assert ref.returncode == 0, ref.stderr[-3000:]
    labelled, same_ids = structure(ref.stdout)
    assert labelled == EXPECTED
    # Fast DDS: a server's request header names the client by its reply reader's GUID, the
    # client's own events by its rmw GID (the request writer's), so the bytes differ.
    assert not same_ids


def test_posekit_in_process_events_have_the_structure_of_rclpys() -> None:
    proc = Proc([sys.executable, "-c", PRELUDE + script("all", OUR_EVENT)], posekit_env())
    try:
        out = proc.finish(120, "the posekit script")
        assert proc.popen.returncode == 0, proc.describe()
    finally:
        stop_all([proc])
    assert structure(out) == (EXPECTED, True)  # one id per client on both sides


def test_posekit_zenoh_server_in_another_process_learns_the_client_gid() -> None:
    env = posekit_env(POSEKIT_TRANSPORT="zenoh",
                      POSEKIT_ZENOH_ROUTER=f"tcp/127.0.0.1:{free_port()}")
    procs = [Proc([sys.executable, "-c", PRELUDE + script("server", OUR_EVENT)], env)]
    try:
        procs[0].wait_line(lambda s: "server ready" in s, 60, "the server")
        procs.append(Proc([sys.executable, "-c", PRELUDE + script("clients", OUR_EVENT)], env))
        out = procs[1].finish(120, "the clients")
        assert procs[1].popen.returncode == 0, procs[1].describe()
    finally:
        stop_all(procs)
    # rmw_zenoh's: the request attachment carries the client's GID, which the client's own
    # events carry too (its rmw GID), so the server names it by the same bytes.
    assert structure(out) == (EXPECTED, True)
