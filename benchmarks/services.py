"""Service round trips (std_srvs/SetBool): posekit vs the real rclpy in the same run.

Run: ``.venv/bin/python benchmarks/services.py`` (``--quick`` for a short run; needs the
reference venv from ``make ros2-ref`` for the rclpy rows). Figures are in
docs/performance.md.

Every mode makes ``N`` sequential calls (the next request after the previous response) and
reports the median and p90 round-trip time per call:

* ``posekit inprocess``: server and client nodes in one ``SingleThreadedExecutor``;
  ``call_async`` + ``spin_until_future_complete`` (bus snapshots, executor queues).
* ``rclpy inprocess``: the same script under the real ROS 2 Jazzy rclpy (Fast DDS, one
  process, loopback discovery): the reference for the in-process row.
* ``posekit zenoh``: the same nodes on two Zenoh sessions (two contexts) in one process,
  server executor in its own thread, the client calling ``Client.call`` (CDR, queryable,
  attachments, executor hand-offs).
* ``raw zenoh``: a plain zenoh queryable answering fixed CDR bytes and a plain ``get``: the
  floor for Python + zenoh on this machine.
* ``posekit dds``: the zenoh row's nodes on two DDS participants (rmw_cyclonedds's service
  mapping, loopback, domain ``$POSEKIT_BENCH_DOMAIN`` or 178).
* ``posekit zenoh, in a callback`` / ``posekit dds, in a callback``: both nodes in one
  context on one transport and one ``SingleThreadedExecutor``; a timer callback makes the
  calls with ``Client.call`` (which deadlocks in rclpy's single-threaded executor): each
  request crosses the transport and comes back to the same executor, which serves it while
  the call waits.

It also prints what a node costs to create on DDS with and without its six parameter
services (twelve more DDS readers and writers, each announced on ``ros_discovery_info``).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import textwrap
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]
ROS2_PYTHON = REPO / ".venv-ros2" / "bin" / "python"

INPROCESS = """
import json, time
{imports}
rclpy.init()
server = Node("bench_server")
server.create_service(SetBool, "flip", lambda q, r: SetBool.Response(success=not q.data))
client_node = Node("bench_client")
client = client_node.create_client(SetBool, "flip")
ex = SingleThreadedExecutor()
ex.add_node(server)
ex.add_node(client_node)
assert client.wait_for_service(timeout_sec=10.0)
times = []
for i in range({n} + 50):
    t0 = time.perf_counter()
    f = client.call_async(SetBool.Request(data=bool(i % 2)))
    ex.spin_until_future_complete(f, timeout_sec=10.0)
    assert f.result().success == (not bool(i % 2))
    times.append(time.perf_counter() - t0)
