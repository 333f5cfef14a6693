"""CPU per message of posekit's Zenoh receive path in one thread, against raw decoding of the
same samples: the per-message Python cost, without the scheduler's noise of two processes.

Run: ``.venv/bin/python benchmarks/transport_replay.py`` (``--rounds N``, ``--messages
tf,image``). Figures are recorded in docs/performance.md.

One process, one Zenoh session (a router on a free loopback port). A publisher and a
subscription of one topic: every publish lands in the subscription's channel at once
(zenoh delivers to a local subscriber inside ``put``), so the channel is filled before the
clock starts. Then, CPU time per message of the thread that handles them
(``time.thread_time``; zenoh's own threads are idle meanwhile):

* ``raw``: take each sample from a plain zenoh subscriber's channel (another topic of the
  same session), decode rmw_zenoh's attachment and the CDR with
  rosbags (``deserialize_cdr``), call a callback: what the raw baseline of
  ``benchmarks/transport.py`` does per sample;
* ``posekit``: ``SingleThreadedExecutor.spin()`` reading the channel itself (the checks,
  ``from_cdr`` into posekit's classes, the queue, the callback), stopped by the callback
  after the last message.

Best and median of the rounds; the ratio of the medians.
"""

from __future__ import annotations

import argparse
import os
import socket
import statistics
import time
from typing import Any

import numpy as np

from posekit.msgs.cdr import get_typestore
from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.sensor_msgs import Image
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.qos import HistoryPolicy, QoSProfile
from posekit.transport.zenoh_wire import decode_attachment

#: (class, type name, messages per round): fewer images, so a round fits the channel.
MESSAGES: dict[str, tuple[type[Any], str, int]] = {
    "tf": (TransformStamped, "geometry_msgs/msg/TransformStamped", 3000),
    "image": (Image, "sensor_msgs/msg/Image", 2000),
}


def _example(kind: str) -> Any:
    if kind == "image":
        return Image(height=128, width=128, encoding="rgb8", step=384,
                     data=np.zeros(128 * 128 * 3, np.uint8))
    return TransformStamped()


def measure(kind: str, rounds: int) -> dict[str, list[float]]:
    """CPU µs per message of each mode (this thread's), one value per round."""
    import zenoh

    from posekit.transport.zenoh_wire import data_key

    cls, type_name, count = MESSAGES[kind]
    ctx = Context()
    ctx.init(transport="zenoh")
    node = Node("replay", context=ctx)
    keep_all = QoSProfile(history=HistoryPolicy.KEEP_ALL, depth=0)
    pub = node.create_publisher(cls, "/replay", keep_all)
    raw_pub = node.create_publisher(cls, "/replay_raw", keep_all)
    session = node.transport.session.session  # type: ignore[attr-defined]
    raw_key = data_key(int(os.environ.get("ROS_DOMAIN_ID", "0")), "/replay_raw", type_name)
    got = [0]
    executor: list[SingleThreadedExecutor] = []

    def callback(_msg: Any) -> None:
        got[0] += 1
        if got[0] == count and executor:
            executor[0].shutdown()

    node.create_subscription(cls, "/replay", callback, keep_all)
    msg = _example(kind)
    deserialize = get_typestore().deserialize_cdr
    results: dict[str, list[float]] = {"raw": [], "posekit": []}
    try:
        for _ in range(rounds):
            # posekit: the executor takes the channel over with a first sample (that
            # spin() ends at once), then a second spin() handles a full channel
            executor[:] = [SingleThreadedExecutor(context=ctx)]
            executor[0].add_node(node)
            got[0] = count - 1
            pub.publish(msg)
            executor[0].spin()
            executor[0] = SingleThreadedExecutor(context=ctx)
            executor[0].add_node(node)
            for _ in range(count):
                pub.publish(msg)
            got[0] = 0
            start = time.thread_time()
            executor[0].spin()
            results["posekit"].append((time.thread_time() - start) / count * 1e6)
            executor[0].remove_node(node)
            executor.clear()
            # raw: a plain zenoh subscriber's channel, read and decoded in this thread
            raw_sub = session.declare_subscriber(raw_key, zenoh.handlers.FifoChannel(count))
            for _ in range(count):
                raw_pub.publish(msg)
            got[0] = 0
            start = time.thread_time()
            for _ in range(count):
                sample = raw_sub.try_recv()
                decode_attachment(sample.attachment.to_bytes())
                callback(deserialize(sample.payload.to_bytes(), type_name))
            results["raw"].append((time.thread_time() - start) / count * 1e6)
            raw_sub.undeclare()
    finally:
        ctx.shutdown()
    return results


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--messages", default="tf,image")
    args = parser.parse_args()
    with socket.socket() as s:  # a private router endpoint
        s.bind(("127.0.0.1", 0))
        os.environ["POSEKIT_ZENOH_ROUTER"] = f"tcp/127.0.0.1:{s.getsockname()[1]}"
    for kind in args.messages.split(","):
        res = measure(kind, args.rounds)
        line = ", ".join(f"{mode} {min(v):.2f} / {statistics.median(v):.2f}"
                         for mode, v in res.items())
        ratio = statistics.median(res["posekit"]) / statistics.median(res["raw"])
        print(f"{kind}: CPU us per message, best / median of {args.rounds} rounds: {line}; "
              f"posekit / raw {ratio:.2f}")


if __name__ == "__main__":
    main()
