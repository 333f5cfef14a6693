"""Reading the messages of a rosbag2 directory (any version rosbags reads; MCAP or SQLite)."""

from __future__ import annotations

from collections.abc import Collection, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from posekit.bag._storage import open_reader

__all__ = ["BagMessage", "read_messages"]


@dataclass(frozen=True, slots=True)
class BagMessage:
    """One recorded message: topic, ROS type name, bag timestamp (ns) and CDR bytes.

    ``timestamp_ns`` is the time the recorder stored with the message (rosbag2 and
    posekit's recorder: the receive time on the recorder's clock, sim time in simulated runs).
    """

    topic: str
    msgtype: str
    timestamp_ns: int
    data: bytes

    def decode(self) -> Any:
        """The message as posekit's dataclass (rosbags' class for types posekit lacks)."""
        from posekit.msgs.cdr import from_cdr

        return from_cdr(self.data, self.msgtype)


def read_messages(
    path: str | Path, topics: Collection[str] | None = None
) -> Iterator[BagMessage]:
    """Yield the messages of the bag at ``path`` in timestamp order.

    Args:
        path: rosbag2 directory.
        topics: only these topics (all when None).

    Raises:
        BagNotFoundError: no such bag directory / no metadata.yaml.
        BagFormatError: the bag is corrupted or unsupported (also raised mid-iteration when a
            damaged chunk is reached).
    """
    with open_reader(path) as reader:
        connections = [
            c for c in reader.connections if topics is None or c.topic in set(topics)
        ]
        if topics is not None and not connections:
            return
        for conn, timestamp, data in reader.messages(connections=connections):
            yield BagMessage(conn.topic, conn.msgtype, int(timestamp), bytes(data))
