"""Vision benchmark: renderer ms/frame, detector cost against raw OpenCV on the same frames,
and the speed of the ``dynamic_detector_listener`` scenario against real time.

Run:  .venv/bin/python benchmarks/vision.py            (timings, ~1 min)
      .venv/bin/python benchmarks/vision.py --accuracy (also the accuracy table of docs/vision.md)

Reference for the detector: the course's per-frame work done with OpenCV directly, i.e.
``ArucoDetector.detectMarkers`` + ``solvePnP(..., SOLVEPNP_IPPE_SQUARE)`` per marker, on the
very same frames. posekit's ``ArucoMarkerDetector.detect`` adds input validation, both IPPE
solutions with reprojection errors (``solvePnPGeneric``), quaternions and result objects.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import math
import sys
import time
from collections.abc import Callable

import cv2
import numpy as np

from posekit.geometry import Transform
from posekit.vision.camera import OAK_RGB_CAMERA, OVERHEAD_CAMERA, T_CAMERA_FRAME_OPTICAL
from posekit.vision.detector import ArucoMarkerDetector
from posekit.vision.evaluation import accuracy_grid
from posekit.vision.render import BoxRenderer

BOX_WORLD = [Transform.from_xyz_rpy((2.25, 0.0, 0.25), (0.0, 0.0, 0.0)).as_matrix(),

             Transform.from_xyz_rpy((2.25, -0.5, 0.25), (0.0, 0.0, -1.57)).as_matrix(),
             Transform.from_xyz_rpy((2.25, 0.5, 0.25), (0.0, 0.0, 1.57)).as_matrix()]


def robot_camera_poses(n: int) -> list[np.ndarray]:
    """Optical-frame poses of the OAK camera along a robot path approaching the boxes while
    turning left and right (base_link -> optical from the spec)."""
    T_base_camera = Transform.from_xyz_rpy((-0.0241, 0.0, 0.1875), (0.0, 0.0, 0.0)).as_matrix()
    T_base_optical = T_base_camera @ T_CAMERA_FRAME_OPTICAL
    poses = []
    for k in range(n):
        s = k / max(n - 1, 1)
        T_world_base = Transform.from_xyz_rpy((1.2 * s, 0.3 * math.sin(4 * s), 0.0),
                                              (0.0, 0.0, 0.35 * math.sin(6 * s))).as_matrix()
        poses.append(T_world_base @ T_base_optical)
    return poses


def per_call_min(fns: list[Callable[[int], object]], n_items: int, repeats: int
                 ) -> list[float]:
    """Sum over items of the minimum (over ``repeats``) wall time of each ``fn(item)``.

    The functions are called alternately item by item, so a burst of load from other
    processes on the machine hits them alike, and the per-item minimum discards it.
    """
    best = [[math.inf] * n_items for _ in fns]
    for _ in range(repeats):
        for i in range(n_items):
            for k, fn in enumerate(fns):
                t0 = time.perf_counter()
                fn(i)
                dt = time.perf_counter() - t0
                if dt < best[k][i]:
                    best[k][i] = dt
    return [sum(b) for b in best]


def best_of(fn: Callable[[], object], repeats: int) -> float:
    """Minimum wall time of ``fn`` over ``repeats`` runs, seconds."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def bench_renderer(n_frames: int, repeats: int) -> None:
    print(f"## Renderer (ms per frame; per-frame minimum of {repeats} runs)")
    print("| scene | camera | ms/frame | frames/s |")
    print("|---|---|---|---|")
    cases = []
    oak = BoxRenderer(OAK_RGB_CAMERA)
    oak_poses = robot_camera_poses(n_frames)
    cases.append(("aruco_box_world, robot driving", "1280x720", oak, oak_poses, BOX_WORLD))
    oak_ss = BoxRenderer(OAK_RGB_CAMERA, supersample=2)
    cases.append(("same, supersample=2", "1280x720", oak_ss, oak_poses, BOX_WORLD))
    oak_noise = BoxRenderer(OAK_RGB_CAMERA, noise_sigma=2.0, seed=0)
    cases.append(("same, noise_sigma=2", "1280x720", oak_noise, oak_poses, BOX_WORLD))
    close = [Transform.from_xyz_rpy((0.0, 0.0, 0.25), (0.0, 0.0, 0.0)).as_matrix()]
    from posekit.vision.evaluation import look_at

    close_poses = [look_at((-0.55 - 0.1 * k / n_frames, 0.2, 0.4), (0.0, 0.0, 0.25))
                   for k in range(n_frames)]
    cases.append(("one box filling the view (0.3 m)", "1280x720", oak, close_poses, close))
    over = BoxRenderer(OVERHEAD_CAMERA)
    T_world_camera = Transform.from_xyz_rpy((2.0, 2.0, 2.0), (0.0, 1.5708, 0.0)).as_matrix()
    T_over = T_world_camera @ T_CAMERA_FRAME_OPTICAL
    cases.append(("aruco_box_camera_world, overhead", "640x480", over, [T_over] * n_frames,
                  [Transform.from_xyz_rpy((2.0, 2.0, 0.25), (0.0, 0.0, 0.0)).as_matrix()]))
    for name, size, renderer, poses, boxes in cases:
        renderer.render(poses[0], boxes)  # warm caches
        (t,) = per_call_min(
            [lambda i, r=renderer, p=poses, b=boxes: r.render(p[i], b)], len(poses), repeats
        )
        ms = 1e3 * t / len(poses)
        print(f"| {name} | {size} | {ms:.2f} | {1e3 / ms:.0f} |")
    print()


