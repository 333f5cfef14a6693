"""The rclpy / tf2_ros facades re-export posekit's implementation and behave like rclpy."""

from __future__ import annotations

import pytest

import posekit.runtime.executors as runtime_executors
import posekit.runtime.node as runtime_node
import posekit.runtime.qos as runtime_qos
import posekit.tf2 as tf2
from posekit import rclpy, time
from posekit.msgs.std_msgs import String
from posekit.rclpy import duration, executors, node, parameter, qos
from posekit.rclpy import time as rclpy_time
from posekit.rclpy.exceptions import NotInitializedException


def test_reexports_are_the_implementation() -> None:
    assert node.Node is runtime_node.Node
    assert rclpy_time.Time is time.Time
    assert duration.Duration is time.Duration
    assert qos.QoSProfile is runtime_qos.QoSProfile
    assert qos.qos_profile_sensor_data is runtime_qos.qos_profile_sensor_data
    assert executors.SingleThreadedExecutor is runtime_executors.SingleThreadedExecutor
    assert parameter.Parameter.Type.DOUBLE.value == 3  # an Enum, as in rclpy
    from posekit import tf2_ros

    assert tf2_ros.Buffer is tf2.Buffer
    assert tf2_ros.TransformException is tf2.TransformException
    for name in ["LookupException", "ConnectivityException", "ExtrapolationException",
                 "InvalidArgumentException", "TimeoutException"]:
        assert issubclass(getattr(tf2_ros, name), tf2_ros.TransformException)


def test_node_requires_init_and_module_level_spin() -> None:
    with pytest.raises(NotInitializedException, match="init"):
        rclpy.create_node("too_early")
    rclpy.init()
    try:
        assert rclpy.ok()
        with pytest.raises(RuntimeError, match="once"):
            rclpy.init()
        n = rclpy.create_node("talker")
        got: list[str] = []
        n.create_subscription(String, "chatter", lambda m: got.append(m.data), 10)
        n.create_publisher(String, "chatter", 10).publish(String(data="hello"))
        rclpy.spin_once(n, timeout_sec=1.0)
        assert got == ["hello"]
        future = rclpy.task.Future()
        n.create_timer(0.001, lambda: future.set_result("done"))
        rclpy.spin_until_future_complete(n, future, timeout_sec=5.0)
        assert future.result() == "done"
        n.create_timer(0.001, rclpy.shutdown)
        rclpy.spin(n)  # returns when the timer shuts the context down
        assert not rclpy.ok()
    finally:
        rclpy.try_shutdown()
