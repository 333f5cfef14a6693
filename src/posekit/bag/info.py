"""What is in a bag: ``posekit bag info DIR`` (the block ``ros2 bag info`` prints).

:func:`bag_info` reads ``metadata.yaml`` and opens the storage (so a damaged storage file is
reported here, not only on playback); :func:`format_info` lays it out like ``ros2 bag info``:
file list, size in KiB/MiB, storage id, ROS distro, duration, start and end as local date and
time with the epoch seconds, message count, one line per topic, then Jazzy's service section
(``Service:`` count and ``Service information:`` lines for recorded service event topics,
``<service>/_service_event`` of type ``pkg/srv/Name_Event``, which are left out of the topic
lines and of the message count, as rosbag2 does). Times are printed to the nanosecond (ROS 2
releases before Jazzy printed milliseconds without zero padding).
``verbose=True`` adds the metadata version, compression and each topic's offered QoS, and,
given :func:`service_counts`, lists each service with its request and response counts instead
of its event count, as Jazzy's ``ros2 bag info --verbose`` does (rosbag2 counts the distinct
``(client_gid, sequence_number)`` pairs of the REQUEST_SENT/REQUEST_RECEIVED events, and of
the RESPONSE_SENT/RESPONSE_RECEIVED ones, read from each event's ``ServiceEventInfo``).
"""

from __future__ import annotations

import datetime
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from posekit.bag._qos import from_rosbags_qos
from posekit.bag._storage import check_bag_dir, open_reader
from posekit.bag.errors import BagFormatError
from posekit.runtime.qos import QoSProfile
from posekit.runtime.services import SERVICE_EVENT_SUFFIX

__all__ = [
    "SERVICE_EVENT_SUFFIX",
    "BagInfo",
    "TopicInfo",
    "bag_info",
    "format_info",
    "is_service_event_topic",
    "is_service_event_type",
    "service_counts",
]

_INDENT = 19  # width of the longest label, "Topic information: "


@dataclass(frozen=True)
class TopicInfo:
    """One topic of a bag."""

    name: str
    msgtype: str
    message_count: int
    serialization_format: str
    offered_qos: list[QoSProfile]
    type_hash: str


@dataclass(frozen=True)
class BagInfo:
    """Summary of a rosbag2 directory (times in ns since the epoch of the recording clock)."""

    path: Path
    version: int
    storage_identifier: str
    files: list[str]
    bag_size: int
    ros_distro: str
    start_ns: int
    duration_ns: int
    message_count: int
    compression_format: str
    compression_mode: str
    topics: list[TopicInfo]
    custom_data: dict[str, str] = field(default_factory=dict)
    #: Compression of the MCAP chunks ("zstd", "lz4", "" for none; empty for SQLite).
    chunk_compression: str = ""

    @property
    def end_ns(self) -> int:
        """Time stamp of the last message."""
        return self.start_ns + self.duration_ns

    def topic(self, name: str) -> TopicInfo:
        """The topic called ``name`` (KeyError listing the others)."""
        for t in self.topics:
            if t.name == name:
                return t
        raise KeyError(f"bag has no topic {name!r}; topics: {[t.name for t in self.topics]}")


def _load_metadata(path: Path) -> dict[str, Any]:
    from ruamel.yaml import YAML
    from ruamel.yaml.error import YAMLError

    try:
        data = YAML(typ="safe").load((path / "metadata.yaml").read_text(encoding="utf-8"))
    except (YAMLError, UnicodeDecodeError, OSError) as exc:
        raise BagFormatError(f"{str(path)!r}: metadata.yaml is not valid YAML: {exc}") from exc
    info = data.get("rosbag2_bagfile_information") if isinstance(data, dict) else None
    if not isinstance(info, dict):
        raise BagFormatError(
            f"{str(path)!r}: metadata.yaml has no 'rosbag2_bagfile_information' mapping"
        )
    return info