def bench_detector(n_frames: int, repeats: int) -> float:
    renderer = BoxRenderer(OAK_RGB_CAMERA, noise_sigma=2.0, seed=0)
    frames = [renderer.render(T, BOX_WORLD) for T in robot_camera_poses(n_frames)]
    K, dist = OAK_RGB_CAMERA.K, OAK_RGB_CAMERA.dist_coeffs
    ours = ArucoMarkerDetector(K, dist, marker_size=0.194)
    raw_detector = cv2.aruco.ArucoDetector(
        cv2.aruco.getPredefinedDictionary(cv2.aruco.DICT_5X5_250), cv2.aruco.DetectorParameters()
    )
    h = 0.194 / 2.0
    obj = np.array([[-h, h, 0.0], [h, h, 0.0], [h, -h, 0.0], [-h, -h, 0.0]], dtype=np.float32)

    def raw_one(i: int) -> int:
        corners, ids, _ = raw_detector.detectMarkers(frames[i])
        n = 0
        if ids is not None:
            for c in corners:
                ok, _rvec, _tvec = cv2.solvePnP(obj, c.reshape(-1, 2), K, dist,
                                                flags=cv2.SOLVEPNP_IPPE_SQUARE)
                n += int(ok)
        return n

    def ours_one(i: int) -> int:
        return len(ours.detect(frames[i]))

    n_raw = sum(raw_one(i) for i in range(len(frames)))
    n_ours = sum(ours_one(i) for i in range(len(frames)))
    t_raw, t_ours = per_call_min([raw_one, ours_one], len(frames), repeats)
    raw_ms = 1e3 * t_raw / len(frames)
    ours_ms = 1e3 * t_ours / len(frames)
    ratio = ours_ms / raw_ms
    print(f"## Detector on {len(frames)} rendered 1280x720 frames "
          f"({n_ours / len(frames):.1f} markers/frame)")
    print("| pipeline | ms/frame | ratio vs raw |")
    print("|---|---|---|")
    print(f"| raw OpenCV: detectMarkers + solvePnP(IPPE_SQUARE) | {raw_ms:.2f} | 1.00 |")
    print(f"| posekit ArucoMarkerDetector.detect (both IPPE solutions, quaternions) "
          f"| {ours_ms:.2f} | {ratio:.3f} |")
    print(f"markers found: raw {n_raw}, posekit {n_ours}; OpenCV threads "
          f"{cv2.getNumThreads()}")
    # the per-marker part alone, where posekit does extra work (second solution, errors)
    c = frames_corners[0] if (frames_corners := [
        cs[0] for cs in (raw_detector.detectMarkers(f)[0] for f in frames) if len(cs)
    ]) else None
    if c is not None:
        pts = c.reshape(4, 2)
        n = 2000
        t_pnp = min(best_of(lambda: [cv2.solvePnP(obj, pts, K, dist,
                                                  flags=cv2.SOLVEPNP_IPPE_SQUARE)
                                     for _ in range(n)], 1) for _ in range(repeats))
        t_est = min(best_of(lambda: [ours.estimate_pose(pts, 0.194) for _ in range(n)], 1)
                    for _ in range(repeats))
        print(f"per marker: raw solvePnP {1e6 * t_pnp / n:.0f} us, posekit estimate_pose "
              f"{1e6 * t_est / n:.0f} us (both solutions, errors, quaternions)")
    print()
    if n_raw != n_ours:
        print("ERROR: posekit and raw OpenCV found different numbers of poses", file=sys.stderr)
        raise SystemExit(1)
    return ratio


