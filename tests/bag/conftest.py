"""Fixtures for bag tests: an isolated in-process context, small publisher nodes whose every
published message is kept (the expected content of a recording), a recorded bag, and a
field-by-field message comparison that works across posekit, rosbags and mcap_ros2 objects.
``logs`` comes from tests/conftest.py."""

from __future__ import annotations

import copy
import dataclasses
import math
from collections.abc import Callable, Iterator
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from posekit.bag import attach_recorder
from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.sensor_msgs import Image, Imu
from posekit.msgs.std_msgs import String
from posekit.runtime.context import Context
from posekit.runtime.node import Node
from posekit.runtime.qos import qos_profile_sensor_data
from posekit.runtime.sim_executor import SimulatedTimeExecutor
from posekit.tf2_ros import StaticTransformBroadcaster, TransformBroadcaster

#: Sim time at which the test systems start (s): not zero, so start/offset bugs show.
START_S = 1000.25
START_NS = 1_000_250_000_000


@pytest.fixture
def ctx() -> Iterator[Context]:
    """As tests/conftest.py's ``ctx`` but pinned to the in-process transport whatever
    $POSEKIT_TRANSPORT says: the recordings are compared message for message."""
    context = Context()
    context.init(transport="inprocess")
    yield context
    context.try_shutdown()


class Talkers(Node):
    """/tf (20 Hz, robot on a circle), /chatter (10 Hz, non-ASCII text), /odom (10 Hz with
    covariance), /imu (25 Hz, best effort), /camera/image (5 Hz, 4x3 rgb8) and one static
    transform; ``sent`` keeps ``(topic, sim time ns, copy of msg)`` for everything published."""

    def __init__(self, context: Context, name: str = "talkers") -> None:
        super().__init__(name, context=context)
        self.sent: list[tuple[str, int, Any]] = []
        self.tf = TransformBroadcaster(self)
        self.static = StaticTransformBroadcaster(self)
        self.chatter = self.create_publisher(String, "chatter", 10)
        self.odom = self.create_publisher(Odometry, "odom", 10)
        self.imu = self.create_publisher(Imu, "imu", qos_profile_sensor_data)
        self.image = self.create_publisher(Image, "camera/image", 5)
        laser = TransformStamped()
        laser.header.frame_id = "base_link"
        laser.child_frame_id = "laser"
        laser.transform.translation.x = 0.12
        laser.transform.translation.z = 0.2
        self.static.sendTransform(laser)
        self.count = 0
        self.create_timer(0.05, self.on_tf)
        self.create_timer(0.1, self.on_slow)
        self.create_timer(0.04, self.on_imu)
        self.create_timer(0.2, self.on_image)

    def _keep(self, topic: str, msg: Any) -> None:
        self.sent.append((topic, self.get_clock().now().nanoseconds, copy.deepcopy(msg)))

    def pose_at(self, t: float) -> TransformStamped:
        ts = TransformStamped()
        ts.header.stamp = self.get_clock().now().to_msg()
        ts.header.frame_id = "odom"
        ts.child_frame_id = "base_link"
        ts.transform.translation.x = math.cos(0.5 * t)
        ts.transform.translation.y = math.sin(0.5 * t)
        yaw = 0.5 * t + math.pi / 2
        ts.transform.rotation.z = math.sin(yaw / 2)
        ts.transform.rotation.w = math.cos(yaw / 2)
        return ts

    def on_tf(self) -> None:
        t = self.get_clock().now().nanoseconds / 1e9
        ts = self.pose_at(t)
        self.tf.sendTransform(ts)
        from posekit.msgs.tf2_msgs import TFMessage

        self._keep("/tf", TFMessage(transforms=[ts]))

    def on_slow(self) -> None:
        self.count += 1
        text = String(data=f"hello {self.count} ✓ ünïcode")
        self.chatter.publish(text)
        self._keep("/chatter", text)
        odom = Odometry()
        odom.header.stamp = self.get_clock().now().to_msg()
        odom.header.frame_id = "odom"
        odom.child_frame_id = "base_link"
        odom.pose.pose.position.x = 0.1 * self.count
        odom.pose.covariance = np.arange(36, dtype=np.float64) * 1e-3 + self.count
        odom.twist.twist.angular.z = -0.25
        self.odom.publish(odom)
        self._keep("/odom", odom)

    def on_imu(self) -> None:
        imu = Imu()
        imu.header.stamp = self.get_clock().now().to_msg()
        imu.header.frame_id = "imu_link"
        imu.angular_velocity.z = 0.5 + 1e-9 * self.get_clock().now().nanoseconds % 7
        imu.linear_acceleration.z = 9.80665
        imu.orientation_covariance[0] = -1.0
        self.imu.publish(imu)
        self._keep("/imu", imu)

    def on_image(self) -> None:
        img = Image()
        img.header.stamp = self.get_clock().now().to_msg()
        img.header.frame_id = "camera"
        img.height, img.width, img.encoding, img.step = 3, 4, "rgb8", 12
        img.data = (np.arange(36, dtype=np.uint8) * 7 + self.count).astype(np.uint8)
        self.image.publish(img)
        self._keep("/camera/image", img)


