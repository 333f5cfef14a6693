"""Viewing another context over the Zenoh transport (what ``posekit view`` does for other
processes): static and dynamic TF and odometry arrive in the tap."""

from __future__ import annotations

import time

import pytest

pytest.importorskip("zenoh")

from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.nav_msgs import Odometry
from posekit.runtime.context import Context
from posekit.runtime.node import Node
from posekit.runtime.tf2_ros import StaticTransformBroadcaster, TransformBroadcaster
from posekit.viewer.taps import ViewerTap

pytestmark = pytest.mark.slow  # real processes, sessions or a browser


def tf(parent: str, child: str, x: float, stamp_s: int) -> TransformStamped:
    t = TransformStamped()
    t.header.frame_id, t.child_frame_id = parent, child
    t.header.stamp.sec = stamp_s
    t.transform.translation.x = x
    return t


def test_tap_over_zenoh_sees_another_context() -> None:
    publisher_ctx, viewer_ctx = Context(), Context()
    publisher_ctx.init(transport="zenoh")
    viewer_ctx.init(transport="zenoh")
    try:
        node = Node("zenoh_view_pub", context=publisher_ctx)
        StaticTransformBroadcaster(node).sendTransform(tf("base_link", "imu_link", 0.1, 0))
        dynamic = TransformBroadcaster(node)
        odom = node.create_publisher(Odometry, "/odometry/filtered", 10)
        tap = ViewerTap(viewer_ctx.transport())
        end = time.monotonic() + 10.0
        frames: dict[str, list[object]] = {}
        trail: dict[str, object] = {}
        while time.monotonic() < end:
            tap.refresh()
            dynamic.sendTransform(tf("odom", "base_link", 2.0, 1))
            msg = Odometry()
            msg.header.frame_id = "odom"
            msg.pose.pose.position.x = 2.0
            odom.publish(msg)
            error, rows = tap.frames_in("odom")
            frames = {r[0]: r for r in rows}
            trail = tap.trails().get("/odometry/filtered", {})
            if error is None and "imu_link" in frames and frames["imu_link"][11] and trail:
                break
            time.sleep(0.1)
        assert frames["imu_link"][2:5] == [2.1, 0.0, 0.0]  # static (latched) + dynamic
        assert frames["imu_link"][10] is True
        assert trail["trail"][0][0] == 2.0
        tap.close()
    finally:
        publisher_ctx.try_shutdown()
        viewer_ctx.try_shutdown()