def bench_pipeline(seconds: float, repeats: int) -> float:
    """Simulated seconds per wall second of ``dynamic_detector_listener`` (camera 30 Hz).

    Reference 1: real time (1.0). Reference 2: the bare work the pipeline cannot avoid on
    the very frames it saw, rendering each 1280x720 frame from the recorded camera pose
    plus raw OpenCV detectMarkers + solvePnP on it, one pass after each pipeline run.
    """
    import posekit.vision.scenarios  # noqa: F401 - registers the scenarios
    from posekit.launch.scenarios import run_scenario

    best_wall, best_cpu, sim = math.inf, math.inf, 0.0
    frames = 0
    poses: list[np.ndarray] = []

    def record_poses(run: object) -> None:
        cam = run.node("oak_camera")  # type: ignore[attr-defined]
        render_at = cam.render_at

        def recording(t_ns: int) -> np.ndarray:
            img = render_at(t_ns)
            poses.append(cam.last_T_world_optical)
            return img

        cam.render_at = recording

    renderer = BoxRenderer(OAK_RGB_CAMERA)
    raw_detector = cv2.aruco.ArucoDetector(
        cv2.aruco.getPredefinedDictionary(cv2.aruco.DICT_5X5_250), cv2.aruco.DetectorParameters()
    )
    K, dist = OAK_RGB_CAMERA.K, OAK_RGB_CAMERA.dist_coeffs
    h = 0.1
    obj = np.array([[-h, h, 0.0], [h, h, 0.0], [h, -h, 0.0], [-h, -h, 0.0]], dtype=np.float32)

    def bare() -> None:
        for T in poses:
            img = renderer.render(T, BOX_WORLD)
            corners, _ids, _ = raw_detector.detectMarkers(img)
            for c in corners:
                cv2.solvePnP(obj, c.reshape(-1, 2), K, dist, flags=cv2.SOLVEPNP_IPPE_SQUARE)

    # Pipeline run and bare pass alternate, so load bursts from other processes hit both;
    # the best of each is kept. The nodes' log lines are kept off the output.
    t_bare, cpu_bare = math.inf, math.inf
    with contextlib.redirect_stderr(io.StringIO()):
        for _ in range(repeats):
            poses.clear()
            w0, c0 = time.perf_counter(), time.process_time()
            result = run_scenario("dynamic_detector_listener", until_sim_time=seconds,
                                  on_start=[record_poses])
            wall, cpu = time.perf_counter() - w0, time.process_time() - c0
            sim = result.sim_time
            frames = result.node("dynamic_detector").frames_processed
            best_wall, best_cpu = min(best_wall, wall), min(best_cpu, cpu)
            w0, c0 = time.perf_counter(), time.process_time()
            bare()
            t_bare = min(t_bare, time.perf_counter() - w0)
            cpu_bare = min(cpu_bare, time.process_time() - c0)
    bare_ms = 1e3 * t_bare / max(len(poses), 1)
    per_frame_ms = 1e3 * best_wall / max(frames, 1)
    speed = sim / best_wall
    print(f"## dynamic_detector_listener, {sim:.0f} simulated s, camera 30 Hz "
          f"({frames} frames), best of {repeats}")
    print("| measure | value | ratio |")
    print("|---|---|---|")
    print(f"| simulated s per wall s | {speed:.2f} | {speed:.2f}x real time (goal >= 1) |")
    print(f"| simulated s per CPU s (this process, all threads) | {sim / best_cpu:.2f} | |")
    print(f"| wall ms per camera frame, whole pipeline (robot, EKF, camera, detector, tf2, "
          f"listener) | {per_frame_ms:.1f} | {per_frame_ms / bare_ms:.2f}x bare |")
    print(f"| bare: render + raw detectMarkers + solvePnP on the same {len(poses)} frames, "
          f"wall ms per frame | {bare_ms:.1f} | 1.00 |")
    cpu_ms, cpu_bare_ms = (1e3 * c / max(frames, 1) for c in (best_cpu, cpu_bare))
    print(f"| CPU ms per camera frame, whole pipeline | {cpu_ms:.1f} | "
          f"{cpu_ms / cpu_bare_ms:.2f}x bare |")
    print(f"| CPU ms per frame, bare | {cpu_bare_ms:.1f} | 1.00 |")
    print()
    return speed


