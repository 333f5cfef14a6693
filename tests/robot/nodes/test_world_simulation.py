"""world_simulation node: physics against the model stepped by hand, sensors, cmd_vel timeout
and stale rejection, static frames and wheel TFs through a TransformListener, worlds."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from posekit.msgs.geometry_msgs import TwistStamped
from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.sensor_msgs import Imu, JointState
from posekit.robot.drive import RosbotBase
from posekit.robot.headless import sub_seeds
from posekit.robot.kinematics import yaw_from_quaternion_xyzw
from posekit.robot.nodes import WorldSimulation
from posekit.robot.params import DEFAULT_DRIVE, DEFAULT_SLIP, WHEEL_JOINT_NAMES
from posekit.runtime.node import Node
from posekit.tf2_ros import Buffer, TransformListener
from posekit.time import Time, stamp_from_ns
from posekit.worlds import WorldError

SIM = {"use_sim_time": True}


def _yaw(q) -> float:
    return yaw_from_quaternion_xyzw(q.x, q.y, q.z, q.w)


class _Commander(Node):
    """Publishes ``command(t)`` -> (v, w) or None at 20 Hz, stamped with ``stamp(t)``."""

    def __init__(self, ctx, command, stamp=lambda t_ns: t_ns) -> None:
        super().__init__("commander", context=ctx, parameter_overrides=SIM)
        self.pub = self.create_publisher(TwistStamped, "cmd_vel", 10)
        self.command, self.stamp = command, stamp
        self.create_timer(0.05, self._tick)

    def _tick(self) -> None:
        t_ns = self.get_clock().now_ns()
        cmd = self.command(t_ns / 1e9)
        if cmd is None:
            return
        msg = TwistStamped()
        msg.header.stamp = stamp_from_ns(self.stamp(t_ns))
        msg.twist.linear.x, msg.twist.angular.z = cmd
        self.pub.publish(msg)


class _Sink(Node):
    def __init__(self, ctx) -> None:
        super().__init__("sink", context=ctx, parameter_overrides=SIM)
        self.truth: list[Odometry] = []
        self.imu: list[Imu] = []
        self.joints: list[JointState] = []
        self.create_subscription(Odometry, "ground_truth/odom", self.truth.append, 100)
        self.create_subscription(Imu, "imu/data", self.imu.append, 100)
        self.create_subscription(JointState, "joint_states", self.joints.append, 100)


def _t(msg) -> float:
    return msg.header.stamp.sec + 1e-9 * msg.header.stamp.nanosec


def _wavy(t: float) -> tuple[float, float] | None:
    return (0.4 * math.sin(1.3 * t), 0.8 * math.cos(0.7 * t)) if t < 3.0 else None


def test_physics_equals_the_model_stepped_at_100_hz(ctx, executor) -> None:
    world = WorldSimulation(context=ctx, parameter_overrides={**SIM, "seed": 7})
    commander = _Commander(ctx, _wavy)
    sink = _Sink(ctx)
    for n in (world, commander, sink):
        executor.add_node(n)
    executor.run_until(4.0)

    # Reference: the drive model stepped by hand on the 10 ms grid with the same commands
    # (issued at each 50 ms tick after the pose at that tick is read).
    ref = RosbotBase(DEFAULT_DRIVE, DEFAULT_SLIP, seed=sub_seeds(7)[0])
    expected = {}
    for k in range(401):
        t_ns = k * 10_000_000
        if k % 5 == 0 and k > 0:
            x, y, yaw = ref.pose
            expected[k // 5] = (x, y, math.remainder(yaw, 2 * math.pi))
            cmd = _wavy(t_ns / 1e9)
            if cmd is not None:
                ref.submit_velocity(*cmd, stamp=t_ns / 1e9, now=t_ns / 1e9)
        ref.step(t_ns / 1e9, 0.01)
    assert len(sink.truth) == 80
    for msg in sink.truth:
        k = round(_t(msg) / 0.05)
        x, y, yaw = expected[k]
        p = msg.pose.pose
        assert (p.position.x, p.position.y) == pytest.approx((x, y), abs=1e-12)
        assert math.remainder(_yaw(p.orientation) - yaw, 2 * math.pi) == pytest.approx(0, abs=1e-12)
    assert msg.header.frame_id == "odom"
    assert msg.child_frame_id == "base_link"
    assert abs(sink.truth[30].pose.pose.position.x) > 0.05  # it did move


def test_sensor_topics_rates_frames_and_consistency(ctx, executor) -> None:
    world = WorldSimulation(context=ctx, parameter_overrides=SIM)
    commander = _Commander(ctx, lambda t: (0.3, 0.5))
    sink = _Sink(ctx)
    for n in (world, commander, sink):
        executor.add_node(n)
    executor.run_until(2.0)
    imu_t = [_t(m) for m in sink.imu]
    assert imu_t == pytest.approx([0.04 * k for k in range(1, 51)], abs=1e-9)  # 25 Hz
    assert {m.header.frame_id for m in sink.imu} == {"imu_link"}
    joint_t = [_t(m) for m in sink.joints]
    assert joint_t == pytest.approx([0.05 * k for k in range(1, 41)], abs=1e-9)
    last = sink.joints[-1]
    assert list(last.name) == list(WHEEL_JOINT_NAMES)
    fl, fr, rl, rr = last.position
    assert fl == rl
    assert fr == rr
    assert fr > fl > 0
    # IMU yaw is the true yaw (Gazebo adds no orientation noise) where both are stamped alike.
    truth_by_t = {round(_t(m), 6): _yaw(m.pose.pose.orientation) for m in sink.truth}
    common = [(m, truth_by_t[round(_t(m), 6)]) for m in sink.imu if round(_t(m), 6) in truth_by_t]
    assert len(common) == 10
    for m, yaw in common:
        assert _yaw(m.orientation) == pytest.approx(yaw, abs=1e-12)
    # Gyro: truth + bias (2e-3) + white noise (5.24e-3) around the true yaw rate.
    wz = np.array([m.angular_velocity.z for m in sink.imu[-25:]])
    true_w = np.array([m.twist.twist.angular.z for m in sink.truth[-10:]])
    assert abs(wz.mean() - true_w.mean()) < 0.01
    assert m.orientation_covariance[8] == pytest.approx(1.9e-3)


def test_a_stopped_command_stream_stops_the_robot_within_the_timeout(ctx, executor) -> None:
    t_last = 2.0
    world = WorldSimulation(context=ctx, parameter_overrides=SIM)
    commander = _Commander(ctx, lambda t: (0.5, 0.0) if t <= t_last + 1e-9 else None)
    sink = _Sink(ctx)
    for n in (world, commander, sink):
        executor.add_node(n)
    executor.run_until(5.0)
    by_t = {round(_t(m), 3): m for m in sink.truth}
    # Until the 0.5 s timeout the last command still drives the robot (slip: about 5 % less).
    for t in (2.1, 2.3, 2.45):
        assert by_t[t].twist.twist.linear.x > 0.45
    # Then it brakes at 1 m/s^2 from 0.5 m/s: still by t_last + 0.5 + 0.5 s.
    assert 0.0 < by_t[2.8].twist.twist.linear.x < 0.3
    x_stop = by_t[3.05].pose.pose.position.x
    for t in (3.05, 3.5, 4.0, 5.0):
        assert by_t[t].twist.twist.linear.x == 0.0
        assert by_t[t].pose.pose.position.x == x_stop
    assert list(world.rejected) == []


def test_stale_and_non_finite_commands_are_rejected_with_a_logged_reason(
    ctx, executor, logs
) -> None:
    world = WorldSimulation(context=ctx, parameter_overrides=SIM)
    # Every command is stamped 0.6 s in the past: older than cmd_vel_timeout (0.5 s).
    stale = _Commander(
        ctx, lambda t: (0.5, 0.0) if t > 0.6 else None, stamp=lambda t_ns: t_ns - 600_000_000
    )
    sink = _Sink(ctx)
    for n in (world, stale, sink):
        executor.add_node(n)
    executor.run_until(2.0)
    assert len(world.rejected) == world.rejected_count == 28  # 0.65 ... 2.0 s
    warnings = [r for r in logs if r.name == "world_simulation" and "Rejected cmd_vel" in r.message]
    assert len(warnings) == 2  # one line per second of sim time: at 0.65 s and 1.7 s
    assert "(20 similar suppressed since the last report)" in warnings[1].message
    assert "stale command" in warnings[0].message
    assert "cmd_vel_timeout" in warnings[0].message
    assert all(m.pose.pose.position.x == 0.0 for m in sink.truth)

    bad = TwistStamped()
    bad.header.stamp = stamp_from_ns(executor.now_ns)
    bad.twist.linear.x = float("nan")
    stale.pub.publish(bad)
    executor.run_until(2.01)
    assert "non-finite" in world.rejected[-1][1]


def test_static_frames_wheels_and_world_statics_through_a_transform_listener(
    ctx, executor
) -> None:
    world = WorldSimulation(
        context=ctx, parameter_overrides={**SIM, "world": "aruco_box_camera_world"}
    )
    listener_node = Node("listener", context=ctx, parameter_overrides=SIM)
    buffer = Buffer()
    TransformListener(buffer, listener_node)
    commander = _Commander(ctx, lambda t: (0.0, 1.0))
    for n in (world, listener_node, commander):
        executor.add_node(n)
    executor.run_until(1.0)
    # docs/specs/rosbot_and_worlds.md: base_link -> oak_rgb_camera_frame = (-0.0241, 0, 0.1875),
    # identity rotation;
    # the optical frame adds R = Rz(-pi/2) Rx(-pi/2).
    t = buffer.lookup_transform("base_link", "oak_rgb_camera_optical_frame", Time())
    tr, q = t.transform.translation, t.transform.rotation
    assert (tr.x, tr.y, tr.z) == pytest.approx((-0.0241, 0.0, 0.1875), abs=1e-12)
    assert (q.x, q.y, q.z, q.w) == pytest.approx((-0.5, 0.5, -0.5, 0.5), abs=1e-12)
    t = buffer.lookup_transform("body_link", "imu_link", Time())
    assert t.transform.translation.y == pytest.approx(-0.0495)
    # Wheels spin about +y: the left wheels turn backwards while the robot turns in place.
    t = buffer.lookup_transform("body_link", "fl_wheel_link", Time())
    assert (t.transform.translation.x, t.transform.translation.y) == pytest.approx((0.053, 0.096))
    assert t.transform.rotation.x == 0.0
    assert t.transform.rotation.z == 0.0
    left_angle = world.base.wheel_angles[0]
    assert left_angle < 0
    spin = 2 * math.atan2(t.transform.rotation.y, t.transform.rotation.w)
    assert math.remainder(spin - left_angle, 2 * math.pi) == pytest.approx(0.0, abs=1e-9)
    # The world's own static frames (overhead camera) hang off odom.
    t = buffer.lookup_transform("odom", "overhead_camera", Time())
    assert (t.transform.translation.x, t.transform.translation.z) == pytest.approx((2.0, 2.0))


def test_worlds_by_name_file_and_errors(ctx, tmp_path) -> None:
    path = tmp_path / "mine.json"
    path.write_text(json.dumps({"name": "mine", "spawn": [1.0, -2.0, 0.5]}))
    world = WorldSimulation(context=ctx, parameter_overrides={**SIM, "world": str(path)})
    assert world.world.name == "mine"
    assert world.true_pose == pytest.approx((1.0, -2.0, 0.5))
    with pytest.raises(WorldError, match="unknown world"):
        WorldSimulation("w2", context=ctx, parameter_overrides={**SIM, "world": "no_such"})
    with pytest.raises(ValueError, match=r"imu_rate 30\.0 Hz must divide the update rate"):
        WorldSimulation("w3", context=ctx, parameter_overrides={**SIM, "imu_rate": 30.0})


def test_a_flood_of_bad_commands_keeps_logs_and_memory_bounded(ctx, executor, logs) -> None:
    """5,000 NaN commands within one simulated second: at most one warning per second of
    sim time, the last MAX_KEPT_REJECTIONS kept, all counted. Oracle: counting."""
    from posekit.robot.nodes.world_simulation import MAX_KEPT_REJECTIONS

    world = WorldSimulation(context=ctx, parameter_overrides=SIM)
    attacker = Node("attacker", context=ctx, parameter_overrides=SIM)
    pub = attacker.create_publisher(TwistStamped, "cmd_vel", 10)
    for n in (world, attacker):
        executor.add_node(n)
    executor.run_until(0.5)
    for i in range(5000):
        bad = TwistStamped()
        bad.header.stamp = stamp_from_ns(executor.now_ns)
        bad.twist.linear.x = float("nan") if i % 2 else float("inf")
        pub.publish(bad)
        if i % 10 == 9:  # the simulator's cmd_vel queue keeps 10
            executor.run_until(executor.now_ns / 1e9 + (0.2 if i % 1000 == 999 else 0.0))
    executor.run_until(executor.now_ns / 1e9 + 0.2)
    assert world.rejected_count == 5000
    assert len(world.rejected) == MAX_KEPT_REJECTIONS
    lines = [r for r in logs if r.name == "world_simulation" and "Rejected cmd_vel" in r.message]
    assert 1 <= len(lines) <= 2  # 1.2 s of sim time
    assert "non-finite" in lines[0].message


def test_future_stamped_commands_are_rejected_with_one_warning_and_the_robot_stops(
    ctx, executor, logs
) -> None:
    """Valid commands until 1.0 s, then the same commands stamped on the wall clock: one
    warning, every one rejected, and ground truth still by 1.0 + 0.5 s timeout + 0.5 s of
    braking (0.5 m/s at 1 m/s²) + one output period."""
    world = WorldSimulation(context=ctx, parameter_overrides=SIM)
    wall_ns = 1_795_000_000 * 1_000_000_000
    commander = _Commander(
        ctx, lambda t: (0.5, 0.0),
        stamp=lambda t_ns: t_ns if t_ns <= 1_000_000_000 else wall_ns + t_ns,
    )
    sink = _Sink(ctx)
    for n in (world, commander, sink):
        executor.add_node(n)
    executor.run_until(4.0)
    warnings = [r for r in logs if r.name == "world_simulation" and "cmd_vel" in r.message]
    assert len(warnings) == 1, [w.message for w in warnings]
    assert "future" in warnings[0].message
    assert len(world.rejected) == 60  # 20 Hz from 1.05 to 4.0 s
    moving = [m for m in sink.truth if m.header.stamp.sec + m.header.stamp.nanosec / 1e9 <= 1.0]
    assert moving[-1].twist.twist.linear.x > 0.4
    late = [m for m in sink.truth
            if m.header.stamp.sec + m.header.stamp.nanosec / 1e9 >= 1.0 + 0.5 + 0.5 + 0.05]
    assert late
    assert all(m.twist.twist.linear.x == 0.0 for m in late)


def _tf_listener_beside(world, ctx, executor) -> tuple[Node, Buffer]:
    """A node with a tf2 Buffer and TransformListener, added with ``world`` to ``executor``."""
    listener_node = Node("listener", context=ctx, parameter_overrides=SIM)
    buffer = Buffer()
    TransformListener(buffer, listener_node)
    for n in (world, listener_node):
        executor.add_node(n)
    return listener_node, buffer


def test_scan_on_the_bus_is_lazy_framed_in_tf_and_sees_the_box_ahead(ctx, executor) -> None:
    """/scan: nothing is cast while nobody subscribes (counted calls); with a subscriber,
    10 Hz scans in frame ``laser``, whose static transform the TF tree carries, and the beam
    looking forward reads the closed-form distance to the box face at x = 2.0 (laser at
    x = 0.02) within 5 sigma of the S2's noise."""
    from posekit.msgs.sensor_msgs import LaserScan
    from posekit.robot.description import T_base_frame

    world = WorldSimulation(
        context=ctx, parameter_overrides={**SIM, "world": "aruco_box_world", "seed": 2}
    )
    calls = []
    real_scan = world.lidar.scan
    world.lidar.scan = lambda *a: calls.append(a) or real_scan(*a)  # type: ignore[method-assign]
    listener_node, buffer = _tf_listener_beside(world, ctx, executor)
    executor.run_until(1.0)
    assert calls == []
    scans: list[LaserScan] = []
    listener_node.create_subscription(LaserScan, "scan", scans.append, 10)
    executor.run_until(2.0)
    assert 9 <= len(scans) <= 11
    assert len(calls) == len(scans)
    assert [_t(s) for s in scans] == pytest.approx([1.1 + 0.1 * k for k in range(len(scans))])
    msg = scans[-1]
    assert msg.header.frame_id == "laser"
    assert msg.ranges.shape == (3000,)
    forward = int(np.argmin(np.abs(np.abs(np.asarray(msg.angle_min + msg.angle_increment
                                                        * np.arange(3000))) - math.pi)))
    assert msg.ranges[forward] == pytest.approx(2.0 - 0.02, abs=5 * 0.015)
    t = buffer.lookup_transform("base_link", "laser", Time())
    tr, q = t.transform.translation, t.transform.rotation
    expected = T_base_frame("laser")
    assert (tr.x, tr.y, tr.z) == pytest.approx(tuple(expected.translation), abs=1e-12)
    assert abs(q.z) == pytest.approx(1.0, abs=1e-12)