def bag_info(path: str | Path) -> BagInfo:
    """Read the summary of the bag directory ``path``.

    Raises:
        BagNotFoundError: missing directory or metadata.yaml.
        BagFormatError: invalid metadata or a storage file that cannot be opened.
    """
    p = check_bag_dir(path)
    meta = _load_metadata(p)
    with open_reader(p) as reader:
        connections = list(reader.connections)
        chunk_compression = _chunk_compression(reader)
    topics = [
        TopicInfo(
            name=c.topic,
            msgtype=c.msgtype,
            message_count=int(c.msgcount),
            serialization_format=c.ext.serialization_format,
            offered_qos=[from_rosbags_qos(q) for q in c.ext.offered_qos_profiles],
            type_hash=str(c.digest or ""),
        )
        for c in connections
    ]
    try:
        files = [str(f) for f in meta.get("relative_file_paths", [])]
        size = sum((p / Path(f).name).stat().st_size for f in files)
        return BagInfo(
            path=p,
            version=int(meta["version"]),
            storage_identifier=str(meta["storage_identifier"]),
            files=files,
            bag_size=size,
            ros_distro=str(meta.get("ros_distro") or "unknown"),
            start_ns=int(meta["starting_time"]["nanoseconds_since_epoch"]),
            duration_ns=int(meta["duration"]["nanoseconds"]),
            message_count=int(meta["message_count"]),
            compression_format=str(meta.get("compression_format") or ""),
            compression_mode=str(meta.get("compression_mode") or ""),
            topics=topics,
            custom_data=dict(meta.get("custom_data") or {}),
            chunk_compression=chunk_compression,
        )
    except (KeyError, TypeError, ValueError, OSError) as exc:
        raise BagFormatError(f"{str(p)!r}: incomplete metadata.yaml: {exc!r}") from exc


def _chunk_compression(reader: Any) -> str:
    """Chunk compression names of rosbags' MCAP storages (private attributes, read only)."""
    names: set[str] = set()
    for storage in getattr(getattr(reader, "storage", None), "storages", []):
        names.update(str(chunk.compression) for chunk in getattr(storage, "chunks", []))
    return ",".join(sorted(names))


def format_size(size: int) -> str:
    """``ros2 bag info``'s size: bytes below 1 KiB, else one decimal in KiB/MiB/GiB/TiB."""
    value = float(size)
    units = ["B", "KiB", "MiB", "GiB", "TiB"]
    index = 0
    while value >= 1024 and index < len(units) - 1:
        value /= 1024
        index += 1
    return f"{value:.0f} {units[index]}" if index == 0 else f"{value:.1f} {units[index]}"


def _seconds(ns: int) -> str:
    sec, frac = divmod(ns, 1_000_000_000)
    return f"{sec}.{frac:09d}"


def _time_point(ns: int) -> str:
    sec, frac = divmod(ns, 1_000_000_000)
    local = datetime.datetime.fromtimestamp(sec)
    day = f"{local.day:2d}"
    return (
        f"{local:%b} {day} {local.year} {local:%H:%M:%S}.{frac:09d} ({_seconds(ns)})"
    )


def _qos_text(q: QoSProfile) -> str:
    history = "keep_all" if q.history.name == "KEEP_ALL" else f"keep_last({q.depth})"
    return (
        f"{history}, {q.resolved_reliability.name.lower()}, "
        f"{q.resolved_durability.name.lower()}"
    )


def service_counts(path: str | Path) -> dict[str, tuple[int, int]]:
    """``{service event topic: (requests, responses)}`` of the bag at ``path``.

    Counted as rosbag2 Jazzy's ``Info::read_service_info``: distinct ``(client_gid,
    sequence_number)`` pairs per kind. Only each event's leading
    ``service_msgs/msg/ServiceEventInfo`` is read, so services of any type are counted (types
    posekit does not know included).

    Raises:
        BagFormatError: a service event too short to hold its ServiceEventInfo.
    """
    from posekit.bag.reader import read_messages

    events = [t.name for t in bag_info(path).topics if is_service_event_topic(t.name, t.msgtype)]
    seen: dict[str, tuple[set[tuple[bytes, int]], set[tuple[bytes, int]]]] = {
        topic: (set(), set()) for topic in events}
    if not events:
        return {}
    for message in read_messages(path, events):
        event_type, gid, sequence = _event_info(message.data, message.topic)
        requests, responses = seen[message.topic]
        if event_type in (0, 1):  # REQUEST_SENT, REQUEST_RECEIVED
            requests.add((gid, sequence))
        elif event_type in (2, 3):  # RESPONSE_SENT, RESPONSE_RECEIVED
            responses.add((gid, sequence))
    return {topic: (len(req), len(resp)) for topic, (req, resp) in seen.items()}


