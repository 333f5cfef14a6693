"""Time series out of recordings, for ``posekit plot`` (PlotJuggler's role for bags).

A recording is a rosbag2 directory (read with rosbags, as :func:`posekit.bag.read_messages`)
or a single ``.mcap`` storage file (read with the ``mcap`` package, which needs no
metadata.yaml: a file copied out of its bag, or one part of a split bag).

* :func:`odometry_recording`: every ``nav_msgs/msg/Odometry``, ``geometry_msgs/msg/PoseStamped``
  and ``geometry_msgs/msg/PoseWithCovarianceStamped`` topic as one series of
  ``(stamp_s, x, y, yaw, vx, vyaw)`` rows (header stamps; twist zero for poses), named like
  the odometry recorder's series when the topic is one of its defaults (``ground_truth/odom``
  -> ``ground_truth``, ``odometry/wheels``, ``odometry/filtered``), else by the topic.
* :func:`field_series`: chosen fields (``pose.pose.position.x``) of one topic against time
  (the bag timestamp, or ``header.stamp``), in seconds.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from posekit.bag.errors import BagFormatError, BagNotFoundError, BagOptionError

__all__ = ["POSE_TYPES", "field_series", "iter_recording", "odometry_recording",
           "recorded_topics"]

#: Types :func:`odometry_recording` turns into pose series.
POSE_TYPES = ("nav_msgs/msg/Odometry", "geometry_msgs/msg/PoseStamped",
              "geometry_msgs/msg/PoseWithCovarianceStamped")


def _is_mcap_file(path: Path) -> bool:
    return path.is_file() and path.suffix == ".mcap"


def recorded_topics(path: str | Path) -> dict[str, str]:
    """topic -> type of a bag directory or ``.mcap`` file."""
    p = Path(path)
    if _is_mcap_file(p):
        with _mcap_reader(p) as reader:
            summary = reader.get_summary()
            if summary is None:
                raise BagFormatError(f"{str(p)!r} has no MCAP summary (an unfinished file?)")
            return {c.topic: summary.schemas[c.schema_id].name
                    for c in summary.channels.values()}
    from posekit.bag.info import bag_info

    return {t.name: t.msgtype for t in bag_info(p).topics}


class _mcap_reader:  # noqa: N801 - a context manager used like a function
    def __init__(self, path: Path) -> None:
        try:
            from mcap.reader import make_reader
        except ImportError:
            raise BagOptionError("reading a lone .mcap file needs the mcap package "
                                 "(pip install mcap, or posekit[plot]); or pass the bag "
                                 "directory") from None
        self._file = path.open("rb")
        self._reader = make_reader(self._file)

    def __enter__(self) -> Any:
        return self._reader

    def __exit__(self, *exc: object) -> None:
        self._file.close()


def iter_recording(path: str | Path,
                   topics: Sequence[str] | None = None) -> Iterator[tuple[str, str, int, Any]]:
    """``(topic, type, bag timestamp ns, decoded message)`` in time order."""
    from posekit.msgs.cdr import from_cdr

    p = Path(path)
    if not p.exists():
        raise BagNotFoundError(f"recording {str(p)!r} does not exist")
    if _is_mcap_file(p):
        with _mcap_reader(p) as reader:
            try:
                for schema, channel, message in reader.iter_messages(topics=topics):
                    yield channel.topic, schema.name, message.log_time, from_cdr(
                        message.data, schema.name)
            except (ValueError, KeyError, OSError) as exc:
                raise BagFormatError(f"cannot read {str(p)!r}: {exc}") from exc
        return
    if p.is_file():
        raise BagFormatError(f"{str(p)!r} is neither a rosbag2 directory nor an .mcap file")
    from posekit.bag.reader import read_messages

    for message in read_messages(p, topics):
        yield message.topic, message.msgtype, message.timestamp_ns, message.decode()


_SERIES_NAMES = {"/ground_truth/odom": "ground_truth", "/odometry/wheels": "wheels",
                 "/odometry/filtered": "filtered"}


def _yaw(q: Any) -> float:
    x, y, z, w = float(q.x), float(q.y), float(q.z), float(q.w)
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def odometry_recording(path: str | Path, topics: Sequence[str] | None = None) -> Any:
    """An :class:`~posekit.robot.nodes.recorder.OdometryRecording` of the pose topics.

    Raises:
        BagOptionError: a named topic is missing or not a pose type; no pose topic at all.
    """
    from posekit.robot.nodes.recorder import OdometryRecording

    available = {t: ty for t, ty in recorded_topics(path).items() if ty in POSE_TYPES}
    wanted = list(topics) if topics else sorted(available)
    if missing := [t for t in wanted if t not in available]:
        raise BagOptionError(f"no pose topic {missing} in {str(path)!r}; pose topics there: "
                             f"{sorted(available) or 'none'}")
    if not wanted:
        raise BagOptionError(f"{str(path)!r} has no {', '.join(POSE_TYPES)} topic")
    rows: dict[str, list[tuple[float, ...]]] = {t: [] for t in wanted}
    for topic, msgtype, _, msg in iter_recording(path, wanted):
        stamp = msg.header.stamp
        t = int(stamp.sec) + int(stamp.nanosec) * 1e-9
        if msgtype == "geometry_msgs/msg/PoseStamped":
            pose, vx, wz = msg.pose, 0.0, 0.0
        else:
            pose = msg.pose.pose
            twist = getattr(getattr(msg, "twist", None), "twist", None)
            vx = float(twist.linear.x) if twist is not None else 0.0
            wz = float(twist.angular.z) if twist is not None else 0.0
        rows[topic].append((t, float(pose.position.x), float(pose.position.y),
                            _yaw(pose.orientation), vx, wz))
    series: dict[str, npt.NDArray[np.float64]] = {
        _SERIES_NAMES.get(topic, topic): np.asarray(r, dtype=np.float64).reshape(-1, 6)
        for topic, r in rows.items()
    }
    return OdometryRecording(series=series)


def field_series(path: str | Path, topic: str, fields: Sequence[str], *,
                 header_stamp: bool = False) -> tuple[npt.NDArray[np.float64],
                                                       dict[str, npt.NDArray[np.float64]]]:
    """``(t_s, {field: values})`` of numeric ``fields`` of ``topic``.

    ``t_s`` is the bag timestamp (or ``header.stamp``) in seconds since the epoch / sim start.

    Raises:
        BagOptionError: the topic is not recorded, a field does not exist or is not a number.
    """
    from posekit.msgs.yaml_io import MessageFieldError, get_field

    topics = recorded_topics(path)
    if topic not in topics:
        raise BagOptionError(f"topic {topic!r} is not in {str(path)!r}; it has "
                             f"{sorted(topics)}")
    times: list[float] = []
    values: dict[str, list[float]] = {f: [] for f in fields}
    for _, _, stamp_ns, msg in iter_recording(path, [topic]):
        if header_stamp:
            header = getattr(msg, "header", None)
            if header is None:
                raise BagOptionError(f"{topics[topic]} has no header; plot against bag time")
            times.append(int(header.stamp.sec) + int(header.stamp.nanosec) * 1e-9)
        else:
            times.append(stamp_ns * 1e-9)
        for name in fields:
            try:
                value = get_field(msg, name)
                values[name].append(float(value))
            except MessageFieldError as exc:
                raise BagOptionError(str(exc)) from None
            except (TypeError, ValueError):
                raise BagOptionError(f"field {name!r} of {topics[topic]} is not a number "
                                     f"(got {type(value).__name__})") from None
    return (np.asarray(times, dtype=np.float64),
            {k: np.asarray(v, dtype=np.float64) for k, v in values.items()})
