"""Player: a recorded run replayed on its own time line gives the same tf answers, latches
every static broadcaster, and paces wall-clock playback by the recorded stamps / rate."""

from __future__ import annotations

import itertools
import types
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import posekit.bag.player as player_module
from posekit.bag import (
    BagFormatError,
    BagNotFoundError,
    BagOptionError,
    Player,
    read_messages,
)
from posekit.msgs.rosgraph_msgs import Clock
from posekit.msgs.std_msgs import String
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.qos import DurabilityPolicy, QoSProfile
from posekit.runtime.sim_executor import SimulatedTimeExecutor
from posekit.tf2 import Buffer
from posekit.tf2_ros import TransformListener
from posekit.time import Time

PAIRS = [("odom", "base_link"), ("odom", "laser"), ("odom", "camera"), ("laser", "camera")]


def _lookups(buffer: Buffer, times_ns: list[int]) -> np.ndarray:
    rows = []
    for target, source in PAIRS:
        for t in times_ns:
            tr = buffer.lookup_transform(target, source, Time(nanoseconds=t)).transform
            rows.append([tr.translation.x, tr.translation.y, tr.translation.z,
                         tr.rotation.x, tr.rotation.y, tr.rotation.z, tr.rotation.w])
    return np.array(rows)


def _fresh_context() -> Context:
    ctx = Context()
    ctx.init(transport="inprocess")
    return ctx


def test_replay_into_buffer_gives_the_live_lookups(ctx: Context, tmp_path: Path,
                                                    kit: Any) -> None:
    # Live: a listener fills a Buffer while the talkers run and the recorder records.
    executor = SimulatedTimeExecutor(context=ctx, start_time=kit.START_S)
    live_node = Node("live_listener", context=ctx)
    live_buffer = Buffer()
    TransformListener(live_buffer, live_node)
    executor.add_node(live_node)
    talkers, camera = kit.Talkers(ctx), kit.CameraMount(ctx)
    executor.add_node(talkers)
    executor.add_node(camera)
    from posekit.bag import attach_recorder

    recorder = attach_recorder(executor, tmp_path / "run")
    executor.run_for(1.0)
    recorder.close()
    # Between /tf samples (interpolated) and on them, inside the recorded window.
    times = [kit.START_NS + k for k in range(50_000_000, 1_000_000_001, 37_000_000)]
    live = _lookups(live_buffer, times)
    live_latest = live_buffer.lookup_transform("odom", "camera", Time())

    # Replay into a fresh process-like context.
    ctx2 = _fresh_context()
    try:
        replay_exec = SimulatedTimeExecutor(context=ctx2)
        node = Node("replay_listener", context=ctx2)
        buffer = Buffer()
        TransformListener(buffer, node)
        replay_exec.add_node(node)
        player = Player(tmp_path / "run", context=ctx2)
        published = player.run_simulated(replay_exec)
        assert published == sum(recorder.counts.values())
        assert replay_exec.now_ns == kit.START_NS + 1_000_000_000  # ends at the last stamp
        replayed = _lookups(buffer, times)
        np.testing.assert_array_equal(replayed, live)  # same data -> identical answers
        latest = buffer.lookup_transform("odom", "camera", Time())
        assert latest.header.stamp == live_latest.header.stamp
        assert sorted(buffer.get_all_frame_names()) == sorted(live_buffer.get_all_frame_names())

        # A listener that starts after playback still gets BOTH static broadcasters'
        # transforms: the player latches every recorded /tf_static message.
        late_node = Node("late_listener", context=ctx2)
        late_buffer = Buffer()
        TransformListener(late_buffer, late_node)
        replay_exec.add_node(late_node)
        replay_exec.run_for(0.01)
        assert sorted(late_buffer.get_all_frame_names()) == ["base_link", "camera", "laser"]
        player.close()
    finally:
        ctx2.try_shutdown()


def test_simulated_replay_keeps_message_content_and_timing(recorded: Any) -> None:
    ctx2 = _fresh_context()
    try:
        executor = SimulatedTimeExecutor(context=ctx2)
        node = Node("sink", context=ctx2)
        got: list[tuple[int, Any]] = []
        node.create_subscription(
            String, "/chatter", lambda m: got.append((node.get_clock().now().nanoseconds, m)), 50
        )
        executor.add_node(node)
        player = Player(recorded.path, context=ctx2, topics=["/chatter"])
        assert list(player.topics) == ["/chatter"]
        player.run_simulated(executor)
        expected = [(t, m) for topic, t, m in recorded.talkers.sent if topic == "/chatter"]
        assert [t for t, _ in got] == [t for t, _ in expected]  # delivered at recorded times
        assert [m.data for _, m in got] == [m.data for _, m in expected]
    finally:
        ctx2.try_shutdown()


def test_simulated_loop_jumps_back_and_listener_clears(recorded: Any, logs: list[Any]) -> None:
    ctx2 = _fresh_context()
    try:
        executor = SimulatedTimeExecutor(context=ctx2)
        node = Node("loop_listener", context=ctx2)
        buffer = Buffer()
        TransformListener(buffer, node)
        count: list[int] = []
        node.create_subscription(String, "/chatter", lambda m: count.append(1), 50)
        executor.add_node(node)
        player = Player(recorded.path, context=ctx2, loop=True)
        player.run_simulated(executor, loops=2)
        assert player.loops_done == 2
        assert len(count) == 2 * recorded.counts["/chatter"]
        assert any("jump back in time" in r.message for r in logs)
    finally:
        ctx2.try_shutdown()