def _event_info(data: bytes, topic: str) -> tuple[int, bytes, int]:
    """``(event_type, client_gid, sequence_number)`` of a CDR service event.

    Its first field is a ServiceEventInfo (uint8, Time{int32, uint32}, uint8[16], int64 at
    offset 32).
    """
    import struct

    if len(data) < 44 or data[0] != 0 or data[1] not in (0, 1):
        raise BagFormatError(f"a message on {topic!r} is not a CDR service event")
    order = "<" if data[1] == 1 else ">"
    (sequence,) = struct.unpack_from(order + "q", data, 4 + 32)
    return data[4], bytes(data[4 + 12:4 + 28]), int(sequence)


def format_info(info: BagInfo, *, verbose: bool = False,
                service_counts: dict[str, tuple[int, int]] | None = None) -> str:
    """The text ``posekit bag info`` prints (see the module docstring).

    ``service_counts`` (from :func:`service_counts`) makes the service lines Jazzy's verbose
    ones.
    """
    pad = " " * _INDENT
    lines = [""]
    files = info.files or [""]
    lines.append(f"{'Files:':<{_INDENT}}{files[0]}")
    lines.extend(pad + f for f in files[1:])
    lines.append(f"{'Bag size:':<{_INDENT}}{format_size(info.bag_size)}")
    lines.append(f"{'Storage id:':<{_INDENT}}{info.storage_identifier}")
    lines.append(f"{'ROS Distro:':<{_INDENT}}{info.ros_distro}")
    if verbose:
        lines.append(f"{'Version:':<{_INDENT}}{info.version}")
        if info.compression_format:
            compression = f"{info.compression_format} ({info.compression_mode})"
        elif info.chunk_compression:
            compression = f"{info.chunk_compression} (storage chunks)"
        else:
            compression = "none"
        lines.append(f"{'Compression:':<{_INDENT}}{compression}")
    lines.append(f"{'Duration:':<{_INDENT}}{_seconds(info.duration_ns)}s")
    lines.append(f"{'Start:':<{_INDENT}}{_time_point(info.start_ns)}")
    lines.append(f"{'End:':<{_INDENT}}{_time_point(info.end_ns)}")
    lines.append(f"{'Messages:':<{_INDENT}}{info.message_count}")
    topics = [t for t in info.topics if not is_service_event_topic(t.name, t.msgtype)]
    services = [t for t in info.topics if is_service_event_topic(t.name, t.msgtype)]
    lines[-1] = (f"{'Messages:':<{_INDENT}}"
                 f"{info.message_count - sum(t.message_count for t in services)}")
    topic_lines = [
        f"Topic: {t.name} | Type: {t.msgtype} | Count: {t.message_count} | "
        f"Serialization Format: {t.serialization_format}"
        + (
            " | QoS: " + "; ".join(_qos_text(q) for q in t.offered_qos)
            if verbose and t.offered_qos
            else ""
        )
        for t in topics
    ] or [""]
    lines.append(f"{'Topic information:':<{_INDENT}}{topic_lines[0]}")
    lines.extend(pad + t for t in topic_lines[1:])
    lines.append(f"{'Service:':<{_INDENT}}{len(services)}")
    counts = service_counts or {}
    service_lines = [
        f"Service: {t.name.removesuffix(SERVICE_EVENT_SUFFIX)} | "
        f"Type: {t.msgtype.removesuffix('_Event')} | "
        + (f"Request Count: {counts[t.name][0]} | Response Count: {counts[t.name][1]} | "
           if t.name in counts else f"Event Count: {t.message_count} | ")
        + f"Serialization Format: {t.serialization_format}"
        for t in services
    ]
    lines.append("Service information: " + (service_lines[0] if service_lines else ""))
    lines.extend(" " * (_INDENT + 2) + t for t in service_lines[1:])
    return "\n".join(lines) + "\n"


def is_service_event_type(msgtype: str) -> bool:
    """rosbag2's test for a service event type: a ``/srv/`` type ending ``_Event``."""
    return len(msgtype) > len("_Event") and "/srv/" in msgtype and msgtype.endswith("_Event")


def is_service_event_topic(name: str, msgtype: str) -> bool:
    """rosbag2's test for a service event topic.

    A ``/srv/`` type ending ``_Event`` on a topic ending ``/_service_event``.
    """
    return (len(name) > len(SERVICE_EVENT_SUFFIX) and name.endswith(SERVICE_EVENT_SUFFIX)
            and is_service_event_type(msgtype))
