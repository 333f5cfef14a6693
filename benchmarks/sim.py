"""Simulated seconds per wall-clock second of the ROSbot P-controller scenario.

The reference is real time: Gazebo runs the course's worlds at a real-time factor of 1, so
the printed ratio *is* the speed-up over the lecture's simulator. The scenario is the
``p_controller`` launch (empty world, goal (5, 5, pi/2), default noise, no cameras): 100 Hz
drive + slip, 25 Hz IMU, 20 Hz wheel odometry, 20 Hz EKF, 20 Hz controller. Two paths run
in the same process, alternately:

* ``headless``: the models in one fixed-step loop (posekit.robot.headless, no runtime);
* ``nodes``: ``run_robot_scenario("p_controller")`` -- five posekit nodes (world_simulation,
  wheel_odometry, ekf_node, p_controller) on the stepped sim-time executor and the in-process
  bus, as ``posekit launch p_controller`` runs it (no recorder, no /clock); ``nodes+rec``
  adds the odometry recorder that ``--plot`` uses.

``--profile`` prints where the node path spends its time (cProfile self time grouped by
package). ``--ekf`` times one 20 Hz EKF tick (25 Hz IMU + 20 Hz odometry fused, then
``to_msg``) of posekit's filter (Python floats over the packed covariance) against the same
filter written with 6x6 numpy products (the previous implementation) and with preallocated
numpy buffers (``out=``), all fed the same measurements.

``--lidar`` times one LiDAR scan (3000 beams ray-cast against the world's boxes, noise,
the LaserScan and its CDR bytes) against its period (100 ms at 10 Hz), in aruco_box_world
(3 boxes), in a 399-box grid and in husarion_world (505 wall faces); ``--lidar-only`` runs
just that.

``--depth`` times one OAK-D depth frame (z-buffer of the world's boxes, walls and ground at
1280x720, noise, range limits), the 32FC1 Image with its CDR bytes, the organised PointCloud2
and, apart, its CDR bytes (what a network transport adds; the in-process bus passes the
message itself), against the frame period (33.3 ms at 30 Hz), and one colour frame of the OAK camera
(boxes and walls) for comparison; ``--depth-only`` runs just that.

Run:  .venv/bin/python benchmarks/sim.py [--duration 60] [--repeats 5] [--profile] [--ekf]
      [--lidar | --lidar-only] [--depth | --depth-only]
"""

from __future__ import annotations

import argparse
import collections
import cProfile
import heapq
import math
import os
import platform
import pstats
import statistics
import time
from typing import Any

import numpy as np

from posekit.geometry import wrap_angle
from posekit.msgs.nav_msgs import Odometry
from posekit.robot.ekf import Ekf2D
from posekit.robot.headless import run_headless
from posekit.robot.scenarios import run_robot_scenario
from posekit.runtime.logging import LogRecord, add_sink, remove_sink

GOAL_RATIO = 200.0


def _headless(duration: float, seed: int) -> tuple[float, float, float | None]:
    """(simulated s per wall s, per CPU s of this process, goal time)."""
    t0, c0 = time.perf_counter(), time.process_time()
    res = run_headless(
        scenario="p_controller", duration=duration, seed=seed, goal=(5.0, 5.0, math.pi / 2)
    )
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    return duration / wall, duration / cpu, res.goal_reached_time


def _nodes(duration: float, seed: int, record: bool) -> tuple[float, float, float | None]:
    """Like _headless for run_robot_scenario (the times include building the nodes)."""
    t0, c0 = time.perf_counter(), time.process_time()
    res = run_robot_scenario("p_controller", seed=seed, until_sim_time=duration, record=record)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    reached_ns = res.node("p_controller").goal_reached_ns
    return duration / wall, duration / cpu, None if reached_ns is None else reached_ns / 1e9


