"""posekit.geometry vs scipy (and transforms3d where it has the operation), in one run.

Prints one table of times and speed-up ratios (reference time / posekit time; > 1 means
posekit is faster). Single items use the public API end to end (construction included where
the operation starts from a quaternion); batches use arrays of 1e5 and 1e6 rotations.

Run:  .venv/bin/python benchmarks/geometry.py            (add --quick for a short smoke run)
      .venv/bin/python benchmarks/geometry.py --quat-matrix   (batch quat->matrix alone: CPU
      time, rounds alternating posekit / scipy, best of 7; for a loaded machine)
On machines that set OPENBLAS_CORETYPE/OPENBLAS_L2_SIZE, unset both for this command only.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import timeit
from collections.abc import Callable

import numpy as np
import transforms3d.euler as t3e
import transforms3d.quaternions as t3q
from scipy.spatial.transform import Rotation as SciRot

from posekit.geometry import Rotation
from posekit.geometry import scalar as ps


def best_time(fn: Callable[[], object], min_total: float = 0.2, repeat: int = 5) -> float:
    """Best per-call seconds over ``repeat`` rounds of enough calls to take ``min_total`` s."""
    number = 1
    while True:
        t = timeit.timeit(fn, number=number)
        if t >= min_total / 5 or number >= 1 << 20:
            break
        number *= 4
    number = max(1, int(number * (min_total / 5) / max(t, 1e-9)))
    return min(timeit.repeat(fn, number=number, repeat=repeat)) / number


def fmt_time(s: float) -> str:
    if s < 1e-3:
        return f"{s * 1e6:8.2f} us"
    return f"{s * 1e3:8.2f} ms"


def import_time(stmt: str, runs: int) -> tuple[float, float]:
    """(min, median) seconds that a fresh interpreter spends running ``stmt``."""

    def run(code: str) -> float:
        out = subprocess.run(
            [sys.executable, "-c", f"import time; t=time.perf_counter(); {code}; "
             "print(time.perf_counter()-t)"],
            capture_output=True, text=True, check=True,
        )
        return float(out.stdout)

    times = [run(stmt) for _ in range(runs)]
    return min(times), statistics.median(times)


def process_time(stmt: str, runs: int) -> tuple[float, float]:
    """(min, median) wall seconds of ``python -c stmt`` as a whole process (with start-up)."""
    times = []
    for _ in range(runs):
        t = timeit.default_timer()
        subprocess.run([sys.executable, "-c", stmt], check=True)
        times.append(timeit.default_timer() - t)
    return min(times), statistics.median(times)


Case = tuple[str, Callable[[], object], Callable[[], object]]


def batch_cases(n: int) -> list[Case]:
    """(name, posekit call, scipy call) for batches of ``n`` rotations."""
    qa = SciRot.random(n, rng=2).as_quat()
    qb = SciRot.random(n, rng=3).as_quat()
    ea = SciRot.from_quat(qa).as_euler("xyz")
    va = np.random.default_rng(4).normal(size=(n, 3))
    ma = SciRot.from_quat(qa).as_matrix()
    pa, pb = Rotation.from_quat(qa), Rotation.from_quat(qb)
    sa, sb = SciRot.from_quat(qa), SciRot.from_quat(qb)
    tag = f"{n:.0e}".replace("+0", "")
    return [
        (f"batch {tag} quat->euler", lambda: Rotation.from_quat(qa).as_euler("xyz"),
         lambda: SciRot.from_quat(qa).as_euler("xyz")),
        (f"batch {tag} euler->quat", lambda: Rotation.from_euler("xyz", ea).as_quat(),
         lambda: SciRot.from_euler("xyz", ea).as_quat()),
        (f"batch {tag} compose", lambda: pa * pb, lambda: sa * sb),
        (f"batch {tag} apply", lambda: pa.apply(va), lambda: sa.apply(va)),
        (f"batch {tag} quat->matrix", lambda: Rotation.from_quat(qa).as_matrix(),
         lambda: SciRot.from_quat(qa).as_matrix()),
        (f"batch {tag} matrix->quat", lambda: Rotation.from_matrix(ma).as_quat(),
         lambda: SciRot.from_matrix(ma).as_quat()),
    ]


def quat_matrix_cpu() -> None:
    """Batch ``from_quat(q).as_matrix()`` in CPU time of this process, posekit and scipy
    rounds alternating, best of 7 (stable where other jobs share the machine)."""
    import time

    def cpu_ms(fn: Callable[[], object], number: int) -> float:
        start = time.process_time_ns()
        for _ in range(number):
            fn()
        return (time.process_time_ns() - start) / number / 1e6

    print("batch quat->matrix, construction included (CPU ms, best of 7 alternating rounds)")
    for n, number in ((100_000, 20), (1_000_000, 3)):
        q = SciRot.random(n, rng=2).as_quat()
        ours = ref = float("inf")
        for _ in range(7):
            ours = min(ours, cpu_ms(lambda q=q: Rotation.from_quat(q).as_matrix(), number))
            ref = min(ref, cpu_ms(lambda q=q: SciRot.from_quat(q).as_matrix(), number))
        print(f"{n:>9,d} rows: posekit {ours:8.2f} ms  scipy {ref:8.2f} ms  "
              f"scipy/posekit {ref / ours:5.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="short run (smaller batches)")
    parser.add_argument("--quat-matrix", action="store_true",
                        help="only batch quat->matrix against scipy, in CPU time")
    args = parser.parse_args()
    if args.quat_matrix:
        quat_matrix_cpu()
        return
    min_total = 0.05 if args.quick else 0.3
    sizes = [10_000] if args.quick else [100_000, 1_000_000]

    singles: list[tuple[str, float, float, float, float]] = []
    rows: list[tuple[str, float, float]] = []

    # ---------------------------------------------------------------- single items
    rng = np.random.default_rng(0)
    q_np = SciRot.random(rng=rng).as_quat()
    q_list = q_np.tolist()
    q_wxyz = np.array([q_np[3], q_np[0], q_np[1], q_np[2]])
    q_tuple = tuple(q_list)
    e_list = [0.1, 0.2, 0.3]
    v_list = [1.0, 2.0, 3.0]
    v_np = np.array(v_list)
    p1, p2 = Rotation.from_quat(q_list), Rotation.random(rng=1)
    s1, s2 = SciRot.from_quat(q_np), SciRot.from_quat(p2.as_quat())
    q2_wxyz = p2.as_quat(scalar_first=True)
    q2_tuple = p2.as_quat_tuple()

    def single(name: str, obj: Callable[[], object], fn: Callable[[], object],
               ref: Callable[[], object], t3d: Callable[[], object]) -> None:
        singles.append((name, best_time(obj, min_total), best_time(fn, min_total),
                        best_time(ref, min_total), best_time(t3d, min_total)))

    single("quat->euler 'xyz'",
           lambda: Rotation.from_quat(q_list).as_euler("xyz"),
           lambda: ps.euler_from_quat("xyz", q_tuple),
           lambda: SciRot.from_quat(q_list).as_euler("xyz"),
           lambda: t3e.quat2euler(q_wxyz, "sxyz"))
    single("euler->quat 'xyz'",
           lambda: Rotation.from_euler("xyz", e_list).as_quat(),
           lambda: ps.quat_from_euler("xyz", 0.1, 0.2, 0.3),
           lambda: SciRot.from_euler("xyz", e_list).as_quat(),
           lambda: t3e.euler2quat(0.1, 0.2, 0.3, "sxyz"))
    single("compose r1*r2", lambda: p1 * p2,
           lambda: ps.quat_multiply(q_tuple, q2_tuple),
           lambda: s1 * s2,
           lambda: t3q.qmult(q_wxyz, q2_wxyz))
    single("apply (one vector)", lambda: p1.apply(v_list),
           lambda: ps.rotate_vector(q_tuple, v_list),
           lambda: s1.apply(v_list),
           lambda: t3q.rotate_vector(v_np, q_wxyz))
    single("quat->matrix",
           lambda: Rotation.from_quat(q_list).as_matrix(),
           lambda: ps.quat_to_matrix(q_tuple),
           lambda: SciRot.from_quat(q_list).as_matrix(),
           lambda: t3q.quat2mat(q_wxyz))

    # ---------------------------------------------------------------- batches
    for n in sizes:
        batch_rows = batch_cases(n)
        for name, ours, ref in batch_rows:
            rows.append((name, best_time(ours, min_total, repeat=3),
                         best_time(ref, min_total, repeat=3)))

    # ---------------------------------------------------------------- report
    print(f"python {sys.version.split()[0]}, numpy {np.__version__}, "
          f"scipy {__import__('scipy').__version__}, transforms3d {t3q.__name__.split('.')[0]} "
          f"{__import__('transforms3d').__version__}")
    print()
    print("Single items (one rotation; inputs are Python lists/tuples, outputs as each API gives)")
    print("  Rotation = posekit object API (vs scipy Rotation); fn = posekit.geometry.scalar "
          "functions on tuples (vs transforms3d functions)")
    header = (f"{'operation':20s} {'Rotation':>10s} {'scipy':>10s} {'x scipy':>8s} | "
              f"{'fn':>10s} {'t3d':>10s} {'x t3d':>6s} {'t3d/Rotation':>12s}")
    print(header)
    print("-" * len(header))
    for name, obj, fn, ref, t3d in singles:
        print(f"{name:20s} {fmt_time(obj):>10s} {fmt_time(ref):>10s} {ref / obj:8.2f} | "
              f"{fmt_time(fn):>10s} {fmt_time(t3d):>10s} {t3d / fn:6.2f} {t3d / obj:12.2f}")
    print()
    print("Batches (posekit Rotation vs scipy Rotation; construction from arrays included)")
    header = f"{'operation':30s} {'posekit':>11s} {'scipy':>11s} {'x scipy':>8s}"
    print(header)
    print("-" * len(header))
    for name, ours, ref in rows:
        print(f"{name:30s} {fmt_time(ours):>11s} {fmt_time(ref):>11s} {ref / ours:8.2f}")

    runs = 3 if args.quick else 9
    ours_imp = import_time("import posekit.geometry", runs)
    ours_use = import_time(
        "import posekit.geometry as g; g.Rotation.from_quat([0, 0, 0, 1]).as_quat()", runs
    )
    np_imp = import_time("import numpy", runs)
    sci_imp = import_time("from scipy.spatial.transform import Rotation", runs)
    proc = process_time("import posekit.geometry", runs)
    bare = process_time("pass", runs)
    print()
    print(f"{'import cost (min / median of ' + str(runs) + ' fresh interpreters)':50s} "
          f"{'min':>8s} {'median':>8s}")
    for label, (lo, med) in [
        ("python -c 'import posekit.geometry' (process)", proc),
        ("python -c 'pass' (interpreter start alone)", bare),
        ("import posekit.geometry (in-process)", ours_imp),
        ("import + first array result (loads numpy)", ours_use),
        ("import numpy", np_imp),
        ("from scipy.spatial.transform import Rotation", sci_imp),
    ]:
        print(f"{label:50s} {lo * 1e3:6.1f}ms {med * 1e3:6.1f}ms")


if __name__ == "__main__":
    main()