class CameraMount(Node):
    """A second static broadcaster (base_link -> camera), as robot_state_publisher and a
    static_transform_publisher would both latch /tf_static."""

    def __init__(self, context: Context) -> None:
        super().__init__("camera_mount", context=context)
        self.static = StaticTransformBroadcaster(self)
        cam = TransformStamped()
        cam.header.frame_id = "base_link"
        cam.child_frame_id = "camera"
        cam.transform.translation.x = 0.05
        cam.transform.rotation.x = -0.5
        cam.transform.rotation.y = 0.5
        cam.transform.rotation.z = -0.5
        cam.transform.rotation.w = 0.5
        self.static.sendTransform(cam)
        self.msg = cam


@dataclasses.dataclass
class RecordedBag:
    path: Path
    talkers: Talkers
    camera: CameraMount
    counts: dict[str, int]


def record_talkers(ctx: Context, path: Path, seconds: float = 1.0, **options: Any) -> RecordedBag:
    executor = SimulatedTimeExecutor(context=ctx, start_time=START_S)
    talkers = Talkers(ctx)
    camera = CameraMount(ctx)
    executor.add_node(talkers)
    executor.add_node(camera)
    recorder = attach_recorder(executor, path, **options)
    executor.run_for(seconds)
    counts = recorder.close()
    return RecordedBag(path, talkers, camera, counts)


@pytest.fixture
def recorded(ctx: Context, tmp_path: Path) -> RecordedBag:
    """One second of the talkers recorded with default options into tmp_path / "bag"."""
    return record_talkers(ctx, tmp_path / "bag")


def _as_array(value: Any) -> np.ndarray | None:
    if isinstance(value, np.ndarray):
        return value
    if isinstance(value, bytes | bytearray | memoryview):
        return np.frombuffer(bytes(value), dtype=np.uint8)
    if isinstance(value, list | tuple) and all(
        isinstance(v, int | float | np.number) and not isinstance(v, bool) for v in value
    ):
        return np.asarray(value)
    return None


def assert_same_message(expected: Any, actual: Any, path: str = "msg") -> None:
    """Field-by-field equality of a posekit message and any object with the ROS field names
    (rosbags dataclasses, mcap_ros2's decoded objects). Floats must be bit-identical."""
    if dataclasses.is_dataclass(expected):
        for f in dataclasses.fields(expected):
            assert hasattr(actual, f.name), f"{path}: decoded object lacks field {f.name!r}"
            assert_same_message(getattr(expected, f.name), getattr(actual, f.name),
                                f"{path}.{f.name}")
        return
    exp_arr, act_arr = _as_array(expected), _as_array(actual)
    if exp_arr is not None and act_arr is not None and (
        isinstance(expected, np.ndarray) or isinstance(actual, np.ndarray | bytes)
    ):
        np.testing.assert_array_equal(act_arr, exp_arr, err_msg=path)
        assert act_arr.shape == exp_arr.shape, path
        return
    if isinstance(expected, list):
        assert len(actual) == len(expected), f"{path}: length {len(actual)} != {len(expected)}"
        for i, (e, a) in enumerate(zip(expected, actual, strict=True)):
            assert_same_message(e, a, f"{path}[{i}]")
        return
    assert actual == expected, f"{path}: {actual!r} != {expected!r}"
    assert type(actual) is type(expected) or isinstance(expected, float | int), path


@pytest.fixture
def same_message() -> Callable[[Any, Any], None]:
    return assert_same_message


@pytest.fixture
def kit() -> SimpleNamespace:
    """Helpers for test modules (conftest is not importable under --import-mode=importlib)."""
    return SimpleNamespace(
        record=record_talkers, START_NS=START_NS, START_S=START_S, same=assert_same_message,
        Talkers=Talkers, CameraMount=CameraMount,
    )