class _NumpyEkf:
    """The planar EKF with 6x6 numpy arrays: ``prealloc`` False is the previous posekit
    implementation (``F @ P @ F.T``, row updates); True reuses buffers through ``out=``."""

    def __init__(self, prealloc: bool) -> None:
        from posekit.robot.params import DEFAULT_EKF

        self.prealloc = prealloc
        self.s = np.zeros(6)
        self.P = np.diag(np.asarray(DEFAULT_EKF.initial_covariance_diagonal))
        self.q = np.asarray(DEFAULT_EKF.process_noise_diagonal)
        self.f = np.eye(6)
        self.tmp, self.out, self.gain = np.empty((6, 6)), np.empty((6, 6)), np.empty(6)
        self.outer = np.empty((6, 6))
        self.t = 0.0
        self.queue: list[tuple[float, int, tuple[tuple[int, ...], tuple[float, ...]]]] = []
        self.seq = 0

    def add(self, t: float, idx: tuple[int, ...], z: tuple[float, ...]) -> None:
        heapq.heappush(self.queue, (t, self.seq, (idx, z)))
        self.seq += 1

    def predict(self, t: float) -> None:
        dt = t - self.t
        if dt <= 0.0:
            return
        s, f = self.s, self.f
        yaw, vx, vy = s[2], s[3], s[4]
        c, sn = math.cos(yaw), math.sin(yaw)
        s[0] += (vx * c - vy * sn) * dt
        s[1] += (vx * sn + vy * c) * dt
        s[2] = wrap_angle(yaw + s[5] * dt)
        f[0, 2], f[0, 3], f[0, 4] = (-vx * sn - vy * c) * dt, c * dt, -sn * dt
        f[1, 2], f[1, 3], f[1, 4] = (vx * c - vy * sn) * dt, sn * dt, c * dt
        f[2, 5] = dt
        if self.prealloc:
            np.matmul(f, self.P, out=self.tmp)
            np.matmul(self.tmp, f.T, out=self.P)
        else:
            self.P = f @ self.P @ f.T
        self.P.flat[::7] += self.q * dt
        self.t = t

    def update(self, idx: tuple[int, ...], z: tuple[float, ...], r: float) -> None:
        s, p = self.s, self.P
        for i, zi in zip(idx, z, strict=True):
            innovation = zi - s[i]
            if i == 2:
                innovation = wrap_angle(innovation)
            row = p[i]
            if self.prealloc:
                np.divide(row, row[i] + r, out=self.gain)
                s += self.gain * innovation
                np.multiply(self.gain[:, None], row, out=self.outer)
                p -= self.outer
            else:
                gain = row / (row[i] + r)
                s += gain * innovation
                p -= gain[:, None] * row
        s[2] = wrap_angle(s[2])

    def step(self, t: float) -> None:
        while self.queue and self.queue[0][0] <= t:
            tm, _, (idx, z) = heapq.heappop(self.queue)
            self.predict(tm)
            self.update(idx, z, 1e-3)
        self.predict(t)
        self.P = 0.5 * (self.P + self.P.T)

    def to_msg(self) -> None:
        full = np.zeros(36)
        full[[0, 1, 5, 6, 7, 11, 30, 31, 35]] = self.P[:3, :3].ravel()
        full2 = np.zeros(36)
        full2[[0, 1, 5, 6, 7, 11, 30, 31, 35]] = self.P[3:, 3:].ravel()
        Odometry()


