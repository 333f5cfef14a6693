"""Recordings survive the way recorders really stop: SIGTERM, and SIGKILL then reindex.

Real processes over a real Zenoh router on a free loopback port: a publisher of numbered
std_msgs/String messages and ``posekit bag record``. Oracles: the ``mcap`` library (its
stream reader reads what is on disk while the recorder runs; its indexed reader needs the
summary section a finished file has) and rosbags' rosbag2 Reader (metadata.yaml plus
storage), and the message numbers themselves (consecutive: nothing lost in between).
"""

from __future__ import annotations

import os
import re
import signal
import sys
import textwrap
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from _support.ports import free_port
from _support.procs import Proc, stop_all

pytest.importorskip("zenoh")
mcap_reader = pytest.importorskip("mcap.reader")
mcap_stream = pytest.importorskip("mcap.stream_reader")
mcap_records = pytest.importorskip("mcap.records")

pytestmark = pytest.mark.slow

PUBLISHER = """
import sys, time
from posekit.msgs.std_msgs import String
from posekit.runtime.context import Context
from posekit.runtime.node import Node

ctx = Context()
ctx.init(transport="zenoh")
node = Node("numbered_talker", context=ctx)
pub = node.create_publisher(String, "/numbered", 100)
n = 0
while True:
    pub.publish(String(data=str(n)))
    n += 1
    time.sleep(0.01)
"""


class Procs:
    def __init__(self, tmp: Path) -> None:
        self.tmp = tmp
        self.env = {k: v for k, v in os.environ.items()
                    if not k.startswith(("ZENOH_", "ROS_DOMAIN", "POSEKIT_"))}
        self.env.update(POSEKIT_ZENOH_ROUTER=f"tcp/127.0.0.1:{free_port()}",
                        PYTHONUNBUFFERED="1")
        self.procs: list[Proc] = []

    def start(self, *args: str) -> Proc:
        proc = Proc([sys.executable, *args], self.env, cwd=self.tmp)
        self.procs.append(proc)
        return proc

    def cli(self, *args: str) -> Proc:
        return self.start("-m", "posekit.cli.main", *args)

    def close(self) -> None:
        stop_all(self.procs)


@pytest.fixture
def procs(tmp_path: Path) -> Iterator[Procs]:
    p = Procs(tmp_path)
    try:
        router = p.cli("router", "--listen", p.env["POSEKIT_ZENOH_ROUTER"])
        router.wait_line(lambda s: "listening on" in s, 15, "the router to listen")
        p.start("-c", textwrap.dedent(PUBLISHER))
        yield p
    finally:
        p.close()


def on_disk(mcap: Path) -> list[int]:
    """Message numbers readable front to back from the file as it is now (no summary
    needed), up to the first incomplete record."""
    numbers: list[int] = []
    if not mcap.exists():
        return numbers
    with mcap.open("rb") as f:
        try:
            for record in mcap_stream.StreamReader(f).records:
                if isinstance(record, mcap_records.Message):
                    # CDR string: 4-byte encapsulation, uint32 length, bytes with NUL
                    numbers.append(int(record.data[8:-1].decode()))
        except Exception:  # the writer is still writing: stop at the incomplete tail
            pass
    return numbers


def wait_for_data_on_disk(mcap: Path, recorder: Proc, at_least: int,
                          timeout: float = 30.0) -> list[int]:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        numbers = on_disk(mcap)
        if len(numbers) >= at_least:
            return numbers
        assert recorder.popen.poll() is None, recorder.describe()
        time.sleep(0.1)
    raise AssertionError(f"fewer than {at_least} messages on disk after {timeout} s "
                         f"(file size {mcap.stat().st_size if mcap.exists() else None})\n"
                         f"{recorder.describe()}")


def read_with_rosbags(bag: Path) -> list[int]:
    from rosbags.rosbag2 import Reader

    with Reader(bag) as reader:
        return [int(data[8:-1].decode()) for _, _, data in reader.messages()]


def assert_consecutive(numbers: list[int]) -> None:
    assert numbers, "no messages"
    assert numbers == list(range(numbers[0], numbers[0] + len(numbers)))


def test_sigterm_finishes_the_bag(procs: Procs) -> None:
    bag = procs.tmp / "term_bag"
    recorder = procs.cli("bag", "record", "-o", str(bag), "/numbered", "--transport", "zenoh")
    # Data reaches the disk while recording (not only at the end): within a few seconds.
    wait_for_data_on_disk(bag / "term_bag_0.mcap", recorder, at_least=20)
    recorder.popen.send_signal(signal.SIGTERM)
    recorder.finish(20, "the recorder after SIGTERM")
    assert recorder.popen.returncode == 0, recorder.describe()
    wrote = re.search(r"wrote (\d+) messages", "".join(recorder.err))
    assert wrote, recorder.describe()
    assert (bag / "metadata.yaml").is_file()
    numbers = read_with_rosbags(bag)
    assert len(numbers) == int(wrote.group(1))
    assert_consecutive(numbers)
    with (bag / "term_bag_0.mcap").open("rb") as f:
        summary = mcap_reader.make_reader(f).get_summary()
    assert summary is not None
    assert summary.statistics.message_count == len(numbers)


def test_sigkill_then_reindex_recovers_what_was_written(procs: Procs) -> None:
    bag = procs.tmp / "kill_bag"
    mcap = bag / "kill_bag_0.mcap"
    recorder = procs.cli("bag", "record", "-o", str(bag), "/numbered", "--transport", "zenoh")
    before = wait_for_data_on_disk(mcap, recorder, at_least=60)
    recorder.kill(signal.SIGKILL)
    assert not (bag / "metadata.yaml").exists()
    info = procs.cli("bag", "info", str(bag))
    info.finish(20, "bag info on the killed bag")
    assert info.popen.returncode == 1
    assert len("".join(info.err).strip().splitlines()) == 1  # one line, no traceback

    reindex = procs.cli("bag", "reindex", str(bag))
    out = reindex.finish(60, "bag reindex")
    assert reindex.popen.returncode == 0, reindex.describe()
    assert "reindexed" in out
    numbers = read_with_rosbags(bag)
    assert_consecutive(numbers)
    assert numbers[: len(before)] == before  # everything that was on disk is kept
    assert (bag / "kill_bag_0.mcap.orig").is_file()
    with mcap.open("rb") as f:
        reader = mcap_reader.make_reader(f)
        assert reader.get_summary() is not None
        schema, channel, _ = next(iter(reader.iter_messages()))
    assert channel.topic == "/numbered"
    assert schema.name == "std_msgs/msg/String"
    info = procs.cli("bag", "info", str(bag))
    text = info.finish(20, "bag info after reindex")
    assert f"Messages:          {len(numbers)}" in text
