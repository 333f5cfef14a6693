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
from posekit.tf2_ros import StaticTransformBroadcaster, TransformBroadcaster
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


def test_viewer_over_zenoh_learns_the_world_from_the_simulator_parameter() -> None:
    """No world given: the viewer asks the other process's nodes for their ``world``
    parameter (the parameter service, as ``ros2 param get``) and sends the pages a new
    ``hello`` with that world's boxes and markers."""
    import asyncio
    import json

    aiohttp = pytest.importorskip("aiohttp")
    import threading

    from posekit.runtime.executors import SingleThreadedExecutor
    from posekit.viewer import attach_viewer
    from posekit.worlds import load_world

    sim_ctx, viewer_ctx = Context(), Context()
    sim_ctx.init(transport="zenoh")
    viewer_ctx.init(transport="zenoh")
    server = None
    executor = SingleThreadedExecutor(context=sim_ctx)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    try:
        sim = Node("world_simulation", context=sim_ctx)
        sim.declare_parameter("world", "aruco_box_world")
        other = Node("other_node", context=sim_ctx)
        other.declare_parameter("world", "")
        executor.add_node(sim)
        executor.add_node(other)
        spinner.start()  # the nodes answer their parameter services
        server = attach_viewer(viewer_ctx, port=0)
        ws_url = server.url.replace("http://", "ws://") + "ws"

        async def hello_with_world() -> dict[str, object]:
            async with aiohttp.ClientSession() as session, session.ws_connect(ws_url) as ws:
                end = time.monotonic() + 15.0
                while time.monotonic() < end:
                    msg = await ws.receive(timeout=end - time.monotonic())
                    if msg.type != aiohttp.WSMsgType.TEXT:
                        continue
                    data = json.loads(msg.data)
                    if data["type"] == "hello" and data["world"]:
                        return dict(data["world"])
                raise AssertionError("no hello with a world within 15 s")

        world = asyncio.run(hello_with_world())
        expected = load_world("aruco_box_world")
        assert world["name"] == "aruco_box_world"
        assert len(world["boxes"]) == len(expected.boxes) > 0
    finally:
        if server is not None:
            server.stop()
        executor.shutdown()
        sim_ctx.try_shutdown()
        viewer_ctx.try_shutdown()
        spinner.join(timeout=5.0)