def test_robot_description_is_latched_and_matches_the_tf_tree(ctx, executor) -> None:
    """/robot_description reaches a subscriber that joins late (TRANSIENT_LOCAL depth 1); its
    URDF, parsed with xml.etree and each joint's origin turned into a matrix with scipy,
    gives the same transform as posekit's tf2 Buffer fed from /tf_static and /tf, for every
    joint, and names exactly the frames the TF tree has."""
    import xml.etree.ElementTree as ET

    from scipy.spatial.transform import Rotation as ScipyRotation

    from posekit.msgs.std_msgs import String
    from posekit.runtime.qos import DurabilityPolicy, HistoryPolicy, QoSProfile

    world = WorldSimulation(context=ctx, parameter_overrides=SIM)
    listener_node, buffer = _tf_listener_beside(world, ctx, executor)
    executor.run_until(0.5)
    got: list[String] = []
    latched = QoSProfile(
        depth=1, history=HistoryPolicy.KEEP_LAST, durability=DurabilityPolicy.TRANSIENT_LOCAL
    )
    listener_node.create_subscription(String, "/robot_description", got.append, latched)
    executor.run_until(1.0)
    assert len(got) == 1
    robot = ET.fromstring(got[0].data)
    assert robot.tag == "robot"
    joints = robot.findall("joint")
    links = {link.get("name") for link in robot.findall("link")}
    assert links == set(buffer.get_all_frame_names()) - {"odom"} | {"base_link"}
    assert len(joints) == len(links) - 1  # a tree rooted at base_link
    for joint in joints:
        parent = joint.find("parent").get("link")
        child = joint.find("child").get("link")
        origin = joint.find("origin")
        xyz = [float(v) for v in origin.get("xyz").split()]
        rpy = [float(v) for v in origin.get("rpy").split()]
        T = buffer.lookup_transform(parent, child, Time())
        tr, q = T.transform.translation, T.transform.rotation
        assert (tr.x, tr.y, tr.z) == pytest.approx(xyz, abs=1e-12), joint.get("name")
        expected = ScipyRotation.from_euler("xyz", rpy)
        actual = ScipyRotation.from_quat([q.x, q.y, q.z, q.w])
        if joint.get("type") == "fixed":
            assert (expected.inv() * actual).magnitude() < 1e-9, joint.get("name")
        else:
            assert joint.get("type") == "continuous"
            axis = [float(v) for v in joint.find("axis").get("xyz").split()]
            assert axis == [0.0, 1.0, 0.0]
            # Only the spin about the joint axis may differ from the origin's rotation.
            rotvec = (expected.inv() * actual).as_rotvec()
            assert abs(rotvec[0]) < 1e-9
            assert abs(rotvec[2]) < 1e-9


