"""``posekit plot odometry``: ground truth vs wheel vs filtered odometry of a run, as a PNG.

matplotlib is an optional dependency, imported only when a plot is drawn (Agg backend, no
display needed). Input is an :class:`~posekit.robot.nodes.recorder.OdometryRecording`
(recorded by ``run_scenario(..., record=True)`` or loaded from its ``.npz``).

The figure has three panels: the x-y paths in odom (start and end marked), the position
error of each estimate against ground truth over time, and the yaw error over time.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from posekit.robot.nodes.recorder import OdometryRecording

__all__ = ["PlotError", "errors_against_truth", "plot_odometry", "plot_odometry_file"]

_FloatArray = npt.NDArray[np.float64]

_STYLE = {
    "ground_truth": ("ground truth", "black", "-"),
    "wheels": ("odometry/wheels", "tab:orange", "--"),
    "filtered": ("odometry/filtered", "tab:blue", "-"),
}


class PlotError(RuntimeError):
    """matplotlib is missing or the recording cannot be plotted (the message says which)."""


def errors_against_truth(
    recording: OdometryRecording, name: str, reference: str = "ground_truth"
) -> tuple[_FloatArray, _FloatArray, _FloatArray]:
    """``(t, position_error_m, yaw_error_rad)`` of series ``name`` against ``reference``.

    The reference pose is linearly interpolated at each stamp; the yaw error is wrapped to [-pi,
    pi).
    """
    est = recording.series[name]
    ref = recording.series[reference]
    if len(est) == 0 or len(ref) == 0:
        empty = np.zeros(0)
        return empty, empty, empty
    t = est[:, 0]
    rx = np.interp(t, ref[:, 0], ref[:, 1])
    ry = np.interp(t, ref[:, 0], ref[:, 2])
    ryaw = np.interp(t, ref[:, 0], np.unwrap(ref[:, 3]))
    pos = np.hypot(est[:, 1] - rx, est[:, 2] - ry)
    dyaw = (est[:, 3] - ryaw + math.pi) % (2 * math.pi) - math.pi
    return t, pos, dyaw


def _pyplot() -> Any:
    try:
        import matplotlib
    except ImportError as exc:
        raise PlotError(
            "posekit plot needs matplotlib (pip install matplotlib, or posekit[plot])"
        ) from exc
    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def plot_odometry(
    recording: OdometryRecording,
    path: str | Path,
    *,
    title: str = "odometry",
    dpi: int = 100,
) -> Path:
    """Draw the recording (see the module docstring) and write a PNG to ``path``.

    Raises:
        PlotError: matplotlib missing, or no series to draw.
    """
    names: list[str] = [
        n for n in ("ground_truth", "wheels", "filtered") if n in recording.series
    ]
    names += [n for n in recording.series if n not in names]
    if not any(len(recording.series[n]) for n in names):
        raise PlotError("the recording holds no odometry messages")
    plt = _pyplot()
    fig, (ax_xy, ax_pos, ax_yaw) = plt.subplots(1, 3, figsize=(15, 5))
    try:
        for name in names:
            rows = recording.series[name]
            if len(rows) == 0:
                continue
            label, color, style = _STYLE.get(name, (name, None, "-"))
            ax_xy.plot(rows[:, 1], rows[:, 2], style, color=color, label=label, lw=1.5)
            ax_xy.plot(rows[0, 1], rows[0, 2], "o", color=color, ms=4)
            ax_xy.plot(rows[-1, 1], rows[-1, 2], "x", color=color, ms=7)
            if name != "ground_truth" and len(recording.series.get("ground_truth", ())):
                t, pos, dyaw = errors_against_truth(recording, name)
                ax_pos.plot(t, pos, style, color=color, label=label)
                ax_yaw.plot(t, np.degrees(dyaw), style, color=color, label=label)
        for t_goal in recording.goal_reached[:1]:
            for ax in (ax_pos, ax_yaw):
                ax.axvline(t_goal, color="tab:green", lw=0.8, ls=":", label="goal reached")
        ax_xy.set(xlabel="x in odom [m]", ylabel="y in odom [m]", title="path")
        ax_xy.set_aspect("equal", adjustable="datalim")
        ax_pos.set(xlabel="sim time [s]", ylabel="position error [m]", title="vs ground truth")
        ax_yaw.set(xlabel="sim time [s]", ylabel="yaw error [deg]", title="vs ground truth")
        for ax in (ax_xy, ax_pos, ax_yaw):
            ax.grid(True, alpha=0.3)
            if ax.get_legend_handles_labels()[0]:
                ax.legend(loc="best", fontsize=8)
        fig.suptitle(title)
        fig.tight_layout()
        out = Path(path)
        if out.suffix.lower() != ".png":
            out = out.with_name(out.name + ".png")
        out.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(out, dpi=dpi, format="png")
    finally:
        plt.close(fig)
    return out


def plot_odometry_file(recording_path: str | Path, output: str | Path, **kwargs: Any) -> Path:
    """``posekit plot odometry RUN.npz -o OUT.png``: load a saved recording and plot it."""
    try:
        recording = OdometryRecording.load(recording_path)
    except (OSError, ValueError) as exc:
        raise PlotError(f"cannot read recording {str(recording_path)!r}: {exc}") from exc
    return plot_odometry(recording, output, **kwargs)
