"""``posekit bag reindex DIR``: recover a bag whose writer died (``ros2 bag reindex``'s role).

A recorder killed with SIGKILL (or by a power cut) leaves an MCAP file with its data chunks
but without the summary section and without ``metadata.yaml``. posekit's recorder writes
every chunk to disk as it goes (at least once a second), and every MCAP chunk it writes
starts with the schema and channel records of the topics known then, so such a file can be
read front to back (the ``mcap`` library's stream reader does not need the summary).

:func:`reindex` reads every storage file of the directory that way, stops at the first
record that is cut off or damaged (what a dying writer leaves at the end), and writes the
messages read into a complete bag in the same directory (summary, index and
``metadata.yaml``, via rosbags' writer). The original file is kept beside it, renamed
``NAME.mcap.orig``. rosbag2's ``reindex`` only writes ``metadata.yaml``: posekit rewrites
the storage as well because posekit's reader (rosbags) needs the summary section.
"""

from __future__ import annotations

import os
import shutil
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from posekit.bag.errors import BagFormatError, BagNotFoundError

__all__ = ["ReindexResult", "reindex"]


@dataclass
class ReindexResult:
    """What :func:`reindex` recovered."""

    path: Path
    #: Messages recovered per topic.
    counts: dict[str, int] = field(default_factory=dict)
    #: Why reading stopped early in each storage file that was cut off (empty if none).
    truncated: dict[str, str] = field(default_factory=dict)
    #: Topics whose messages could not be kept (no usable message definition), with why.
    skipped: dict[str, str] = field(default_factory=dict)

    @property
    def total(self) -> int:
        """Messages recovered in all."""
        return sum(self.counts.values())


@dataclass
class _Topic:
    name: str
    msgtype: str
    msgdef: str
    qos: str
    messages: list[tuple[int, bytes]] = field(default_factory=list)


def _salvage(path: Path, topics: dict[tuple[str, str], _Topic]) -> str:
    """Read ``path`` front to back into ``topics``.

    Returns why it stopped early ('' if it reached a clean end).
    """
    from mcap.records import Channel, Footer, Message, Schema
    from mcap.stream_reader import StreamReader

    schemas: dict[int, Schema] = {}
    channels: dict[int, _Topic] = {}
    with path.open("rb") as stream:
        reader = StreamReader(stream, record_size_limit=1 << 30)
        try:
            for record in reader.records:
                if isinstance(record, Schema):
                    schemas[record.id] = record
                elif isinstance(record, Channel):
                    schema = schemas.get(record.schema_id)
                    if schema is None:
                        continue
                    key = (record.topic, schema.name)
                    topic = topics.get(key)
                    if topic is None:
                        topic = topics[key] = _Topic(
                            record.topic, schema.name,
                            bytes(schema.data).decode("utf-8", "replace"),
                            record.metadata.get("offered_qos_profiles", ""),
                        )
                    channels[record.id] = topic
                elif isinstance(record, Message):
                    target = channels.get(record.channel_id)
                    if target is not None:
                        target.messages.append((record.log_time, bytes(record.data)))
                elif isinstance(record, Footer):
                    return ""
        except Exception as exc:  # the cut-off tail a dying writer leaves; keep what came before
            return f"{type(exc).__name__}: {exc}" if str(exc) else type(exc).__name__
    return "no footer (the writer did not finish the file)"


def _connection_args(topic: _Topic) -> dict[str, Any]:
    """msgdef and RIHS01 hash for rosbags' writer, from the recorded definition."""
    from rosbags.rosbag2.metadata import parse_qos
    from rosbags.typesys import Stores, get_types_from_msg
    from rosbags.typesys import get_typestore as rosbags_typestore

    store = rosbags_typestore(Stores.EMPTY)
    store.register(get_types_from_msg(topic.msgdef, topic.msgtype))
    return {
        "msgdef": topic.msgdef,
        "rihs01": store.hash_rihs01(topic.msgtype),
        "offered_qos_profiles": parse_qos(topic.qos) if topic.qos else [],
    }


def _file_order(path: Path) -> tuple[str, int, str]:
    """rosbag2's file order: ``<bag>_2.mcap`` before ``<bag>_10.mcap``."""
    stem, _, index = path.stem.rpartition("_")
    return (stem, int(index), path.name) if index.isdigit() else (path.stem, -1, path.name)


def reindex(path: str | Path) -> ReindexResult:
    """Rebuild the bag directory ``path`` from its MCAP storage files (module docstring).

    Raises :class:`BagNotFoundError` if ``path`` is missing or holds no ``.mcap`` file, and
    :class:`BagFormatError` if nothing at all could be read.
    """
    from posekit.bag._split import SplitWriter

    bag = Path(path)
    if not bag.is_dir():
        raise BagNotFoundError(f"bag {str(bag)!r} does not exist or is not a directory")
    files = sorted((p for p in bag.iterdir() if p.suffix == ".mcap" and p.is_file()),
                   key=_file_order)
    if not files:
        raise BagNotFoundError(f"{str(bag)!r} holds no .mcap storage file to reindex")
    result = ReindexResult(bag)
    topics: dict[tuple[str, str], _Topic] = {}
    for file in files:
        reason = _salvage(file, topics)
        if reason:
            result.truncated[file.name] = reason
    if not topics:
        raise BagFormatError(
            f"nothing recoverable in {str(bag)!r}: no channel records before the damage "
            f"({'; '.join(result.truncated.values()) or 'empty files'})"
        )
    staging = bag / f".reindex-{os.getpid()}"
    out = staging / bag.name
    try:
        writer = SplitWriter(out, version=9)  # rosbag2's names: <bag>_0.mcap
        writer.set_custom_data("reindexed_by", "posekit")
        writer.open()
        try:
            merged: list[tuple[int, int, Any, bytes]] = []
            for index, topic in enumerate(topics.values()):
                try:
                    connection = writer.add_connection(topic.name, topic.msgtype,
                                                       **_connection_args(topic))
                except Exception as exc:  # a definition rosbags cannot parse
                    result.skipped[topic.name] = f"{type(exc).__name__}: {exc}"
                    continue
                result.counts[topic.name] = len(topic.messages)
                merged.extend((t, index, connection, data) for t, data in topic.messages)
            merged.sort(key=lambda m: (m[0], m[1]))
            for stamp, _, connection, data in merged:
                writer.write(connection, stamp, data)
        finally:
            writer.close()
        for file in files:
            file.rename(file.with_name(file.name + ".orig"))
        for produced in out.iterdir():
            target = bag / produced.name
            if target.exists():
                target.unlink()
            produced.rename(target)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return result
