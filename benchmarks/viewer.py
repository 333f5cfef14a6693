"""CPU cost of a browser viewer attached to a simulated run: what the OAK-D depth costs.

The ``p_controller`` scenario runs for ``--sim-time`` (3) s of simulated time as fast as it
goes (no recorder) in this process, in four variants, alternately, ``--repeats`` times:

* ``none``: no viewer;
* ``attached``: a viewer attached in process (what ``posekit launch ... --viewer`` does), no
  page showing anything;
* ``depth image``: plus a client that watches ``/oak/stereo/depth`` (what the page sends while
  an Image display of that topic is enabled);
* ``depth cloud``: plus a client that follows ``/oak/stereo/depth/points`` (what the page's
  PointCloud2 display sends).

The client is another process (aiohttp), as a browser would be. The simulator renders the
depth frame only while the image or the cloud has a subscriber. Once the client's topic is
subscribed (or at once, for the first two variants), the CPU time of this process (every
thread: simulator, viewer server, JPEG encoder) is measured over the run; the median is
printed. Reference: the ``none`` variant of the same run.

Run:  .venv/bin/python benchmarks/viewer.py [--sim-time 3] [--repeats 3]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from typing import Any

from posekit.robot.scenarios import run_robot_scenario

DEPTH_IMAGE = "/oak/stereo/depth"
DEPTH_CLOUD = "/oak/stereo/depth/points"
#: The client: connect, send one request, read (and drop) what comes until closed or 120 s.
CLIENT = """
import asyncio, json, sys, aiohttp
async def main(url, request):
    async with aiohttp.ClientSession() as s, s.ws_connect(url, max_msg_size=0) as ws:
        await ws.send_str(request)
        loop = asyncio.get_running_loop()
        end = loop.time() + 120.0
        while loop.time() < end:
            msg = await ws.receive(timeout=end - loop.time())
            if msg.type in (aiohttp.WSMsgType.CLOSE, aiohttp.WSMsgType.CLOSED,
                            aiohttp.WSMsgType.ERROR):
                return
asyncio.run(main(sys.argv[1], sys.argv[2]))
"""
REQUESTS = {
    "depth image": (DEPTH_IMAGE, {"op": "watch", "topics": [DEPTH_IMAGE]}),
    "depth cloud": (DEPTH_CLOUD, {"op": "display_subscribe", "topic": DEPTH_CLOUD,
                                  "type": "sensor_msgs/msg/PointCloud2", "queue": 1}),
}


def _run(variant: str, sim_time: float) -> float:
    """CPU seconds of this process over one run of ``variant`` (see the module doc)."""
    import json

    servers: list[Any] = []
    clients: list[subprocess.Popen[bytes]] = []
    start: list[float] = []

    def attach(run: Any) -> None:
        if variant != "none":
            from posekit.cli.view_cmd import attach_to_run

            server = attach_to_run(run, port=0)
            servers.append(server)
            if variant in REQUESTS:
                topic, request = REQUESTS[variant]
                url = server.url.replace("http://", "ws://") + "ws"
                clients.append(subprocess.Popen(
                    [sys.executable, "-c", CLIENT, url, json.dumps(request)],
                    stdout=subprocess.DEVNULL))
                transport = run.context.transport()
                deadline = time.monotonic() + 30.0
                while transport.count_subscribers(topic) == 0:
                    if time.monotonic() > deadline:
                        raise RuntimeError(f"the viewer did not subscribe {topic} within 30 s")
                    time.sleep(0.01)
        start.append(time.process_time())

    try:
        run_robot_scenario("p_controller", until_sim_time=sim_time, record=False,
                           on_start=[attach])
        return time.process_time() - start[0]
    finally:
        for server in servers:
            server.stop()
        for client in clients:
            client.terminate()
            client.wait(timeout=10.0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sim-time", type=float, default=3.0, help="simulated s per run")
    parser.add_argument("--repeats", type=int, default=3, help="runs per variant")
    args = parser.parse_args()
    variants = ["none", "attached", "depth image", "depth cloud"]
    cpu: dict[str, list[float]] = {v: [] for v in variants}
    for _ in range(args.repeats):
        for v in variants:
            cpu[v].append(_run(v, args.sim_time))
    try:
        load = " ".join(f"{x:.1f}" for x in os.getloadavg())
    except OSError:
        load = "n/a"
    print(f"p_controller, {args.sim_time:g} s of sim time, CPU s of this process, median of "
          f"{args.repeats} (load {load}):")
    for v in variants:
        print(f"  {v:12s} {statistics.median(cpu[v]):6.2f} s   "
              f"(runs: {', '.join(f'{c:.2f}' for c in cpu[v])})")


if __name__ == "__main__":
    main()