def _ekf_tick_us(kind: str, ticks: int = 1200) -> float:
    """Microseconds of CPU per 20 Hz tick (best of 5 runs of ``ticks`` ticks)."""
    best = math.inf
    for _ in range(5):
        ekf: Any = Ekf2D() if kind == "posekit" else _NumpyEkf(prealloc=kind == "prealloc")
        t_imu, t_odom = 0.04, 0.05
        c0 = time.process_time()
        for k in range(1, ticks + 1):
            t = 0.05 * k
            while t_imu <= t + 1e-12:
                if kind == "posekit":
                    ekf.add_imu(t_imu, 0.01 * t_imu, 0.01, (1.9e-3, 2.0e-3))
                else:
                    ekf.add(t_imu, (2, 5), (0.01 * t_imu, 0.01))
                t_imu += 0.04
            if kind == "posekit":
                ekf.add_wheel_twist(t_odom, 0.3, 0.0, 0.01, (3.3e-5, 3.3e-5, 2.8e-3))
            else:
                ekf.add(t_odom, (3, 4, 5), (0.3, 0.0, 0.01))
            t_odom += 0.05
            ekf.step(t)
            ekf.to_msg()
        best = min(best, (time.process_time() - c0) / ticks * 1e6)
    return best


def _ekf_report() -> None:
    print("\nEKF tick (fuse 1-2 IMU + 1 odometry, predict, to_msg), CPU us, best of 5:")
    dense = _ekf_tick_us("dense")
    for kind, label in (
        ("dense", "numpy 6x6 products (previous posekit)"),
        ("prealloc", "numpy with preallocated out= buffers"),
        ("posekit", "posekit: Python floats, packed covariance"),
    ):
        us = dense if kind == "dense" else _ekf_tick_us(kind)
        print(f"  {label:42s} {us:7.1f} us   x{dense / us:4.1f}")


def _scan_cpu_ms(world: Any, repeats: int = 30) -> tuple[float, float]:
    """(median, best) CPU ms of one scan -> LaserScan -> CDR bytes, robot at the spawn."""
    from posekit.geometry import Rotation, Transform
    from posekit.msgs.cdr import to_cdr
    from posekit.robot.description import T_base_frame
    from posekit.robot.lidar import Lidar
    from posekit.worlds.obstacles import BoxObstacles, WallSegments

    lidar = Lidar(BoxObstacles.from_world(world), seed=1, walls=WallSegments.from_world(world))
    x, y, yaw = world.spawn
    T = Transform(Rotation.from_rpy(0.0, 0.0, yaw), (x, y, 0.0)) * T_base_frame("laser")
    times = []
    for k in range(repeats):
        c0 = time.process_time()
        to_cdr(lidar.to_msg(lidar.scan(T, k)))
        times.append((time.process_time() - c0) * 1e3)
    return statistics.median(times), min(times)


def _lidar_report() -> None:
    from posekit.robot.lidar import DEFAULT_LIDAR
    from posekit.worlds import World, load_world

    period_ms = 1e3 / DEFAULT_LIDAR.rate_hz
    grid = World.from_dict({
        "name": "grid400",
        "boxes": [
            {"name": f"b{i}_{j}", "model": "aruco_box", "pose": [1.5 * i, 1.5 * j, 0.25, 0, 0, 0]}
            for i in range(-10, 10) for j in range(-10, 10) if (i, j) != (0, 0)
        ],
    })
    print(f"\nLiDAR scan ({DEFAULT_LIDAR.samples} beams, noise, LaserScan, CDR), CPU ms vs its "
          f"{period_ms:.0f} ms period:")
    for label, world in (("aruco_box_world (3 boxes)", load_world("aruco_box_world")),
                         ("grid of 399 boxes", grid),
                         ("husarion_world (505 faces)", load_world("husarion_world"))):
        median, best = _scan_cpu_ms(world)
        print(f"  {label:28s} median {median:6.2f} ms  best {best:6.2f} ms  "
              f"= {100 * median / period_ms:5.1f} % of the period")


