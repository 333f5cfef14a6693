"""``image_saver``: writes images of a topic as PNG files (stands in for rqt_image_view).

Subscribes to ``topic`` (default ``aruco_detection_image``) and writes at most one image per
``period`` seconds of the image stamps (the first one immediately), each to
``<output_dir>/<prefix>_<sec>_<nanosec 9 digits>.png``, keeping at most ``max_images``
files (0 = no limit; then it stops writing). With ``save_last_on_shutdown`` (true) the last
image received is also written when the node is destroyed, as ``<prefix>_last.png``.
Colour images are written in their true colours (rgb8 is converted; bgr8 is OpenCV's
order); mono8/mono16 are written as grey. An image that cannot be decoded or written is
logged and skipped.

Parameters: ``topic``, ``output_dir`` (posekit_images), ``prefix`` (the topic's last name
component), ``period`` (1.0 s), ``max_images`` (0), ``save_last_on_shutdown`` (true).

Wire it into a run: :func:`image_saver_entry` (a launch entry for ``extra_nodes``) or
:func:`attach_image_saver` (an ``on_start`` hook), e.g. for a ``--save-images DIR`` option.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import cv2
import numpy as np

from posekit.launch import Node as LaunchNode
from posekit.msgs.errors import ImageConversionError
from posekit.msgs.image import image_to_numpy
from posekit.msgs.sensor_msgs import Image
from posekit.runtime.node import Node
from posekit.runtime.parameters import declare_value
from posekit.time import stamp_to_ns
from posekit.vision.nodes._common import NS

__all__ = ["ImageSaver", "attach_image_saver", "image_saver_entry"]


class ImageSaver(Node):
    """Saves images of a topic as PNG (see the module docstring).

    Attributes: ``saved`` (paths written, in order), ``last_path`` (the most recent one or
    None), ``output_dir``.
    """

    def __init__(self, node_name: str = "image_saver", **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)
        topic = str(declare_value(self, "topic", "aruco_detection_image"))
        self.output_dir = Path(str(declare_value(self, "output_dir", "posekit_images")))
        prefix = str(declare_value(self, "prefix", ""))
        period = float(declare_value(self, "period", 1.0))
        self._max_images = int(declare_value(self, "max_images", 0))
        self._save_last = bool(declare_value(self, "save_last_on_shutdown", True))
        self._prefix = prefix or topic.strip("/").split("/")[-1] or "image"
        self._period_ns = max(0, round(period * NS))
        self._next_ns: int | None = None
        self._last_msg: Image | None = None
        self.saved: list[Path] = []
        self.last_path: Path | None = None
        self._sub = self.create_subscription(Image, topic, self._on_image, 10)

    def _on_image(self, msg: Image) -> None:
        self._last_msg = msg
        t_ns = stamp_to_ns(msg.header.stamp)
        if self._next_ns is not None and t_ns < self._next_ns:
            return
        if self._max_images and len(self.saved) >= self._max_images:
            return
        sec, nsec = divmod(t_ns, NS)
        if self.write(msg, self.output_dir / f"{self._prefix}_{sec}_{nsec:09d}.png"):
            self._next_ns = t_ns + self._period_ns

    def write(self, msg: Image, path: Path) -> bool:
        """Write ``msg`` to ``path`` as PNG; False (logged) if it cannot be."""
        try:
            array = image_to_numpy(msg)
        except ImageConversionError as exc:
            self.get_logger().error(f"cannot save image: {exc}", throttle_duration_sec=2.0)
            return False
        encoding = str(msg.encoding)
        if array.size == 0:
            self.get_logger().error("cannot save an empty image", throttle_duration_sec=2.0)
            return False
        if encoding in ("rgb8", "rgb16"):
            array = cv2.cvtColor(array, cv2.COLOR_RGB2BGR)
        elif encoding in ("rgba8", "rgba16"):
            array = cv2.cvtColor(array, cv2.COLOR_RGBA2BGRA)
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            ok = bool(cv2.imwrite(str(path), np.ascontiguousarray(array)))
        except (OSError, cv2.error) as exc:
            ok, reason = False, str(exc)
        else:
            reason = "cv2.imwrite refused the image"
        if not ok:
            self.get_logger().error(f"cannot write {path}: {reason}", throttle_duration_sec=2.0)
            return False
        self.saved.append(path)
        self.last_path = path
        return True

    def destroy_node(self) -> None:
        """Write the last image (``save_last_on_shutdown``), then destroy the node."""
        if self._save_last and self._last_msg is not None:
            msg, self._last_msg = self._last_msg, None
            self.write(msg, self.output_dir / f"{self._prefix}_last.png")
        super().destroy_node()


def image_saver_entry(output_dir: str | Path, *, topic: str = "aruco_detection_image",
                      period: float = 1.0, max_images: int = 0,
                      name: str = "image_saver") -> LaunchNode:
    """A launch entry running an :class:`ImageSaver` (for ``run_scenario(extra_nodes=...)``)."""
    return LaunchNode(ImageSaver, name=name, parameters=[{
        "topic": topic, "output_dir": str(output_dir), "period": float(period),
        "max_images": int(max_images),
    }])


def attach_image_saver(run: Any, output_dir: str | Path, *,
                       topic: str = "aruco_detection_image", period: float = 1.0,
                       max_images: int = 0) -> ImageSaver:
    """``on_start`` hook body: add an :class:`ImageSaver` to a started launch run.

    It joins the run's context and executor and is destroyed - writing the last image - with the
    run.
    """
    node = ImageSaver(
        "image_saver", context=run.context,
        parameter_overrides={"topic": topic, "output_dir": str(output_dir),
                             "period": float(period), "max_images": int(max_images),
                             "use_sim_time": True},
    )
    run.executor.add_node(node)
    run.nodes.append(node)
    return node
