"""``odometry_recorder``: records odometry topics of a run (for tests, plots and the CLI).

Subscribes ground truth (``ground_truth/odom``), wheel odometry (``odometry/wheels``) and
filtered odometry (``odometry/filtered``) and keeps every message as one row
``(stamp_s, x, y, yaw, vx, vyaw)``; also records when ``goal_reached`` turned True.
:meth:`OdometryRecorder.recording` returns an :class:`OdometryRecording` (numpy arrays) that
can be saved to / loaded from ``.npz`` and plotted with :mod:`posekit.robot.plot`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from posekit.geometry import wrap_angle
from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.std_msgs import Bool
from posekit.robot.kinematics import yaw_from_quaternion_xyzw
from posekit.runtime.node import Node
from posekit.time import stamp_to_ns

__all__ = ["COLUMNS", "DEFAULT_TOPICS", "OdometryRecorder", "OdometryRecording"]

#: Row layout of every recorded series.
COLUMNS: tuple[str, ...] = ("t", "x", "y", "yaw", "vx", "vyaw")

#: Series name -> topic recorded by default.
DEFAULT_TOPICS: dict[str, str] = {
    "ground_truth": "ground_truth/odom",
    "wheels": "odometry/wheels",
    "filtered": "odometry/filtered",
}

_FloatArray = npt.NDArray[np.float64]


@dataclass
class OdometryRecording:
    """Recorded odometry: ``series[name]`` is an (N, 6) array with columns :data:`COLUMNS`
    (stamp in s, pose in the message's frame, yaw wrapped to [-pi, pi], body twist);
    ``goal_reached`` the sim times (s) at which ``goal_reached`` was True."""

    series: dict[str, _FloatArray] = field(default_factory=dict)
    goal_reached: list[float] = field(default_factory=list)

    def final_errors(self, reference: str = "ground_truth") -> dict[str, tuple[float, float]]:
        """Per series: (position error m, |yaw error| rad) of its last row against the
        ``reference`` row with the closest stamp at or before it."""
        ref = self.series[reference]
        if len(ref) == 0:
            raise ValueError(f"series '{reference}' is empty")
        out: dict[str, tuple[float, float]] = {}
        for name, rows in self.series.items():
            if name == reference or len(rows) == 0:
                continue
            last = rows[-1]
            i = int(np.searchsorted(ref[:, 0], last[0] + 1e-12, side="right")) - 1
            r = ref[max(i, 0)]
            pos = math.hypot(last[1] - r[1], last[2] - r[2])
            out[name] = (pos, abs(wrap_angle(last[3] - r[3])))
        return out

    def save(self, path: str | Path) -> Path:
        """Write an ``.npz`` (arrays per series plus ``goal_reached``); returns the path."""
        p = Path(path)
        arrays: dict[str, Any] = {f"series_{k}": v for k, v in self.series.items()}
        arrays["goal_reached"] = np.asarray(self.goal_reached, dtype=np.float64)
        np.savez(p, **arrays)
        return p if p.suffix == ".npz" else p.with_name(p.name + ".npz")

    @classmethod
    def load(cls, path: str | Path) -> OdometryRecording:
        """Read a file written by :meth:`save` (ValueError if it is not one)."""
        with np.load(Path(path)) as data:
            series = {
                k[len("series_"):]: np.asarray(data[k], dtype=np.float64)
                for k in data.files
                if k.startswith("series_")
            }
            if not series:
                raise ValueError(f"{path} holds no odometry series (not a posekit recording)")
            for name, rows in series.items():
                if rows.ndim != 2 or rows.shape[1] != len(COLUMNS):
                    raise ValueError(f"{path}: series '{name}' has shape {rows.shape}")
            goal = [float(v) for v in data["goal_reached"]] if "goal_reached" in data else []
        return cls(series, goal)


class OdometryRecorder(Node):
    """Records odometry topics (see the module docstring).

    Args:
        topics: series name -> topic (default :data:`DEFAULT_TOPICS`).
    """

    def __init__(
        self,
        node_name: str = "odometry_recorder",
        *,
        topics: dict[str, str] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(node_name, **kwargs)
        self._rows: dict[str, list[tuple[float, ...]]] = {}
        self._goal: list[float] = []
        for name, topic in (topics or DEFAULT_TOPICS).items():
            rows: list[tuple[float, ...]] = []
            self._rows[name] = rows
            self.create_subscription(Odometry, topic, self._make_callback(rows), 100)
        self.create_subscription(Bool, "goal_reached", self._on_goal, 10)

    @staticmethod
    def _make_callback(rows: list[tuple[float, ...]]) -> Any:
        append = rows.append

        def on_odom(msg: Odometry) -> None:
            pose = msg.pose.pose
            q = pose.orientation
            twist = msg.twist.twist
            append(
                (
                    stamp_to_ns(msg.header.stamp) / 1e9,
                    float(pose.position.x),
                    float(pose.position.y),
                    yaw_from_quaternion_xyzw(float(q.x), float(q.y), float(q.z), float(q.w)),
                    float(twist.linear.x),
                    float(twist.angular.z),
                )
            )

        return on_odom

    def _on_goal(self, msg: Bool) -> None:
        if msg.data:
            self._goal.append(self.get_clock().now_ns() / 1e9)

    @property
    def goal_reached_times(self) -> list[float]:
        """Sim times (s) at which ``goal_reached`` True arrived (live list)."""
        return self._goal

    def rows(self, name: str) -> list[tuple[float, ...]]:
        """The raw rows recorded for series ``name`` so far (live list)."""
        return self._rows[name]

    def recording(self) -> OdometryRecording:
        """A snapshot of everything recorded so far."""
        series = {
            name: np.asarray(rows, dtype=np.float64).reshape(-1, len(COLUMNS))
            for name, rows in self._rows.items()
        }
        return OdometryRecording(series, list(self._goal))