def test_contact_through_the_node_truth_stops_wheels_turn(ctx, executor, tmp_path) -> None:
    """Driving at a solid box: ground truth stops at the face minus the robot's half length
    (closed form, docs/robot.md "Contact"); /joint_states keep advancing at the commanded
    wheel speed, so wheel odometry (integrated from them here) runs on past the box."""
    from posekit.robot.contact import ROBOT_HALF_EXTENTS
    from posekit.robot.odometry import WheelOdometry

    path = tmp_path / "wall.json"
    path.write_text(json.dumps({"name": "wall", "boxes": [
        {"name": "b", "model": "aruco_box", "pose": [1.25, 0.0, 0.25, 0.0, 0.0, 0.0]}]}))
    world = WorldSimulation(
        context=ctx,
        parameter_overrides={**SIM, "world": str(path), "slip_enabled": False},
    )
    commander = _Commander(ctx, lambda t: (0.5, 0.0))
    sink = _Sink(ctx)
    for n in (world, commander, sink):
        executor.add_node(n)
    executor.run_until(6.0)
    truth_x = [m.pose.pose.position.x for m in sink.truth]
    assert truth_x[-1] == pytest.approx(1.0 - ROBOT_HALF_EXTENTS[0], abs=1e-6)
    assert truth_x[-1] == truth_x[-20]  # at rest for the last second
    odom = WheelOdometry()
    for js in sink.joints:
        odom.update(js.position[0], js.position[1], _t(js))
    assert odom.x > 2.0  # the wheels never stopped
    assert sink.joints[-1].velocity[0] > 10.0  # rad/s, still commanded