def print_accuracy(trials: int, refine: bool) -> None:
    distances = (0.5, 1.0, 1.5, 2.0, 2.5, 3.0)
    angles = (0.0, 15.0, 30.0, 45.0, 60.0)
    cells = accuracy_grid(distances, angles, trials=trials, jitter=0.02, refine_subpixel=refine)
    print(f"## Accuracy, refine_subpixel={refine}, {trials} frames per cell "
          "(camera jittered +-2 cm)")
    print("| range (m) | angle (deg) | detected | max pos err (mm) | max pos err (% range) "
          "| mean pos err (mm) | max rot err (deg) | max rot err, better of 2 (deg) "
          "| mean ambiguity |")
    print("|---|---|---|---|---|---|---|---|---|")
    for c in cells:
        print(f"| {c.distance:.1f} | {c.angle_deg:.0f} | {c.detection_rate:.0%} "
              f"| {1e3 * c.max_position_error:.1f} "
              f"| {100 * c.max_position_error / c.distance:.2f} "
              f"| {1e3 * c.mean_position_error:.1f} | {c.max_rotation_error_deg:.1f} "
              f"| {c.max_rotation_error_best_of_two_deg:.1f} | {c.mean_ambiguity_ratio:.2f} |")
    print()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=60)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--accuracy", action="store_true", help="print the accuracy tables")
    parser.add_argument("--trials", type=int, default=20)
    parser.add_argument("--pipeline-seconds", type=float, default=10.0,
                        help="simulated seconds of dynamic_detector_listener (0 = skip)")
    parser.add_argument("--threads", type=int, default=None,
                        help="cv2.setNumThreads (default: OpenCV's choice)")
    args = parser.parse_args()
    if args.threads is not None:
        cv2.setNumThreads(args.threads)
    print(f"OpenCV {cv2.__version__}, numpy {np.__version__}\n")
    bench_renderer(args.frames, args.repeats)
    ratio = bench_detector(args.frames, args.repeats)
    print(f"detector overhead ratio {ratio:.3f} (goal <= 1.10)")
    if args.pipeline_seconds > 0:
        print()
        speed = bench_pipeline(args.pipeline_seconds, repeats=3)
        print(f"dynamic_detector_listener speed {speed:.2f}x real time (goal >= 1.00)")
    if args.accuracy:
        print()
        print_accuracy(args.trials, refine=False)
        print_accuracy(args.trials, refine=True)


if __name__ == "__main__":
    main()
