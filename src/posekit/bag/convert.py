"""``posekit bag convert``: rosbag2's ``bag_rewrite`` (``ros2 bag convert``) on posekit's writer.

Reads one or more input bags, merges their messages in timestamp order and writes each output
bag described by an options mapping (the ``output_bags`` entries of ros2 bag convert's YAML):

* ``uri`` (required), ``storage_id`` (``mcap`` or empty: posekit writes MCAP);
* ``max_bagfile_size`` (bytes) / ``max_bagfile_duration`` (seconds): file splitting;
* ``compression_mode`` (``file``/``message``; empty: zstd MCAP chunks, posekit's default) and
  ``compression_format`` (``zstd``);
* topic selection as in recording: ``all_topics``, ``topics``, ``regex`` (contains a match),
  ``exclude_regex``, ``exclude_topics``, ``include_hidden_topics``. With no selection the
  output bag is empty, as in rosbag2.

Messages are copied as recorded (CDR bytes, timestamps, offered QoS), never decoded, so
types posekit has no class for convert too as long as the input carries their definition.
Other keys of rosbag2's options (service selection, serialization format, queue sizes) are
accepted and ignored; an unknown key is an error.
"""

from __future__ import annotations

import heapq
import re
from collections.abc import Iterator, Mapping, Sequence
from contextlib import ExitStack
from pathlib import Path
from typing import Any

from posekit.bag._split import SplitWriter
from posekit.bag._storage import open_reader
from posekit.bag.errors import BagOptionError

__all__ = ["convert", "load_output_options"]

_KNOWN = {
    "uri", "storage_id", "max_bagfile_size", "max_bagfile_duration", "storage_preset_profile",
    "storage_config_uri", "all_topics", "topics", "topic_types", "all_services", "services",
    "rmw_serialization_format", "regex", "exclude_regex", "exclude_topics",
    "exclude_topic_types", "exclude_services", "compression_mode", "compression_format",
    "compression_queue_size", "compression_threads", "include_hidden_topics",
    "include_unpublished_topics",
}


def load_output_options(path: str | Path) -> list[dict[str, Any]]:
    """The ``output_bags`` list of a ros2 bag convert options file (checked)."""
    import yaml  # type: ignore[import-untyped,unused-ignore]

    try:
        data = yaml.safe_load(Path(path).read_text(encoding="utf-8"))
    except yaml.YAMLError as exc:
        raise BagOptionError(f"{str(path)!r} is not valid YAML: {exc}") from None
    bags = data.get("output_bags") if isinstance(data, dict) else None
    if not isinstance(bags, list) or not all(isinstance(b, dict) for b in bags):
        raise BagOptionError(f"{str(path)!r} needs a top-level 'output_bags' list of mappings")
    for options in bags:
        if unknown := sorted(set(options) - _KNOWN):
            raise BagOptionError(f"unknown output bag option(s) {unknown}")
        if not options.get("uri"):
            raise BagOptionError("every output bag needs a 'uri'")
        if options.get("storage_id", "") not in ("", "mcap"):
            raise BagOptionError(f"storage_id {options['storage_id']!r}: posekit writes mcap")
    return bags


class _Output:
    """One output bag: its writer and which topics go into it."""

    def __init__(self, options: Mapping[str, Any]) -> None:
        mode = str(options.get("compression_mode") or "").lower()
        if mode not in ("", "none", "file", "message"):
            raise BagOptionError(f"compression_mode {mode!r}: use file, message or none")
        fmt = str(options.get("compression_format") or "")
        if fmt not in ("", "zstd"):
            raise BagOptionError(f"compression_format {fmt!r}: only zstd is available")
        try:
            self.regex = re.compile(options["regex"]) if options.get("regex") else None
            self.exclude_regex = (re.compile(options["exclude_regex"])
                                  if options.get("exclude_regex") else None)
        except re.error as exc:
            raise BagOptionError(f"invalid regular expression: {exc}") from None
        self.all_topics = bool(options.get("all_topics", False))
        self.topics = set(options.get("topics") or [])
        self.exclude = set(options.get("exclude_topics") or [])
        self.include_hidden = bool(options.get("include_hidden_topics", False))
        self.writer = SplitWriter(
            options["uri"], compression=mode if mode in ("file", "message") else "storage",
            max_bytes=int(options.get("max_bagfile_size") or 0),
            max_duration_ns=int(float(options.get("max_bagfile_duration") or 0) * 1e9),
        )
        self.handles: dict[tuple[str, str], int] = {}

    def wants(self, topic: str) -> bool:
        if topic in self.exclude or (self.exclude_regex and self.exclude_regex.search(topic)):
            return False
        if topic in self.topics:
            return True
        if not (self.all_topics or (self.regex and self.regex.search(topic))):
            return False
        hidden = any(part.startswith("_") for part in topic.split("/") if part)
        return self.include_hidden or not hidden


def _definition(conn: Any, store: Any) -> dict[str, Any]:
    """How rosbags' Writer gets a type's definition.

    posekit's typestore for Jazzy types, else the definition and hash stored with the input
    connection.
    """
    if conn.msgtype in store.fielddefs:
        return {"typestore": store}
    if conn.msgdef is not None and conn.msgdef.data and conn.digest:
        return {"msgdef": conn.msgdef.data, "rihs01": conn.digest}
    raise BagOptionError(f"no message definition for {conn.msgtype} in the input bag")


def convert(inputs: Sequence[str | Path], outputs: Sequence[Mapping[str, Any]]) -> dict[str, int]:
    """Write ``outputs`` from the merged messages of ``inputs``; returns messages per output.

    Raises:
        BagNotFoundError, BagFormatError: an input is missing or damaged.
        BagExistsError: an output exists. BagOptionError: bad options.
    """
    if not inputs:
        raise BagOptionError("give at least one input bag")
    writers = [_Output(options) for options in outputs]
    counts = {str(options["uri"]): 0 for options in outputs}
    with ExitStack() as stack:
        readers = [stack.enter_context(open_reader(p)) for p in inputs]
        connections = [c for r in readers for c in r.connections]
        from posekit.msgs.cdr import get_typestore

        store = get_typestore()
        for out in writers:
            out.writer.set_custom_data("converted_by", "posekit bag convert")
            out.writer.open()
            for conn in connections:
                key = (conn.topic, conn.msgtype)
                if key in out.handles or not out.wants(conn.topic):
                    continue
                out.handles[key] = out.writer.add_connection(
                    conn.topic, conn.msgtype, **_definition(conn, store),
                    serialization_format=conn.ext.serialization_format,
                    offered_qos_profiles=list(conn.ext.offered_qos_profiles))

        def stream(reader: Any) -> Iterator[tuple[int, int, Any, bytes]]:
            for n, (conn, timestamp, data) in enumerate(reader.messages()):
                yield int(timestamp), n, conn, bytes(data)

        try:
            for timestamp, _, conn, data in heapq.merge(*(stream(r) for r in readers),
                                                         key=lambda item: item[0]):
                for out, options in zip(writers, outputs, strict=True):
                    handle = out.handles.get((conn.topic, conn.msgtype))
                    if handle is not None:
                        out.writer.write(handle, timestamp, data)
                        counts[str(options["uri"])] += 1
        finally:
            for out in writers:
                out.writer.close()
    return counts
