"""The course's ``random_mover`` demo as a pure, seeded model.

Every ``1 / publish_rate`` s (default 2 Hz) the node publishes a TwistStamped with
``linear.x ~ U(-0.5, 0.5)`` m/s and ``angular.z ~ U(-1.0, 1.0)`` rad/s (the course uses the
unseeded ``random`` module; here ``seed`` makes runs reproducible), and logs the filtered
pose at most once per second as ``Odom: x=.., y=.., yaw=..``.
"""

from __future__ import annotations

import random
from dataclasses import dataclass

__all__ = ["RandomMover", "RandomMoverParams"]


@dataclass(frozen=True, slots=True)
class RandomMoverParams:
    """Node parameters: ``publish_rate`` (Hz), ranges (m/s, rad/s), ``seed`` (None: random)."""

    publish_rate: float = 2.0
    max_linear: float = 0.5
    max_angular: float = 1.0
    seed: int | None = 0
    log_period: float = 1.0


class RandomMover:
    """Draws the random commands and decides when to log (see module doc)."""

    def __init__(self, params: RandomMoverParams = RandomMoverParams()) -> None:
        if params.publish_rate <= 0.0:
            raise ValueError(f"publish_rate must be > 0 Hz, got {params.publish_rate}")
        self.params = params
        self._rng = random.Random(params.seed)
        self._last_log: float | None = None

    @property
    def period(self) -> float:
        """Seconds between commands (0.5 s by default)."""
        return 1.0 / self.params.publish_rate

    def next_command(self) -> tuple[float, float]:
        """The next ``(linear.x m/s, angular.z rad/s)``, each uniform in its range."""
        p = self.params
        v = self._rng.uniform(-p.max_linear, p.max_linear)
        w = self._rng.uniform(-p.max_angular, p.max_angular)
        return v, w

    def pose_log(self, t: float, x: float, y: float, yaw: float) -> str | None:
        """The log line for a filtered pose received at ``t`` (s), or None when throttled."""
        # 1 ns of slack: float seconds such as 2.05 - 1.05 fall just short of 1.0.
        if self._last_log is not None and t - self._last_log < self.params.log_period - 1e-9:
            return None
        self._last_log = t
        return f"Odom: x={x:.2f}, y={y:.2f}, yaw={yaw:.2f}"