class _FakeTime:
    """Stands in for the ``time`` module inside the player: a wall clock that only moves
    when the player waits, so wall-clock pacing is checked exactly and instantly."""

    def __init__(self) -> None:
        self.now = 100.0

    def monotonic(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        self.now += max(0.0, seconds)


class _FakeWaitExecutor(SingleThreadedExecutor):
    """Runs ready callbacks, then 'waits' by moving the fake clock."""

    def __init__(self, fake: _FakeTime, context: Context) -> None:
        super().__init__(context=context)
        self.fake = fake

    def spin_once(self, timeout_sec: float | None = None) -> None:
        self.spin_some()
        self.fake.sleep(timeout_sec or 0.0)


@pytest.mark.parametrize("rate", [1.0, 4.0])
def test_wall_clock_play_paces_by_stamps_over_rate_and_publishes_clock(
    recorded: Any, monkeypatch: pytest.MonkeyPatch, rate: float, kit: Any
) -> None:
    fake = _FakeTime()
    monkeypatch.setattr(player_module, "time", types.SimpleNamespace(monotonic=fake.monotonic))
    ctx2 = _fresh_context()
    try:
        executor = _FakeWaitExecutor(fake, ctx2)
        node = Node("wall_sink", context=ctx2)
        chatter: list[tuple[float, str]] = []
        clocks: list[int] = []
        node.create_subscription(String, "/chatter",
                                 lambda m: chatter.append((fake.now, m.data)), 50)
        node.create_subscription(Clock, "/clock",
                                 lambda m: clocks.append(m.clock.sec * 10**9 + m.clock.nanosec),
                                 1000)
        executor.add_node(node)
        player = Player(recorded.path, context=ctx2, rate=rate, clock_frequency=50.0)
        start_wall = fake.now
        player.play(executor, sleep=fake.sleep)
        expected = [(t, m.data) for topic, t, m in recorded.talkers.sent if topic == "/chatter"]
        assert [d for _, d in chatter] == [d for _, d in expected]
        for (wall, _), (t, _) in zip(chatter, expected, strict=True):
            assert wall - start_wall == pytest.approx((t - kit.START_NS) / 1e9 / rate, abs=1e-9)
        # /clock: bag time, never backwards, from the first to the last stamp, and at least
        # clock_frequency per wall second of playback.
        assert clocks[0] == kit.START_NS
        assert clocks[-1] == kit.START_NS + 1_000_000_000
        assert all(b >= a for a, b in itertools.pairwise(clocks))
        assert len(set(clocks)) >= 50 * 1.0 / rate
    finally:
        ctx2.try_shutdown()


def test_wall_clock_loop_plays_every_pass(recorded: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    fake = _FakeTime()
    monkeypatch.setattr(player_module, "time", types.SimpleNamespace(monotonic=fake.monotonic))
    ctx2 = _fresh_context()
    try:
        executor = _FakeWaitExecutor(fake, ctx2)
        node = Node("loop_sink", context=ctx2)
        got: list[str] = []
        node.create_subscription(String, "/chatter", lambda m: got.append(m.data), 50)
        executor.add_node(node)
        player = Player(recorded.path, context=ctx2, loop=True, rate=10.0, publish_clock=False)
        player.play(executor, loops=3, sleep=fake.sleep)
        once = [m.data for topic, _, m in recorded.talkers.sent if topic == "/chatter"]
        assert got == once * 3
    finally:
        ctx2.try_shutdown()


def test_player_publishes_with_the_recorded_qos(recorded: Any) -> None:
    ctx2 = _fresh_context()
    try:
        player = Player(recorded.path, context=ctx2)
        static = player.topics["/tf_static"].qos
        assert static.durability == DurabilityPolicy.TRANSIENT_LOCAL
        assert static.depth == 2  # both latched messages
        assert player.topics["/imu"].qos.reliability.name == "BEST_EFFORT"
        assert player.topics["/tf"].qos == QoSProfile(depth=100)
        assert "/clock" not in player.topics
    finally:
        ctx2.try_shutdown()


def test_bad_input(tmp_path: Path, recorded: Any, ctx: Context) -> None:
    with pytest.raises(BagNotFoundError, match="does not exist"):
        Player(tmp_path / "missing", context=ctx)
    (tmp_path / "empty_dir").mkdir()
    with pytest.raises(BagNotFoundError, match=r"no metadata\.yaml"):
        Player(tmp_path / "empty_dir", context=ctx)
    with pytest.raises(BagOptionError, match="rate"):
        Player(recorded.path, context=ctx, rate=0.0)
    with pytest.raises(BagOptionError, match="not in bag"):
        Player(recorded.path, context=ctx, topics=["/nope"])
    assert isinstance(BagNotFoundError("x"), FileNotFoundError)
    assert issubclass(BagFormatError, Exception)
    # The recorded bag is untouched by failed players.
    assert sum(1 for _ in read_messages(recorded.path)) == sum(recorded.counts.values())


def test_bag_clock_follows_rate_pause_and_rate_changes_without_jumps() -> None:
    # Closed form: bag time = anchor + elapsed wall time * rate, frozen while paused.
    clock = player_module._BagClock(wall=10.0, bag=1_000_000_000, rate=2.0)
    assert clock.at(10.5, paused=False, rate=2.0) == 2_000_000_000
    assert clock.at(11.0, paused=True, rate=2.0) == 3_000_000_000  # paused where it was...
    assert clock.at(12.0, paused=True, rate=2.0) == 3_000_000_000
    assert clock.at(12.5, paused=False, rate=2.0) == 3_000_000_000  # ...resumes from there
    assert clock.at(13.0, paused=False, rate=2.0) == 4_000_000_000
    assert clock.at(14.0, paused=False, rate=0.5) == 6_000_000_000  # re-anchored, no jump
    assert clock.at(16.0, paused=False, rate=0.5) == 7_000_000_000