print(json.dumps(times[50:]))
rclpy.shutdown()
"""

ROS_IMPORTS = """import rclpy
from rclpy.node import Node
from rclpy.executors import SingleThreadedExecutor
from std_srvs.srv import SetBool"""

POSEKIT_IMPORTS = """from posekit import rclpy
from posekit.rclpy.node import Node
from posekit.rclpy.executors import SingleThreadedExecutor
from posekit.msgs.std_srvs import SetBool"""


def _stats(times: list[float]) -> dict[str, float]:
    ordered = sorted(times)
    return {
        "n": len(times),
        "median_us": statistics.median(ordered) * 1e6,
        "p90_us": ordered[int(0.9 * (len(ordered) - 1))] * 1e6,
    }


def _run_script(python: str, source: str, env: dict[str, str]) -> list[float]:
    proc = subprocess.run([python, "-c", textwrap.dedent(source)], capture_output=True,
                          text=True, env=env, timeout=300)
    if proc.returncode != 0:
        raise RuntimeError(proc.stderr[-2000:])
    times: list[float] = json.loads(proc.stdout.strip().splitlines()[-1])
    return times


def posekit_inprocess(n: int) -> list[float]:
    env = dict(os.environ, POSEKIT_TRANSPORT="inprocess")
    return _run_script(sys.executable, INPROCESS.format(imports=POSEKIT_IMPORTS, n=n), env)


def rclpy_inprocess(n: int) -> list[float] | None:
    if not ROS2_PYTHON.exists():
        return None
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("ROS_", "RMW_", "POSEKIT_", "PYTHON"))}
    env.update(ROS_DOMAIN_ID="177", ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
               RMW_IMPLEMENTATION="rmw_fastrtps_cpp")
    return _run_script(str(ROS2_PYTHON), INPROCESS.format(imports=ROS_IMPORTS, n=n), env)


def _free_endpoint() -> str:
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return f"tcp/127.0.0.1:{s.getsockname()[1]}"


def posekit_zenoh(n: int) -> list[float]:
    from posekit.transport.zenoh_session import SessionOptions
    from posekit.transport.zenoh_transport import ZenohTransport

    options = SessionOptions(router_endpoint=_free_endpoint())
    return _two_contexts(n, lambda: ZenohTransport(options))


def _dds_options() -> Any:
    from posekit.transport.dds_wire import DiscoveryOptions

    return DiscoveryOptions(domain_id=int(os.environ.get("POSEKIT_BENCH_DOMAIN", "178")))


def posekit_dds(n: int) -> list[float]:
    from posekit.transport.dds_transport import DdsTransport

    options = _dds_options()
    return _two_contexts(n, lambda: DdsTransport(options))


def dds_node_cost(count: int = 10) -> tuple[float, float]:
    """Milliseconds per node created on DDS: (without, with) parameter services."""
    from posekit.runtime.context import Context
    from posekit.runtime.node import Node
    from posekit.transport.dds_transport import DdsTransport

    context = Context()
    context.init()
    try:
        transport = DdsTransport(_dds_options())
        Node("warm_up", context=context, transport=transport)
        costs = []
        for services in (False, True):
            t0 = time.perf_counter()
            for i in range(count):
                Node(f"cost_{int(services)}_{i}", context=context, transport=transport,
                     start_parameter_services=services)
            costs.append((time.perf_counter() - t0) / count * 1e3)
        transport.close()
        return costs[0], costs[1]
    finally:
        context.shutdown()


def _timed_calls(client: Any, count: int, times: list[float]) -> None:
    """``count`` sequential ``Client.call`` round trips of SetBool, each checked and timed
    (seconds, appended to ``times``)."""
    from posekit.msgs.std_srvs import SetBool

    for i in range(count):
        t0 = time.perf_counter()
        response = client.call(SetBool.Request(data=bool(i % 2)), timeout_sec=10.0)
        if response is None or response.success == bool(i % 2):
            raise RuntimeError(f"bad response {response!r}")
        times.append(time.perf_counter() - t0)


def _two_contexts(n: int, make_transport: Callable[[], Any]) -> list[float]:
    from posekit.msgs.std_srvs import SetBool
    from posekit.runtime.context import Context
    from posekit.runtime.executors import SingleThreadedExecutor
    from posekit.runtime.node import Node

    server_ctx, client_ctx = Context(), Context()
    server_ctx.init()
    client_ctx.init()
    try:
        server = Node("bench_server", context=server_ctx, transport=make_transport())
        server.create_service(SetBool, "flip", lambda q, r: SetBool.Response(success=not q.data))
        ex = SingleThreadedExecutor(context=server_ctx)
        ex.add_node(server)
        spinner = threading.Thread(target=ex.spin, daemon=True)
        spinner.start()
        client_node = Node("bench_client", context=client_ctx, transport=make_transport())
        client = client_node.create_client(SetBool, "flip")
        if not client.wait_for_service(timeout_sec=10.0):
            raise RuntimeError("the server did not appear")
        times: list[float] = []
        _timed_calls(client, n + 50, times)
        return times[50:]
    finally:
        client_ctx.shutdown()
        server_ctx.shutdown()


def _one_executor(n: int, transport: Any) -> list[float]:
    """``Client.call`` inside a callback, the server on another node of the same executor:
    every request and response crosses the transport, and the calling executor serves the
    request while it waits."""
    from posekit.msgs.std_srvs import SetBool
    from posekit.runtime.context import Context
    from posekit.runtime.executors import SingleThreadedExecutor
    from posekit.runtime.node import Node

    context = Context()
    context.init()
    try:
        server = Node("bench_server", context=context, transport=transport)
        server.create_service(SetBool, "flip", lambda q, r: SetBool.Response(success=not q.data))
        client_node = Node("bench_client", context=context, transport=transport)
        client = client_node.create_client(SetBool, "flip")
        if not client.wait_for_service(timeout_sec=10.0):
            raise RuntimeError("the server did not appear")
        ex = SingleThreadedExecutor(context=context)
        ex.add_node(server)
        ex.add_node(client_node)
        times: list[float] = []

        def calls() -> None:
            timer.cancel()
            _timed_calls(client, n + 50, times)

        timer = client_node.create_timer(0.001, calls)
        while len(times) < n + 50:
            before = len(times)
            ex.spin_once(timeout_sec=10.0)
            if len(times) == before:
                raise RuntimeError("the calls did not run")
        return times[50:]
    finally:
        context.shutdown()
        transport.close()


def posekit_zenoh_in_callback(n: int) -> list[float]:
    from posekit.transport.zenoh_session import SessionOptions
    from posekit.transport.zenoh_transport import ZenohTransport

    return _one_executor(n, ZenohTransport(SessionOptions(router_endpoint=_free_endpoint())))


def posekit_dds_in_callback(n: int) -> list[float]:
    from posekit.transport.dds_transport import DdsTransport

    return _one_executor(n, DdsTransport(_dds_options()))


def raw_zenoh(n: int) -> list[float]:
    import zenoh

    from posekit.transport.zenoh_session import SessionOptions, open_session

    options = SessionOptions(router_endpoint=_free_endpoint())
    a, b = open_session(options), open_session(options)
    key = "0/flip/std_srvs::srv::dds_::SetBool_/RIHS01_bench"
    reply = b"\x00\x01\x00\x00\x01\x00\x00\x00\x01\x00\x00\x00\x00"
    attachment = bytes(33)
    queryable = a.session.declare_queryable(
        key, lambda q: q.reply(key, reply, attachment=attachment), complete=True
    )
    def ask() -> bool:
        return any(r.ok is not None for r in b.session.get(
            key, payload=b"\x00\x01\x00\x00\x01", attachment=attachment,
            target=zenoh.QueryTarget.ALL_COMPLETE, timeout=10.0))

    try:
        deadline = time.monotonic() + 10.0  # until the queryable is known to the querier
        while not ask():
            if time.monotonic() > deadline:
                raise RuntimeError("the queryable never answered")
            time.sleep(0.01)
        times = []
        for _ in range(n + 50):
            t0 = time.perf_counter()
            if not ask():
                raise RuntimeError("no reply")
            times.append(time.perf_counter() - t0)
        return times[50:]
    finally:
        queryable.undeclare()
        b.close()
        a.close()


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("-n", type=int, default=None)
    ns = parser.parse_args()
    n = ns.n or (200 if ns.quick else 2000)
    rows: dict[str, dict[str, float] | None] = {}
    for name, fn in (("posekit inprocess", posekit_inprocess),
                     ("rclpy inprocess", rclpy_inprocess),
                     ("posekit zenoh", posekit_zenoh), ("raw zenoh", raw_zenoh),
                     ("posekit dds", posekit_dds),
                     ("posekit zenoh, in a callback", posekit_zenoh_in_callback),
                     ("posekit dds, in a callback", posekit_dds_in_callback)):
        times = fn(n)
        rows[name] = _stats(times) if times else None
    for name, row in rows.items():
        if row is None:
            print(f"{name:<29} (skipped: no .venv-ros2)")
        else:
            print(f"{name:<29} n={row['n']:<5} median {row['median_us']:8.1f} us  "
                  f"p90 {row['p90_us']:8.1f} us")
    pk, ros = rows["posekit inprocess"], rows["rclpy inprocess"]
    if pk and ros:
        print(f"ratio posekit/rclpy in-process median: {pk['median_us'] / ros['median_us']:.4f} "
              f"(rclpy {ros['median_us'] / pk['median_us']:.0f}x slower)")
    pz, rz = rows["posekit zenoh"], rows["raw zenoh"]
    if pz and rz:
        print(f"ratio posekit/raw zenoh median: {pz['median_us'] / rz['median_us']:.2f}")
    pd = rows["posekit dds"]
    if pd and pz:
        print(f"ratio posekit dds/posekit zenoh median: {pd['median_us'] / pz['median_us']:.2f}")
    without, with_services = dds_node_cost()
    print(f"dds node creation: {without:.1f} ms without parameter services, "
          f"{with_services:.1f} ms with them")


if __name__ == "__main__":
    main()
