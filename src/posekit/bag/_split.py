"""rosbag2 Jazzy's storage file layout on top of rosbags' Writer.

``<name>_<i>.mcap`` files, split by size or duration, one merged ``metadata.yaml``.

rosbag2 names a bag's storage files after the bag directory with a running index
(``run1/run1_0.mcap``, ``run1_1.mcap``, ...) and starts a new file before writing a message
when the current file has grown past ``max_bagfile_size`` bytes or the message lies more than
``max_bagfile_duration`` after the file's first message. Every file carries every topic's
schema and channel. metadata.yaml lists the files (``relative_file_paths`` and ``files`` with
per-file start, duration and count) and the totals, with ``ros_distro: jazzy``.

Each file is written by one rosbags ``Writer`` (MCAP storage plugin, so schemas, channels,
chunk compression and the metadata record are rosbags' own); this module only chooses the
file names, decides when to split and merges the per-file metadata.
"""

from __future__ import annotations

import os
import pathlib
from pathlib import Path
from typing import Any

from posekit.bag.errors import BagExistsError, BagOptionError

__all__ = ["COMPRESSION_MODES", "ROS_DISTRO", "SplitWriter"]

#: ``ros_distro`` written into metadata.yaml: the ROS 2 release posekit follows.
ROS_DISTRO = "jazzy"
#: posekit's names for rosbags' compression modes: MCAP chunks, whole files, messages, none.
COMPRESSION_MODES = ("storage", "file", "message", "none")


class _StemDir(pathlib.PosixPath):
    """A directory path whose ``name`` is a chosen file stem.

    rosbags' MCAP storage writes ``<dir>/<dir.name>.mcap``; giving it the bag directory with
    ``name`` set to ``<bag>_<i>`` makes that ``<bag>/<bag>_<i>.mcap``.
    """

    stem_override: str | None = None

    @property
    def name(self) -> str:
        return self.stem_override if self.stem_override is not None else super().name


def _stem_dir(directory: Path, stem: str) -> Path:
    path = _StemDir(directory)
    path.stem_override = stem
    return path


def _part_writer(directory: Path, stem: str, version: int) -> Any:
    """A rosbags ``Writer`` whose storage file is ``<directory>/<stem>.mcap``."""
    from rosbags.rosbag2 import StoragePlugin, Writer

    class _PartWriter(Writer):
        def open(self) -> None:  # the bag directory exists: only the storage file is new
            self.storage = self.STORAGE_PLUGINS[self.storage_plugin](
                self.path, self.compression_mode)

    writer = _PartWriter(directory / stem, version=8 if version == 8 else 9,
                         storage_plugin=StoragePlugin.MCAP)
    writer.path = _stem_dir(directory, stem)
    writer.metapath = directory / "metadata.yaml"
    return writer


