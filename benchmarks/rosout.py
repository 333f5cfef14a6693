"""Cost of /rosout: a node's log call with and without its /rosout publisher.

Run: ``.venv/bin/python benchmarks/rosout.py``. Both nodes log through a sink that discards
records (no terminal I/O, which would dominate); the ratio shows what publishing the Log on
the in-process bus with no subscriber adds (figures in docs/performance.md). Rates use the
process CPU time, so they do not depend on how busy the machine is.
"""

from __future__ import annotations

import time

from posekit.runtime import logging as rlog
from posekit.runtime.context import Context
from posekit.runtime.node import Node

N = 20_000


def per_second(node: Node) -> float:
    logger = node.get_logger()
    start = time.process_time()
    for i in range(N):
        logger.info(f"step {i} done")
    return N / (time.process_time() - start)


def main() -> None:
    rlog.remove_sink(rlog._stderr_sink)
    rlog.add_sink(lambda record: None)
    ctx = Context()
    ctx.init(transport="inprocess")
    quiet = Node("no_rosout", context=ctx, enable_rosout=False)
    loud = Node("with_rosout", context=ctx)
    best = {"without": 0.0, "with": 0.0}
    for _ in range(3):  # best of three, interleaved
        best["without"] = max(best["without"], per_second(quiet))
        best["with"] = max(best["with"], per_second(loud))
    print(f"log calls/s without /rosout: {best['without']:,.0f}")
    print(f"log calls/s with /rosout (no subscriber): {best['with']:,.0f}")
    print(f"ratio with/without: {best['with'] / best['without']:.2f}")
    ctx.shutdown()


if __name__ == "__main__":
    main()
