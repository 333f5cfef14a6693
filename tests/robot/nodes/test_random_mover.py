"""random_mover node: 2 Hz seeded commands in the course's ranges, pose log at 1 Hz."""

from __future__ import annotations

import random

import pytest

from posekit.msgs.geometry_msgs import TwistStamped
from posekit.msgs.nav_msgs import Odometry
from posekit.robot.nodes import RandomMoverNode
from posekit.runtime.node import Node

SIM = {"use_sim_time": True}


class _Observer(Node):
    def __init__(self, ctx) -> None:
        super().__init__("observer", context=ctx, parameter_overrides=SIM)
        self.cmds: list[TwistStamped] = []
        self.create_subscription(TwistStamped, "cmd_vel", self.cmds.append, 100)
        self.pub = self.create_publisher(Odometry, "odometry/filtered", 10)
        self.create_timer(0.05, self._odom)

    def _odom(self) -> None:
        msg = Odometry()
        msg.pose.pose.position.x = self.get_clock().now_ns() / 1e9
        self.pub.publish(msg)


def test_commands_are_the_seeded_uniform_draws_at_2_hz(ctx, executor, logs) -> None:
    node = RandomMoverNode(context=ctx, parameter_overrides={**SIM, "seed": 42})
    obs = _Observer(ctx)
    executor.add_node(node)
    executor.add_node(obs)
    executor.run_until(10.0)
    stamps = [c.header.stamp.sec + 1e-9 * c.header.stamp.nanosec for c in obs.cmds]
    assert stamps == pytest.approx([0.5 * k for k in range(1, 21)], abs=1e-9)
    rng = random.Random(42)  # the reference: Python's generator, linear.x then angular.z
    for c in obs.cmds:
        assert c.twist.linear.x == rng.uniform(-0.5, 0.5)
        assert c.twist.angular.z == rng.uniform(-1.0, 1.0)
    lines = [r for r in logs if r.name == "random_mover"]
    assert [r.stamp_ns for r in lines] == [50_000_000 * (1 + 20 * k) for k in range(10)]
    assert lines[1].message == "Odom: x=1.05, y=0.00, yaw=0.00"  # the pose sent at 1.05 s


def test_publish_rate_parameter(ctx, executor) -> None:
    node = RandomMoverNode(context=ctx, parameter_overrides={**SIM, "publish_rate": 5.0})
    obs = _Observer(ctx)
    executor.add_node(node)
    executor.add_node(obs)
    executor.run_until(1.0)
    assert len(obs.cmds) == 5
    with pytest.raises(ValueError, match="publish_rate"):
        RandomMoverNode("r2", context=ctx, parameter_overrides={**SIM, "publish_rate": 0.0})