class SplitWriter:
    """Writes a rosbag2 directory as rosbag2 Jazzy lays it out (see the module docstring).

    The interface follows rosbags' ``Writer`` (``set_custom_data``, ``open``,
    ``add_connection``, ``write``, ``close``); a connection handle stays valid across splits.

    Args:
        path: bag directory to create (must not exist).
        version: metadata.yaml version, 8 or 9.
        compression: ``"storage"`` (zstd MCAP chunks), ``"file"`` (each finished file
            zstd-compressed to ``.mcap.zstd``), ``"message"`` (each message zstd-compressed) or
            ``"none"``.
        max_bytes: start a new file once the current one holds more than this many bytes
            (0: never).
        max_duration_ns: start a new file for a message more than this after the current
            file's first message (0: never).
    """

    def __init__(self, path: str | Path, *, version: int = 9, compression: str = "storage",
                 max_bytes: int = 0, max_duration_ns: int = 0) -> None:
        if compression not in COMPRESSION_MODES:
            raise BagOptionError(f"compression must be one of {COMPRESSION_MODES}, "
                                 f"got {compression!r}")
        if max_bytes < 0 or max_duration_ns < 0:
            raise BagOptionError("split thresholds must be >= 0 (0 disables splitting)")
        self.path = Path(path)
        if self.path.exists():
            raise BagExistsError(f"{str(self.path)!r} exists already; bags are not overwritten")
        self.version = version
        self.compression = compression
        self.max_bytes = int(max_bytes)
        self.max_duration_ns = int(max_duration_ns)
        self.custom_data: dict[str, str] = {}
        self._connections: list[tuple[tuple[Any, ...], dict[str, Any]]] = []
        self._current: list[Any] = []  # rosbags connection per handle, in the open file
        self._writer: Any = None
        self._index = 0
        self._file_start_ns: int | None = None
        self._parts: list[dict[str, Any]] = []

    # -- rosbags Writer's interface ---------------------------------------------------------
    def set_custom_data(self, key: str, value: str) -> None:
        """Store ``key: value`` under ``custom_data`` in metadata.yaml."""
        self.custom_data[str(key)] = str(value)

    def open(self) -> None:
        """Create the bag directory and its first storage file."""
        try:
            self.path.mkdir(mode=0o755, parents=True)
        except FileExistsError:
            raise BagExistsError(
                f"{str(self.path)!r} exists already; bags are not overwritten") from None
        self._open_part()

    def add_connection(self, *args: Any, **kwargs: Any) -> int:
        """Add a topic (rosbags ``Writer.add_connection``'s arguments); returns its handle."""
        self._connections.append((args, kwargs))
        self._current.append(self._writer.add_connection(*args, **kwargs))
        return len(self._connections) - 1

    def write(self, handle: int, timestamp_ns: int, data: bytes | memoryview) -> None:
        """Write one serialized message, starting a new file first when a threshold is met."""
        if self._should_split(timestamp_ns):
            self._close_part()
            self._index += 1
            self._open_part()
        if self._file_start_ns is None:
            self._file_start_ns = timestamp_ns
        self._writer.write(self._current[handle], timestamp_ns, data)

    def close(self) -> dict[str, Any]:
        """Finish the last file and write the merged metadata.yaml; returns its content."""
        self._close_part()
        meta = self._merged()
        text = _dump_yaml({"rosbag2_bagfile_information": meta})
        tmp = self.path / "metadata.yaml.tmp"
        tmp.write_text(text, encoding="utf-8")
        os.replace(tmp, self.path / "metadata.yaml")
        return meta

    @property
    def storage(self) -> Any:
        """rosbags' storage writer of the open file (None when closed), for flushing."""
        return self._writer.storage if self._writer is not None else None

    @property
    def files(self) -> list[str]:
        """Storage files finished so far."""
        return [str(p["relative_file_paths"][0]) for p in self._parts]

    # -- internals ----------------------------------------------------------------------
    def _file_size(self) -> int:
        storage = self._writer.storage
        written = storage.bio.tell() if getattr(storage, "bio", None) is not None else 0
        pending = getattr(getattr(storage, "chunk", None), "bio", None)
        return int(written + (pending.tell() if pending is not None else 0))

    def _should_split(self, timestamp_ns: int) -> bool:
        if self._file_start_ns is None:
            return False
        if self.max_bytes and self._file_size() > self.max_bytes:
            return True
        return bool(self.max_duration_ns
                    and timestamp_ns - self._file_start_ns > self.max_duration_ns)

    def _open_part(self) -> None:
        from rosbags.rosbag2 import CompressionFormat, CompressionMode

        writer = _part_writer(self.path, f"{self.path.name}_{self._index}", self.version)
        mode = {"storage": CompressionMode.STORAGE, "file": CompressionMode.FILE,
                "message": CompressionMode.MESSAGE}.get(self.compression)
        if mode is not None:
            writer.set_compression(mode, CompressionFormat.ZSTD)
        for key, value in self.custom_data.items():
            writer.set_custom_data(key, value)
        writer.open()
        self._writer = writer
        self._file_start_ns = None
        self._current = [writer.add_connection(*a, **kw) for a, kw in self._connections]

    def _close_part(self) -> None:
        import yaml  # type: ignore[import-untyped,unused-ignore]

        if self._writer is None:
            return
        writer, self._writer = self._writer, None
        writer.close()
        text = (self.path / "metadata.yaml").read_text(encoding="utf-8")
        self._parts.append(yaml.safe_load(text)["rosbag2_bagfile_information"])

    def _merged(self) -> dict[str, Any]:
        parts = self._parts
        meta = dict(parts[-1])
        with_data = [p for p in parts if p["message_count"]] or parts[:1]
        start = min(p["starting_time"]["nanoseconds_since_epoch"] for p in with_data)
        end = max(p["starting_time"]["nanoseconds_since_epoch"] + p["duration"]["nanoseconds"]
                  for p in with_data)
        topics: dict[str, dict[str, Any]] = {}
        for part in parts:
            for entry in part["topics_with_message_count"]:
                name = entry["topic_metadata"]["name"]
                if name in topics:
                    topics[name]["message_count"] += entry["message_count"]
                else:
                    topics[name] = {"topic_metadata": entry["topic_metadata"],
                                    "message_count": entry["message_count"]}
        meta.update(
            relative_file_paths=[f for p in parts for f in p["relative_file_paths"]],
            files=[f for p in parts for f in p["files"]],
            starting_time={"nanoseconds_since_epoch": start},
            duration={"nanoseconds": max(0, end - start)},
            message_count=sum(p["message_count"] for p in parts),
            topics_with_message_count=list(topics.values()),
            custom_data=dict(self.custom_data) or None,
            ros_distro=ROS_DISTRO,
        )
        return meta


def _dump_yaml(data: dict[str, Any]) -> str:
    import yaml

    text: str = yaml.safe_dump(data, default_flow_style=False, sort_keys=False,
                               allow_unicode=True, width=1 << 16)
    return text