def test_depth_on_the_bus_is_lazy_framed_in_tf_and_sees_the_box_ahead(ctx, executor) -> None:
    """/oak/stereo/depth and its cloud: nothing is rendered while nobody subscribes (counted
    calls); with subscribers, 30 Hz 32FC1 images and organised clouds in
    ``oak_rgb_camera_optical_frame`` (a frame of the TF tree), and the centre pixel reads the
    closed-form depth of box_1's face at x = 2.0 (camera at x = -0.0241) within 5 sigma of the
    stereo noise."""
    from posekit.msgs.image import image_to_numpy
    from posekit.msgs.point_cloud2 import read_points
    from posekit.msgs.sensor_msgs import Image, PointCloud2
    from posekit.robot.depth import DEFAULT_DEPTH

    world = WorldSimulation(
        context=ctx, parameter_overrides={**SIM, "world": "aruco_box_world", "seed": 2}
    )
    calls = []
    real_frame = world.depth_camera.frame
    world.depth_camera.frame = lambda *a: calls.append(a) or real_frame(*a)  # type: ignore[method-assign]
    listener_node, buffer = _tf_listener_beside(world, ctx, executor)
    executor.run_until(0.5)
    assert calls == []
    images: list[Image] = []
    clouds: list[PointCloud2] = []
    listener_node.create_subscription(Image, "oak/stereo/depth", images.append, 10)
    executor.run_until(0.8)
    assert 8 <= len(images) <= 10
    assert len(calls) == len(images)
    listener_node.create_subscription(PointCloud2, "oak/stereo/depth/points", clouds.append, 10)
    executor.run_until(0.9)
    assert 2 <= len(clouds) <= 4
    assert len(calls) == len(images)  # one render serves both topics
    img = images[-1]
    assert (img.encoding, img.width, img.height) == ("32FC1", 1280, 720)
    assert img.header.frame_id == "oak_rgb_camera_optical_frame"
    z = image_to_numpy(img)
    sigma = float(DEFAULT_DEPTH.noise_sigma(2.0241))
    assert z[360, 640] == pytest.approx(2.0241, abs=5 * sigma)
    cloud = clouds[-1]
    assert cloud.header.frame_id == img.header.frame_id
    assert (cloud.height, cloud.width, cloud.point_step) == (720, 1280, 32)
    pts = read_points(cloud, ["x", "y", "z"]).reshape(720, 1280)
    assert pts["z"][360, 640] == pytest.approx(2.0241, abs=5 * sigma)
    t = buffer.lookup_transform("base_link", "oak_rgb_camera_optical_frame", Time())
    assert t.transform.translation.z == pytest.approx(0.1875, abs=1e-9)
