"""Damaged bags (a bounded, seeded fuzzer): playback either fails with BagFormatError, or
plays every message, or says how many messages it could not find. Never silently short.

Oracle: the recording itself, numbered messages "msg K" written by this test: a message
played must be one that was written, and the count read is compared with what was written
(the metadata's count for a bag whose storage was damaged after the fact).
"""

from __future__ import annotations

import contextlib
import io
import random
import shutil
from collections.abc import Iterator
from pathlib import Path

import pytest

from posekit.bag import BagError, Player, Recorder
from posekit.msgs.std_msgs import String
from posekit.runtime.context import Context
from posekit.runtime.node import Node
from posekit.runtime.sim_executor import SimulatedTimeExecutor

MESSAGES = 600
CHUNKS = 12
TRIALS = 45


@pytest.fixture(scope="module")
def good_bag(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A bag of MESSAGES numbered strings in CHUNKS MCAP chunks."""
    path = tmp_path_factory.mktemp("damaged") / "good"
    ctx = Context()
    ctx.init(transport="inprocess")
    try:
        executor = SimulatedTimeExecutor(context=ctx, publish_clock=False)
        node = Node("numbered", context=ctx)
        pub = node.create_publisher(String, "/chat", MESSAGES)
        recorder = Recorder(path, ["/chat"], context=ctx, flush_period=None)
        executor.add_node(node)
        executor.add_node(recorder.node)
        per_chunk = MESSAGES // CHUNKS
        for chunk in range(CHUNKS):
            for i in range(per_chunk):
                pub.publish(String(data=f"msg {chunk * per_chunk + i} " + "x" * 100))
            executor.run_for(0.1)
            recorder.flush()  # one MCAP chunk per batch
        assert recorder.close() == {"/chat": MESSAGES}
    finally:
        ctx.try_shutdown()
    return path


def chunk_index_damaged(good: Path, tmp: Path) -> Path:
    """A copy whose third chunk index (summary section) claims an end time before its
    messages: the reader then skips the chunk's messages without any error. MCAP layout:
    footer = opcode, u64 length, u64 summary_start, u64 summary_offset_start, u32 crc, then
    the 8-byte magic; a ChunkIndex record (opcode 0x08) starts with u64 message_start_time,
    u64 message_end_time."""
    bag = tmp / "chunk_index"
    shutil.copytree(good, bag)
    storage = bag / "good_0.mcap"
    data = bytearray(storage.read_bytes())
    footer = len(data) - 8 - 29
    assert data[footer] == 0x02
    pos = int.from_bytes(data[footer + 9:footer + 17], "little")
    seen = 0
    while data[pos] != 0x02:
        length = int.from_bytes(data[pos + 1:pos + 9], "little")
        if data[pos] == 0x08:
            seen += 1
            if seen == 3:
                start = int.from_bytes(data[pos + 9:pos + 17], "little")
                data[pos + 17:pos + 25] = (start - 1).to_bytes(8, "little")
                break
        pos += 9 + length
    assert seen == 3
    storage.write_bytes(bytes(data))
    return bag


def damaged_copies(good: Path, tmp: Path) -> Iterator[tuple[int, Path]]:
    rng = random.Random(1)
    for trial in range(TRIALS):
        bag = tmp / f"d{trial}"
        shutil.copytree(good, bag)
        storage = bag / "good_0.mcap"
        data = bytearray(storage.read_bytes())
        kind = trial % 3
        if kind == 0:  # a few flipped bytes
            for _ in range(rng.randint(1, 4)):
                data[rng.randrange(len(data))] = rng.randrange(256)
        elif kind == 1:  # a zeroed span
            start = rng.randrange(len(data))
            data[start:start + rng.randint(1, 64)] = b"\0" * 8
        else:  # truncated
            data = data[: rng.randrange(len(data))]
        storage.write_bytes(bytes(data))
        yield trial, bag


def test_damage_is_reported_never_silently_short(good_bag: Path, tmp_path: Path,
                                                 logs: list) -> None:
    written = {f"msg {k} " + "x" * 100 for k in range(MESSAGES)}
    outcomes = {"error": 0, "complete": 0, "short": 0}
    for trial, bag in damaged_copies(good_bag, tmp_path):
        ctx = Context()
        ctx.init(transport="inprocess")
        played: list[str] = []
        try:
            listener = Node("listener", context=ctx)
            listener.create_subscription(String, "/chat", lambda m, out=played: out.append(m.data),
                                         MESSAGES)
            executor = SimulatedTimeExecutor(context=ctx, publish_clock=False)
            executor.add_node(listener)
            before = len(logs)
            try:
                player = Player(bag, context=ctx)
                player.run_simulated(executor)
            except BagError:
                outcomes["error"] += 1
                continue
            assert player.expected == MESSAGES, trial
            assert set(played) <= written, trial  # nothing invented
            read = player.published + player.skipped
            if read == MESSAGES:
                assert player.missing == 0, trial
                outcomes["complete"] += 1
            else:
                assert player.missing == MESSAGES - read, trial
                errors = [r for r in logs[before:] if "is damaged" in r.message]
                assert len(errors) == 1, trial
                assert f"read {read} of the {MESSAGES}" in errors[0].message
                outcomes["short"] += 1
        finally:
            ctx.try_shutdown()
    # Both readable outcomes occur, so the checks above are exercised.
    assert outcomes["error"] > 0
    assert outcomes["complete"] > 0


def test_a_skipped_chunk_is_reported(good_bag: Path, tmp_path: Path, logs: list) -> None:
    bag = chunk_index_damaged(good_bag, tmp_path)
    ctx = Context()
    ctx.init(transport="inprocess")
    try:
        player = Player(bag, context=ctx)
        published = player.run_simulated(SimulatedTimeExecutor(context=ctx,
                                                               publish_clock=False))
    finally:
        ctx.try_shutdown()
    per_chunk = MESSAGES // CHUNKS
    assert published == MESSAGES - per_chunk
    assert player.missing == per_chunk
    errors = [r for r in logs if "is damaged" in r.message]
    assert len(errors) == 1
    assert f"read {MESSAGES - per_chunk} of the {MESSAGES} messages" in errors[0].message


def test_cli_exits_1_with_one_line_on_a_short_bag(good_bag: Path, tmp_path: Path) -> None:
    from posekit.cli import bag_cmd

    short = chunk_index_damaged(good_bag, tmp_path)
    ctx = Context()
    ctx.init(transport="inprocess")
    err = io.StringIO()
    try:
        with contextlib.redirect_stderr(err):
            code = bag_cmd.play([str(short), "--rate", "1000", "--no-clock"], context=ctx)
    finally:
        ctx.try_shutdown()
    assert code == 1
    lines = [line for line in err.getvalue().splitlines() if line.startswith("posekit bag")]
    assert len(lines) == 1
    assert "is damaged" in lines[0]
