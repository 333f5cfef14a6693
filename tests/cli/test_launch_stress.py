"""A ``--realtime`` launch never freezes while remote image subscribers come, go and die.

A ``posekit launch kdl_chain_demo --realtime`` once stopped for good (sim time stuck, main
thread blocked in the image publisher's network ``put``) after a remote ``topic hz`` on its
camera image subscribed and left. Here waves of remote subscribers of the overhead camera
image (``posekit topic hz``, several at once, joining while others leave) are ended with
SIGINT or killed with SIGKILL while images stream to them, for about 20 s.

Oracle: the launch's simulated time, read from its ``/clock`` by a subscriber in this test
process: it must advance in every 5 s of wall time, during the stress and after it (a
frozen simulator publishes nothing new), and the launch must still answer a fresh tool.
"""

from __future__ import annotations

import signal
import threading
import time

import pytest

from _support.procs import Proc
from _support.world import World

pytestmark = pytest.mark.slow

IMAGE = "/overhead_camera/image_raw"
STRESS_S = 15.0
WINDOW_S = 5.0


class ClockWatch:
    """(wall s, sim s) of every /clock message, from a zenoh node in this process."""

    def __init__(self) -> None:
        from posekit.msgs.rosgraph_msgs import Clock
        from posekit.runtime.context import Context
        from posekit.runtime.executors import SingleThreadedExecutor
        from posekit.runtime.node import Node

        self.samples: list[tuple[float, float]] = []
        self.ctx = Context()
        self.ctx.init(transport="zenoh")
        self.node = Node("_stress_clock_watch", context=self.ctx)
        self.node.create_subscription(Clock, "/clock", self._on_clock, 1)
        self.executor = SingleThreadedExecutor(context=self.ctx)
        self.executor.add_node(self.node)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._spin, daemon=True)
        self._thread.start()

    def _on_clock(self, msg: object) -> None:
        clock = msg.clock  # type: ignore[attr-defined]
        self.samples.append((time.monotonic(), clock.sec + clock.nanosec * 1e-9))

    def _spin(self) -> None:
        while not self._stop.is_set():
            self.executor.spin_once(timeout_sec=0.1)

    def sim_time(self) -> float:
        return self.samples[-1][1] if self.samples else 0.0

    def close(self) -> None:
        self._stop.set()
        self._thread.join(5)
        self.executor.shutdown()
        self.node.destroy_node()
        self.ctx.shutdown()


def assert_advancing(samples: list[tuple[float, float]], start: float, end: float) -> None:
    """Sim time grows within every WINDOW_S of wall time in [start, end]."""
    t = start
    while t + WINDOW_S <= end:
        inside = [sim for wall, sim in samples if t <= wall <= t + WINDOW_S]
        where = f"between wall {t - start:.1f} s and {t - start + WINDOW_S:.1f} s of the stress"
        assert len(inside) >= 2, f"no /clock {where}"
        assert inside[-1] > inside[0], f"sim time did not advance {where}: {inside[-3:]}"
        t += WINDOW_S / 2


def test_remote_image_subscribers_joining_leaving_and_dying_never_freeze_the_launch(
    joined: World,
) -> None:
    launch = joined.cli("launch", "kdl_chain_demo", "--realtime")
    launch.wait_stderr("[overhead_camera]", 60, "the launch to start")
    watch = ClockWatch()
    try:
        deadline = time.monotonic() + 30
        while watch.sim_time() < 1.0:
            assert time.monotonic() < deadline, f"no /clock from the launch\n{launch.describe()}"
            time.sleep(0.1)
        start = time.monotonic()
        live: list[Proc] = []
        frozen: list[Proc] = []
        waves = 0
        while time.monotonic() - start < STRESS_S:
            # A wave: three new subscribers join while the previous wave's leave or die.
            joining = [joined.cli("topic", "hz", IMAGE) for _ in range(3)]
            for i, proc in enumerate(live):
                if i == 0:  # frozen mid-stream: its socket stays open, nobody reads it
                    proc.popen.send_signal(signal.SIGSTOP)
                    frozen.append(proc)
                else:
                    proc.kill(signal.SIGKILL if (i + waves) % 2 else signal.SIGINT)
            live = joining
            waves += 1
            # Let images stream to them (hz prints once it has received a few).
            wave_end = time.monotonic() + 6.0
            while time.monotonic() < wave_end and not all(
                any("average rate" in line for line in p.out) for p in live
            ):
                time.sleep(0.2)
        for i, proc in enumerate(live):
            proc.kill(signal.SIGKILL if i % 2 else signal.SIGINT)
        assert_advancing(watch.samples, start, time.monotonic())  # with frozen readers
        for proc in frozen:
            proc.kill(signal.SIGKILL)
        received = sum(any("average rate" in line for line in p.out) for p in joined.procs)
        time.sleep(WINDOW_S + 1.0)  # the launch goes on after the last one died
        end = time.monotonic()
        assert waves >= 3
        assert received >= 3, "no subscriber received images: nothing was stressed"
        assert_advancing(watch.samples, start, end)
        assert launch.popen.poll() is None, launch.describe()
        sim_before = watch.sim_time()
    finally:
        watch.close()
    echo = joined.cli("topic", "echo", "/clock", "--once")
    text = echo.finish(30, "a fresh topic echo /clock")
    sec = int(text.split("sec:")[1].split()[0])
    assert sec >= int(sim_before), (text, sim_before)
