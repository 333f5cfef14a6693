"""The ROSbot's 2-D LiDAR (Slamtec RPLIDAR S2) simulated by ray casting the world's boxes.

Defaults are those of Husarion's ``slamtec_rplidar`` description for model ``s2`` (the
ROSbot's component LDR02), which configures Gazebo's ``gpu_lidar``: scan frame ``laser``,
topic ``scan``, **10 Hz**, **3000 samples** from -pi to pi, range **0.05-30 m**, Gaussian
noise sigma **0.015 m** (mean 0). Gazebo spaces the samples ``(max - min) / (samples - 1)``
apart: 2 pi / 2999 = 2.0951e-3 rad = 0.120 deg, the S2 datasheet's 0.12 deg angular
resolution at 10 Hz. The description's range resolution (0.013 m) is not applied: posekit
reports continuous ranges.

A scan is taken at one instant from the robot's true pose (as Gazebo's gpu_lidar renders
all beams at once), so ``time_increment`` is 0; ``scan_time`` is the period. Every box and
wall of the world is seen (the course's boxes are visual-only in Gazebo and gpu_lidar renders
visuals). Beam ``i`` points at ``angle_min + i * angle_increment`` about the ``laser``
frame's +z; the description turns ``laser`` by pi, so angle 0 looks backwards from the
robot. Returns as REP 117 and Gazebo report them: ``+inf`` when the beam hits nothing
within ``range_max``, ``-inf`` when the (noisy) range is below ``range_min``. Noise is added
to every hit, then the limits are applied.

Determinism: the noise of scan ``k`` (the scan time on the sensor's grid) is drawn from a
generator seeded with ``(seed, k)``, so a seed gives the same scan at the same time whether
or not earlier scans were computed (the node skips scans nobody subscribes to).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from posekit.geometry import Transform
from posekit.msgs.sensor_msgs import LaserScan
from posekit.worlds.obstacles import BoxObstacles, WallSegments, cast_rays

__all__ = ["DEFAULT_LIDAR", "Lidar", "LidarParams"]

_FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class LidarParams:
    """A planar scanner: ``frame_id``, ``rate_hz`` (Hz), ``samples`` beams from ``angle_min``
    to ``angle_max`` (rad, both included), ``range_min``/``range_max`` (m), Gaussian
    ``noise_stddev`` (m)."""

    frame_id: str = "laser"
    rate_hz: float = 10.0
    samples: int = 3000
    angle_min: float = -math.pi
    angle_max: float = math.pi
    range_min: float = 0.05
    range_max: float = 30.0
    noise_stddev: float = 0.015

    def __post_init__(self) -> None:
        if self.samples < 2:
            raise ValueError(f"lidar samples must be >= 2, got {self.samples}")
        if not self.angle_min < self.angle_max:
            raise ValueError(f"need angle_min < angle_max, got {self.angle_min}, {self.angle_max}")
        if not 0.0 <= self.range_min < self.range_max:
            raise ValueError(f"need 0 <= range_min < range_max, got {self.range_min}, "
                             f"{self.range_max}")
        if not (self.rate_hz > 0.0 and self.noise_stddev >= 0.0):
            raise ValueError("lidar rate_hz must be > 0 and noise_stddev >= 0")

    @property
    def angle_increment(self) -> float:
        """Angle between beams (rad): ``(angle_max - angle_min) / (samples - 1)``."""
        return (self.angle_max - self.angle_min) / (self.samples - 1)

    @property
    def angles(self) -> _FloatArray:
        """``(samples,)`` beam angles (rad) in the scan frame."""
        return self.angle_min + self.angle_increment * np.arange(self.samples, dtype=np.float64)


#: The ROSbot's Slamtec S2 as Husarion's description configures it (module doc).
DEFAULT_LIDAR = LidarParams()


class Lidar:
    """Scans of ``obstacles`` and ``walls`` (see the module doc); ``seed`` fixes the noise."""

    def __init__(
        self,
        obstacles: BoxObstacles,
        params: LidarParams = DEFAULT_LIDAR,
        *,
        seed: int = 0,
        walls: WallSegments | None = None,
    ) -> None:
        self.params = params
        self.obstacles = obstacles
        self.walls = walls
        self.seed = int(seed)
        angles = params.angles
        #: Unit beam directions in the scan frame, (samples, 3).
        self.directions_laser = np.stack(
            [np.cos(angles), np.sin(angles), np.zeros_like(angles)], axis=1
        )

    def true_ranges(self, T_world_laser: Transform) -> _FloatArray:
        """Noise-free distances (m, float64; ``inf`` for no hit) from the scan frame's pose."""
        m = T_world_laser.as_matrix()
        directions = self.directions_laser @ m[:3, :3].T
        return cast_rays(
            m[:3, 3], directions, self.obstacles, self.params.range_max, walls=self.walls
        )

    def scan(self, T_world_laser: Transform, scan_index: int) -> npt.NDArray[np.float32]:
        """The reported ranges (float32, REP 117 infinities) of scan number ``scan_index``."""
        p = self.params
        r = self.true_ranges(T_world_laser)
        hit = np.isfinite(r)
        if p.noise_stddev > 0.0:
            rng = np.random.default_rng((self.seed, int(scan_index)))
            r = r + np.where(hit, p.noise_stddev * rng.standard_normal(r.shape[0]), 0.0)
        r[hit & (r > p.range_max)] = np.inf
        r[hit & (r < p.range_min)] = -np.inf
        r[~hit] = np.inf
        return r.astype(np.float32)

    def to_msg(self, ranges: npt.NDArray[np.float32]) -> LaserScan:
        """A LaserScan of ``ranges`` in the scan frame (the caller sets ``header.stamp``).

        ``intensities`` has one 0.0 per beam: Gazebo reports the visuals' laser_retro, which
        the course's models leave at 0.
        """
        p = self.params
        msg = LaserScan()
        msg.header.frame_id = p.frame_id
        msg.angle_min = p.angle_min
        msg.angle_max = p.angle_max
        msg.angle_increment = p.angle_increment
        msg.time_increment = 0.0
        msg.scan_time = 1.0 / p.rate_hz
        msg.range_min = p.range_min
        msg.range_max = p.range_max
        msg.ranges = ranges
        msg.intensities = np.zeros(ranges.shape[0], dtype=np.float32)
        return msg