def _depth_cpu_ms(world: Any, yaw_offset: float, repeats: int = 20) -> dict[str, float]:
    """Median CPU ms: depth frame, Image + CDR, cloud, the cloud's CDR, a colour frame."""
    from posekit.geometry import Rotation, Transform
    from posekit.msgs.cdr import to_cdr
    from posekit.msgs.std_msgs import Header
    from posekit.robot.depth import DepthCamera, depth_cloud, depth_image_msg
    from posekit.robot.description import T_base_frame
    from posekit.vision.camera import OAK_RGB_CAMERA
    from posekit.vision.render import BoxRenderer
    from posekit.worlds.obstacles import WallSegments

    camera = DepthCamera(world, seed=1)
    colour = BoxRenderer(OAK_RGB_CAMERA, walls=WallSegments.from_world(world))
    boxes = [b.T_world_box for b in world.boxes]
    x, y, yaw = world.spawn
    T = (Transform(Rotation.from_rpy(0.0, 0.0, yaw + yaw_offset), (x, y, 0.0))
         * T_base_frame(camera.params.frame_id)).as_matrix()
    header = Header(frame_id=camera.params.frame_id)
    times: dict[str, list[float]] = {"frame": [], "image": [], "cloud": [], "cloud_cdr": [],
                                     "colour": []}
    for k in range(repeats):
        c0 = time.process_time()
        z = camera.frame(T, k)
        c1 = time.process_time()
        to_cdr(depth_image_msg(z, header))
        c2 = time.process_time()
        cloud = depth_cloud(z, camera.params, header)
        c3 = time.process_time()
        to_cdr(cloud)
        c4 = time.process_time()
        del cloud
        colour.render(T, boxes)
        c5 = time.process_time()
        for key, dt in zip(times, (c1 - c0, c2 - c1, c3 - c2, c4 - c3, c5 - c4), strict=True):
            times[key].append(dt * 1e3)
    return {key: statistics.median(v) for key, v in times.items()}


def _depth_report() -> None:
    from posekit.robot.depth import DEFAULT_DEPTH
    from posekit.worlds import load_world

    period_ms = 1e3 / DEFAULT_DEPTH.rate_hz
    print(f"\nOAK-D depth frame {DEFAULT_DEPTH.width}x{DEFAULT_DEPTH.height}, median CPU ms vs "
          f"its {period_ms:.1f} ms period (load {_load()}):")
    print(f"  {'world, view':34s} {'depth':>7s} {'+Image':>7s} {'+cloud':>7s} {'+CDR':>7s} "
          f"{'all':>7s} {'share':>6s} {'colour':>7s}")
    for label, name, yaw in (("empty_world", "empty_world", 0.0),
                             ("aruco_box_world, at the boxes", "aruco_box_world", 0.0),
                             ("husarion_world, spawn view", "husarion_world", 0.0),
                             ("husarion_world, facing the H", "husarion_world", 1.6)):
        t = _depth_cpu_ms(load_world(name), yaw)
        total = t["frame"] + t["image"] + t["cloud"] + t["cloud_cdr"]
        print(f"  {label:34s} {t['frame']:7.1f} {t['image']:7.1f} {t['cloud']:7.1f} "
              f"{t['cloud_cdr']:7.1f} {total:7.1f} {100 * total / period_ms:5.0f}% "
              f"{t['colour']:7.1f}")


def _load() -> str:
    try:
        return " ".join(f"{x:.1f}" for x in os.getloadavg())
    except OSError:  # not available on this platform
        return "n/a"


def _group(filename: str) -> str:
    path = filename.replace("\\", "/")
    for key, label in (
        ("posekit/robot/nodes/", "robot nodes (node glue)"),
        ("posekit/robot/", "robot models"),
        ("posekit/runtime/bus", "runtime bus (message copies)"),
        ("posekit/runtime/", "runtime executor/clock/entities"),
        ("posekit/msgs/", "message classes"),
        ("posekit/tf2", "tf2"),
        ("numpy", "numpy"),
    ):
        if key in path:
            return label
    return "other (builtins, dataclass inits, math)"


