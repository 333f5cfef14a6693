"""Shared machinery of the simulated camera nodes: a timer at the camera rate renders the
world's boxes and walls from the camera's optical-frame pose at the current sim time and
publishes the image and its ``CameraInfo`` with the same stamp (as gz-sensors + ros_gz_bridge
do)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import numpy.typing as npt

from posekit.msgs.image import numpy_to_image
from posekit.msgs.sensor_msgs import CameraInfo, Image
from posekit.msgs.std_msgs import Header
from posekit.runtime.node import Node
from posekit.runtime.parameters import declare_value
from posekit.time import stamp_from_ns
from posekit.vision.camera import PinholeCamera
from posekit.vision.render import BoxRenderer
from posekit.worlds import World, load_world
from posekit.worlds.obstacles import WallSegments

__all__ = ["SimulatedCamera"]

F64Array = npt.NDArray[np.float64]


class SimulatedCamera(Node):
    """Base of the camera nodes. Subclasses set up ``camera`` and topics, then call
    :meth:`_start` and implement :meth:`T_world_optical_at`.

    Common parameters: ``world`` (a world name or file), ``noise_sigma`` (grey levels, 0),
    ``seed`` (0), ``supersample`` (1), ``lazy`` (true: render only while someone subscribes
    to the image topic, like ros_gz_bridge's lazy mode; CameraInfo is always published).

    Attributes: ``frames_published`` (images sent), ``last_T_world_optical`` (pose used for
    the last image), ``world``, ``camera``, ``frame_id``.
    """

    def __init__(self, node_name: str, default_world: str, **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)
        self.world: World = load_world(str(declare_value(self, "world", default_world)))
        self._noise_sigma = float(declare_value(self, "noise_sigma", 0.0))
        self._seed = int(declare_value(self, "seed", 0))
        self._supersample = int(declare_value(self, "supersample", 1))
        self._lazy = bool(declare_value(self, "lazy", True))
        self._boxes = [box.T_world_box for box in self.world.boxes]
        self.frames_published = 0
        self.last_T_world_optical: F64Array | None = None
        self.camera: PinholeCamera
        self.frame_id: str = ""

    def _start(self, camera: PinholeCamera, image_topic: str, info_topic: str, frame_id: str,
               rate_hz: float) -> None:
        if not (math.isfinite(rate_hz) and rate_hz > 0.0):
            raise ValueError(f"camera rate must be > 0 Hz, got {rate_hz}")
        self.camera = camera
        self.frame_id = frame_id
        walls = WallSegments.from_world(self.world) if self.world.walls else None
        self._renderer = BoxRenderer(camera, supersample=self._supersample,
                                     noise_sigma=self._noise_sigma, seed=self._seed, walls=walls)
        self._info_msg = camera.camera_info(frame_id=frame_id)
        self._image_pub = self.create_publisher(Image, image_topic, 10)
        self._info_pub = self.create_publisher(CameraInfo, info_topic, 10)
        self._now_ns = self.get_clock().now_ns
        self.create_timer(1.0 / rate_hz, self._on_frame)
        self.get_logger().info(
            f"camera {camera.width}x{camera.height} hfov {math.degrees(camera.hfov):.1f} deg "
            f"at {rate_hz:g} Hz on {self._image_pub.topic_name} (frame '{frame_id}'), "
            f"{len(self._boxes)} boxes in '{self.world.name}'"
        )

    def T_world_optical_at(self, t_ns: int) -> F64Array:
        """Pose (4x4) of the optical frame (x right, y down, z forward) in the world at
        ``t_ns``."""
        raise NotImplementedError

    def render_at(self, t_ns: int) -> npt.NDArray[np.uint8]:
        """The rgb8 image (H, W, 3) the camera sees at ``t_ns``."""
        T = self.T_world_optical_at(t_ns)
        self.last_T_world_optical = T
        return self._renderer.render(T, self._boxes)

    def _on_frame(self) -> None:
        now_ns = self._now_ns()
        header = Header(stamp=stamp_from_ns(now_ns), frame_id=self.frame_id)
        self._info_msg.header = header
        self._info_pub.publish(self._info_msg)
        if self._lazy and not self._image_pub.get_subscription_count():
            return
        msg = numpy_to_image(self.render_at(now_ns), "rgb8", header)
        self._image_pub.publish(msg)
        self.frames_published += 1
