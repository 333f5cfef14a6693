"""Recording another context over a network transport (Zenoh, DDS), as ``posekit bag record``
records other processes.

Oracles: the QoS each publisher was created with (a best-effort sensor topic and a latched,
transient-local one, published before the recorder existed) must be what metadata.yaml
stores as offered, and the messages the publishers sent must be in the bag (the latched one
too: only a transient-local request receives it, only a best-effort request matches the
sensor publisher), read back by rosbags.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from _support.network import network_contexts
from posekit.bag import Recorder, bag_info, read_messages
from posekit.msgs.std_msgs import Float64, String
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.qos import (
    DurabilityPolicy,
    QoSProfile,
    ReliabilityPolicy,
    qos_profile_sensor_data,
)

pytestmark = pytest.mark.slow  # real Zenoh sessions and DDS participants


@pytest.fixture(params=["zenoh", "dds"])
def network(request: pytest.FixtureRequest,
            monkeypatch: pytest.MonkeyPatch) -> Iterator[tuple[Context, Context]]:
    with network_contexts(request.param, monkeypatch) as contexts:
        yield contexts


def test_best_effort_and_latched_topics_of_another_context(
    network: tuple[Context, Context], tmp_path: Path,
) -> None:
    talker, recording = network
    node = Node("net_sensors", context=talker)
    latched = node.create_publisher(
        String, "/description", QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    latched.publish(String(data="<robot/>"))
    sensor = node.create_publisher(Float64, "/sensor", qos_profile_sensor_data)
    transport = recording.transport()
    deadline = time.monotonic() + 20.0
    while not (transport.count_publishers("/description")
               and transport.count_publishers("/sensor")):
        assert time.monotonic() < deadline, "the other context's publishers never showed"
        time.sleep(0.05)
    rec = Recorder(tmp_path / "net", ["/description", "/sensor"], context=recording)
    executor = SingleThreadedExecutor(context=recording)
    executor.add_node(rec.node)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    try:
        deadline = time.monotonic() + 20.0
        k = 0
        while rec.counts.get("/sensor", 0) < 5 or not rec.counts.get("/description"):
            assert time.monotonic() < deadline, f"recorded only {rec.counts}"
            sensor.publish(Float64(data=float(k)))
            k += 1
            time.sleep(0.02)
    finally:
        executor.shutdown()
        spinner.join(timeout=5)
        rec.close()
    info = bag_info(tmp_path / "net")
    offered = {t.name: t.offered_qos for t in info.topics}
    assert [q.reliability for q in offered["/sensor"]] == [ReliabilityPolicy.BEST_EFFORT]
    assert [q.durability for q in offered["/description"]] == [
        DurabilityPolicy.TRANSIENT_LOCAL]
    messages = list(read_messages(tmp_path / "net"))
    assert [m.decode().data for m in messages if m.topic == "/description"] == ["<robot/>"]
    values = [m.decode().data for m in messages if m.topic == "/sensor"]
    assert len(values) >= 5
    assert values == sorted(values)  # in order, each at most once
    assert len(set(values)) == len(values)