def _profile(duration: float, seed: int) -> None:
    profiler = cProfile.Profile()
    profiler.enable()
    run_robot_scenario("p_controller", seed=seed, until_sim_time=duration, record=False)
    profiler.disable()
    stats = pstats.Stats(profiler)
    groups: collections.Counter[str] = collections.Counter()
    raw = stats.stats  # type: ignore[attr-defined]
    for (filename, _line, _name), (_cc, _nc, tottime, _ct, _callers) in raw.items():
        groups[_group(filename)] += tottime
    total = sum(groups.values())
    print(f"\nnode path, cProfile self time by package ({duration:.0f} s simulated):")
    for label, seconds in groups.most_common():
        print(f"  {100 * seconds / total:5.1f} %  {label}")
    print("\ntop functions by self time:")
    stats.sort_stats("tottime").print_stats(12)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=60.0, help="simulated seconds per run")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--profile", action="store_true", help="profile the node path")
    parser.add_argument("--ekf", action="store_true", help="EKF tick: posekit vs numpy forms")
    parser.add_argument("--lidar", action="store_true", help="one LiDAR scan vs its period")
    parser.add_argument("--lidar-only", action="store_true", help="only the LiDAR figures")
    parser.add_argument("--depth", action="store_true", help="one depth frame vs its period")
    parser.add_argument("--depth-only", action="store_true", help="only the depth figures")
    args = parser.parse_args()
    if args.lidar_only or args.depth_only:
        if args.lidar_only:
            _lidar_report()
        if args.depth_only:
            _depth_report()
        return

    quiet: list[LogRecord] = []
    add_sink(quiet.append)
    from posekit.runtime.logging import _stderr_sink  # keep the benchmark output readable

    remove_sink(_stderr_sink)
    try:
        _headless(2.0, args.seed)  # warm-up (imports)
        _nodes(2.0, args.seed, True)
        names = ("headless", "nodes", "nodes+rec")
        ratios: dict[str, list[float]] = {name: [] for name in names}
        cpu_ratios: dict[str, list[float]] = {name: [] for name in names}
        goals: dict[str, float | None] = {}
        load0 = _load()
        for _ in range(args.repeats):
            for name in names:
                if name == "headless":
                    r, rc, goals[name] = _headless(args.duration, args.seed)
                else:
                    r, rc, goals[name] = _nodes(args.duration, args.seed, name == "nodes+rec")
                ratios[name].append(r)
                cpu_ratios[name].append(rc)
        print(f"python {platform.python_version()} on {platform.machine()}, "
              f"load average {load0} -> {_load()}")
        print(
            f"p_controller scenario, {args.duration:.0f} s simulated x {args.repeats} runs "
            "(simulated s / wall s, i.e. times real time; cpu = simulated s / CPU s of this "
            "process, what an unshared core would give)"
        )
        for name in names:
            median = statistics.median(ratios[name])
            print(
                f"  {name:10s} median {median:6.0f}x  best {max(ratios[name]):6.0f}x  "
                f"cpu median {statistics.median(cpu_ratios[name]):6.0f}x  "
                f"(goal reached at t = {goals[name]} s)"
            )
        paired = [n / h for n, h in zip(ratios["nodes"], ratios["headless"], strict=True)]
        print(f"  nodes / headless speed (paired runs, median): {statistics.median(paired):.2f}")
        for name in ("headless", "nodes"):
            met = statistics.median(ratios[name]) >= GOAL_RATIO
            met_cpu = statistics.median(cpu_ratios[name]) >= GOAL_RATIO
            print(
                f"goal >= {GOAL_RATIO:.0f}x ({name}): wall {'met' if met else 'NOT met'}, "
                f"cpu {'met' if met_cpu else 'NOT met'}"
            )
        if args.profile:
            _profile(args.duration, args.seed)
        if args.ekf:
            _ekf_report()
        if args.lidar:
            _lidar_report()
        if args.depth:
            _depth_report()
    finally:
        remove_sink(quiet.append)
        add_sink(_stderr_sink)


if __name__ == "__main__":
    main()
