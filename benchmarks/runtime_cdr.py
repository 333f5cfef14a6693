"""CDR encode/decode rates: posekit.msgs.to_cdr/from_cdr vs rosbags' typestore directly.

Run: ``.venv/bin/python benchmarks/runtime_cdr.py``. Prints messages/s for both and the ratio
posekit/rosbags (> 1 means posekit is faster). rosbags works on its own message classes;
posekit on its dataclasses and returns ``bytes`` (rosbags returns a memoryview).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np
from rosbags.typesys import Stores, get_typestore

from posekit.msgs import from_cdr, to_cdr
from posekit.msgs.builtin_interfaces import Time
from posekit.msgs.geometry_msgs import Quaternion, Transform, TransformStamped, Vector3
from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.sensor_msgs import Image
from posekit.msgs.std_msgs import Header
from posekit.msgs.tf2_msgs import TFMessage


def rates(fn_a: Callable[[], Any], fn_b: Callable[[], Any], rounds: int = 7) -> tuple[float, float]:
    """Calls per second of two functions, timed in alternating rounds (best round of each).

    Alternating keeps the comparison fair on a shared, noisy machine.
    """
    n = 1
    while True:
        t0 = time.perf_counter()
        for _ in range(n):
            fn_a()
        dt = time.perf_counter() - t0
        if dt > 0.02:
            break
        n *= 4
    n = max(1, int(n * 0.1 / dt))
    best = [float("inf"), float("inf")]
    for _ in range(rounds):
        for i, fn in enumerate((fn_a, fn_b)):
            t0 = time.perf_counter()
            for _ in range(n):
                fn()
            best[i] = min(best[i], time.perf_counter() - t0)
    return n / best[0], n / best[1]


def main() -> None:
    ref = get_typestore(Stores.ROS2_JAZZY)
    tf = TFMessage(
        transforms=[
            TransformStamped(
                header=Header(stamp=Time(sec=1, nanosec=2), frame_id="odom"),
                child_frame_id="base_link",
                transform=Transform(Vector3(1.0, 2.0, 3.0), Quaternion(0.0, 0.0, 0.0, 1.0)),
            )
        ]
    )
    odom = Odometry(header=Header(frame_id="odom"), child_frame_id="base_link")
    odom.pose.covariance = np.arange(36, dtype=np.float64)
    img = Image(header=Header(frame_id="camera"), height=720, width=1280, encoding="rgb8")
    img.step = 3 * 1280
    img.data = np.random.default_rng(0).integers(0, 256, 720 * 3840, dtype=np.uint8)

    print(f"{'message':<22}{'op':<10}{'posekit/s':>12}{'rosbags/s':>12}{'ratio':>8}")
    for label, msg in (("TFMessage (1 tf)", tf), ("Odometry", odom), ("Image 1280x720 rgb8", img)):
        name = msg.__msgtype__
        data = to_cdr(msg)
        ref_msg = ref.deserialize_cdr(data, name)
        assert bytes(ref.serialize_cdr(ref_msg, name)) == data
        enc_ours, enc_ref = rates(
            lambda m=msg: to_cdr(m), lambda m=ref_msg, n=name: ref.serialize_cdr(m, n)
        )
        msg_type = type(msg)
        dec_ours, dec_ref = rates(
            lambda d=data, t=msg_type: from_cdr(d, t),
            lambda d=data, n=name: ref.deserialize_cdr(d, n),
        )
        for op, ours, theirs in (("to_cdr", enc_ours, enc_ref), ("from_cdr", dec_ours, dec_ref)):
            print(f"{label:<22}{op:<10}{ours:>12,.0f}{theirs:>12,.0f}{ours / theirs:>8.2f}")


if __name__ == "__main__":
    main()
