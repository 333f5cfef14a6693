"""``aruco_marker_listener``: the lecture's ``aruco_marker_listener.py`` (Listening for Marker
Frames).

A ``Buffer`` (10 s) filled by a ``TransformListener``; every ``period`` seconds the node
discovers the frames whose names start with ``marker_prefix`` from
``Buffer.all_frames_as_yaml()`` and logs each one's position in ``target_frame``::

    aruco_marker_4 in odom: x=2.003, y=0.001, z=0.249

from ``lookup_transform(target_frame, frame, Time())`` (latest common time), waiting up to
``lookup_timeout`` seconds (wall clock, as tf2_ros) for missing data. A lookup that fails is
logged as a warning ``<frame> -> <target_frame>: <reason>`` and the next frame is tried.

Parameters: ``target_frame`` (odom), ``marker_prefix`` (aruco_marker_), ``period`` (1.0 s),
``lookup_timeout`` (0.1 s, the course's).
"""

from __future__ import annotations

from typing import Any

import yaml

from posekit.runtime.parameters import declare_value
from posekit.tf2.exceptions import TransformException
from posekit.time import Time
from posekit.vision.nodes._tf_lookup import PeriodicTfLookupNode

__all__ = ["ArucoMarkerListener"]

_SAFE_LOADER: Any = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


class ArucoMarkerListener(PeriodicTfLookupNode):
    """Logs every discovered marker frame's position in the target frame (module doc).

    Attributes: ``positions`` (``{frame: (x, y, z)}`` from the latest successful lookup, in
    metres in ``target_frame``), ``lookups`` (``[(sim_ns, frame, (x, y, z))]`` of every
    successful lookup), ``failures`` (``[(sim_ns, frame, reason)]``).
    """

    def __init__(self, node_name: str = "aruco_marker_listener", **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)
        self._target_frame = str(declare_value(self, "target_frame", "odom"))
        self._marker_prefix = str(declare_value(self, "marker_prefix", "aruco_marker_"))
        self.positions: dict[str, tuple[float, float, float]] = {}
        self.lookups: list[tuple[int, str, tuple[float, float, float]]] = []
        self.failures: list[tuple[int, str, str]] = []

    def _discover_marker_frames(self) -> list[str]:
        # yaml.safe_load's parser, in C when PyYAML has it (the dump of ~25 frames costs
        # ~30 ms to parse in pure Python).
        frames = yaml.load(self._tf_buffer.all_frames_as_yaml(), Loader=_SAFE_LOADER) or {}
        return sorted(name for name in frames if str(name).startswith(self._marker_prefix))

    def _timer_callback(self) -> None:
        now_ns = self.get_clock().now_ns()
        for frame in self._discover_marker_frames():
            try:
                t = self._tf_buffer.lookup_transform(
                    self._target_frame, frame, Time(), timeout=self._timeout
                )
            except TransformException as exc:
                self.failures.append((now_ns, frame, str(exc)))
                self.get_logger().warn(f"{frame} -> {self._target_frame}: {exc}")
                continue
            p = t.transform.translation
            xyz = (float(p.x), float(p.y), float(p.z))
            self.positions[frame] = xyz
            self.lookups.append((now_ns, frame, xyz))
            self.get_logger().info(
                f"{frame} in {self._target_frame}: x={p.x:.3f}, y={p.y:.3f}, z={p.z:.3f}"
            )
