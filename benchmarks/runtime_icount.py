"""Fixed workloads of the runtime for counting instructions (load-independent figures).

Wall-clock and even CPU-time rates on the shared 2-core machine move by tens of percent with
the other jobs; the number of instructions a workload executes does not. Run each workload at
two sizes under valgrind and divide the difference by the number of callbacks between them
(the difference removes start-up and import costs):

    run() { PYTHONHASHSEED=0 valgrind --tool=cachegrind --cache-sim=no \\
        --cachegrind-out-file=/dev/null .venv/bin/python benchmarks/runtime_icount.py "$@" \\
        2>&1 | grep 'I *refs'; }
    run tf 50; run tf 250          # (difference) / 20000 = instructions per TF message
    run stepped 5; run stepped 25  # (difference) / 45600 = instructions per timer callback

* ``tf N``: N batches of 100 TFMessages (one transform) published to one subscription on the
  in-process bus, each batch delivered by ``SingleThreadedExecutor.spin_some()`` (the first
  row of ``benchmarks/runtime.py``).
* ``stepped S``: 5 nodes with 10 empty timers each (periods 10-50 ms) stepped to S simulated
  seconds by ``SimulatedTimeExecutor.run_until`` (2280 timer callbacks per simulated second;
  the middle row of the stepped-executor figures of ``benchmarks/runtime.py``).

Prints the number of callbacks run, so both sizes can be checked.
"""

from __future__ import annotations

import gc
import sys

from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.tf2_msgs import TFMessage
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.qos import QoSProfile
from posekit.runtime.sim_executor import SimulatedTimeExecutor


def stepped(sim_seconds: float, ctx: Context) -> int:
    executor = SimulatedTimeExecutor(context=ctx, publish_clock=False)
    for i in range(5):
        node = Node(f"n{i}", context=ctx)
        for j in range(10):
            node.create_timer(0.01 * (1 + (i + j) % 5), lambda: None)
        executor.add_node(node)
    gc.collect()
    executor.run_until(sim_seconds)
    return executor.callbacks_run


def tf(batches: int, ctx: Context) -> int:
    node = Node("bench", context=ctx)
    count = [0]

    def callback(_msg: object) -> None:
        count[0] += 1

    publisher = node.create_publisher(TFMessage, "topic", QoSProfile(depth=100))
    node.create_subscription(TFMessage, "topic", callback, QoSProfile(depth=100))
    executor = SingleThreadedExecutor(context=ctx)
    executor.add_node(node)
    t = TransformStamped()
    t.transform.rotation.w = 1.0
    msgs = [TFMessage(transforms=[t]) for _ in range(100)]
    gc.collect()
    for _ in range(batches):
        for m in msgs:
            publisher.publish(m)
        executor.spin_some()
    return count[0]


def main() -> None:
    what, size = sys.argv[1], float(sys.argv[2])
    ctx = Context()
    ctx.init()
    try:
        print(stepped(size, ctx) if what == "stepped" else tf(int(size), ctx))
    finally:
        ctx.shutdown()


if __name__ == "__main__":
    main()
