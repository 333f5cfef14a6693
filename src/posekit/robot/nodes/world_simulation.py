"""``world_simulation``: posekit's replacement for Gazebo + ros2_control + robot_state_publisher.

One node steps the simulated ROSbot (:class:`~posekit.robot.drive.RosbotBase`) on the node
clock (sim time under a stepped executor) and publishes what the course's simulation does:

=========================  ==========================  ==========================================
topic                      type                        content
=========================  ==========================  ==========================================
``cmd_vel`` (in)           geometry_msgs/TwistStamped  velocity command (timeout, stale and
                                                       future stamps rejected)
``joint_states``           sensor_msgs/JointState      four wheel joints (``joint_states_rate``)
``imu/data``               sensor_msgs/Imu             frame ``imu_link``, 25 Hz, course noise
``ground_truth/odom``      nav_msgs/Odometry           true pose of base_link in ``odom`` (tests,
                                                       viewer; never used by the controllers)
``scan``                   sensor_msgs/LaserScan       frame ``laser``, 10 Hz, 3000 beams, the
                                                       world's boxes and walls (only while
                                                       subscribed)
``oak/stereo/depth``       sensor_msgs/Image           OAK-D depth, ``32FC1`` metres, 1280x720,
                                                       30 Hz, 1-12 m, frame
                                                       ``oak_rgb_camera_optical_frame`` (only
                                                       while subscribed)
``oak/stereo/depth/points`` sensor_msgs/PointCloud2    the same frame as an organised cloud
                                                       (x, y, z, rgb; only while subscribed)
``/robot_description``     std_msgs/String             the URDF, once, KEEP_LAST 1 TRANSIENT_LOCAL
                                                       (latched, as robot_state_publisher)
``/tf_static``             tf2_msgs/TFMessage          robot's fixed frames + the world's statics
``/tf``                    tf2_msgs/TFMessage          ``body_link -> *_wheel_link`` (wheel spin)
=========================  ==========================  ==========================================

Frames: the course's worlds place everything in ``odom`` coordinates and spawn the robot at
the origin, so posekit has no separate ``world`` frame: ground truth is reported in ``odom``
(``ground_truth_frame_id``) and the world's fixed cameras hang off ``odom`` (the world's
``static_transforms``). A world with a non-zero ``spawn`` starts the robot there; the
scenarios give the same pose to wheel odometry and the EKF as their initial state.

The physics runs at ``update_rate`` (100 Hz, the controller_manager rate): the base is
stepped on the exact 10 ms grid, always up to the current time before anything reads or
changes it. The node has one timer per *output* rate (IMU 40 ms, joint states and ground
truth 50 ms) rather than a 100 Hz timer: at an output time ``t`` it steps the physics up to
``t`` with the commands received before ``t`` and publishes (stamped ``t``); a ``cmd_vel``
arriving at ``t`` first steps the physics up to ``t``, then takes effect from ``t`` on. This
gives the same steps, commands and samples as a 100 Hz timer (tested) with 40 executor
wake-ups per simulated second instead of 100. Every rate must divide the update rate.
Randomness (slip, IMU noise) comes from ``seed`` through
:func:`posekit.robot.headless.sub_seeds`, so a seed gives the same models as the headless
loop.

Parameters (controller names as the course's ``controllers.yaml``; *posekit* ones marked):
``world`` (``empty_world``; a built-in name or a .json/.yaml file), ``seed`` (0),
``update_rate`` (100.0), ``wheel_separation`` (0.186), ``wheel_radius`` (0.0425),
``wheel_separation_multiplier`` (1.36), ``left_wheel_radius_multiplier`` /
``right_wheel_radius_multiplier`` (0.95), ``cmd_vel_timeout`` (0.5),
``linear.x.max_velocity`` (1.0), ``linear.x.max_acceleration`` (1.0),
``angular.z.max_velocity`` (3.14), ``angular.z.max_acceleration`` (4.0); *posekit*:
``imu_rate`` (25.0), ``joint_states_rate`` (20.0; Gazebo's joint_state_broadcaster runs at
100 Hz, see docs/robot.md), ``ground_truth_rate`` (20.0), ``ground_truth_frame_id``
(``odom``), ``slip_enabled`` (true), ``encoder_quantize`` (false),
``publish_world_static_transforms`` (true), ``lidar_rate`` (10.0), ``contact`` (true: the
world's boxes with ``collision`` stop the robot's body, see :mod:`posekit.robot.contact`).
The LiDAR model and its sources are in :mod:`posekit.robot.lidar`; a scan is computed only
when ``scan`` has a subscriber, and its noise depends on the seed and the scan time only.
The depth camera (:mod:`posekit.robot.depth`; *posekit* parameter ``depth_rate``, 30.0 Hz)
renders a frame only when its image or its cloud has a subscriber, from the true pose at the
last physics step (at most one update period old), with noise from the seed and the frame time.
"""

from __future__ import annotations

from collections import deque
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt

from posekit.geometry import Rotation, Transform, wrap_angle
from posekit.msgs.geometry_msgs import TwistStamped
from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.sensor_msgs import Image, Imu, JointState, LaserScan, PointCloud2
from posekit.msgs.std_msgs import Header, String
from posekit.robot._msgutil import covariance_from_diagonal, yaw_quaternion
from posekit.robot.contact import Contact
from posekit.robot.depth import (
    DEFAULT_DEPTH,
    DepthCamera,
    DepthParams,
    depth_cloud,
    depth_image_msg,
)
from posekit.robot.description import (
    T_base_frame,
    robot_description_urdf,
    static_transforms,
    wheel_transforms,
)
from posekit.robot.drive import CommandResult, RosbotBase
from posekit.robot.encoders import WheelEncoders
from posekit.robot.headless import sub_seeds
from posekit.robot.imu import ImuModel
from posekit.robot.lidar import DEFAULT_LIDAR, Lidar, LidarParams
from posekit.robot.nodes._util import NS, declare_wheel_geometry, period_ns
from posekit.robot.params import (
    DEFAULT_DRIVE,
    DEFAULT_IMU,
    DriveParams,
    EncoderParams,
    ImuParams,
    SlipParams,
)
from posekit.runtime.node import Node
from posekit.runtime.parameters import declare_value
from posekit.runtime.qos import DurabilityPolicy, HistoryPolicy, QoSProfile
from posekit.runtime.ratelimit import RateLimitedLog
from posekit.tf2_ros import StaticTransformBroadcaster, TransformBroadcaster
from posekit.time import stamp_from_ns
from posekit.worlds import World, load_world
from posekit.worlds.obstacles import BoxObstacles, WallSegments

__all__ = ["MAX_KEPT_REJECTIONS", "WorldSimulation"]

#: Mixed with the run seed to give the LiDAR its own noise stream.
_LIDAR_STREAM = 0x5CA2
#: ... and the depth camera its own.
_DEPTH_STREAM = 0xDE97

#: Rejected /cmd_vel messages kept in :attr:`WorldSimulation.rejected` (the newest ones).
MAX_KEPT_REJECTIONS = 100


def _ticks(rate_hz: float, update_period_ns: int, what: str) -> int:
    n = period_ns(rate_hz, what) / update_period_ns
    k = round(n)
    if k < 1 or abs(n - k) > 1e-9:
        raise ValueError(
            f"{what} {rate_hz} Hz must divide the update rate ({NS / update_period_ns:g} Hz)"
        )
    return k


class WorldSimulation(Node):
    """The simulated world and ROSbot (see the module docstring for topics and parameters).

    Attributes for tests and tools: ``world`` (the loaded :class:`World`), ``base`` (the
    :class:`RosbotBase`), ``rejected`` (``(t_ns, reason)`` of the last refused commands)
    and ``rejected_count``. Refused commands are logged at most once per second of the node's
    clock, with the number suppressed in between; future-stamped ones once per run of them.
    """

    #: This node simulates the world: a launch running it owns the simulation clock
    #: (:data:`posekit.launch.CLOCK_SOURCE`).
    posekit_clock_source: ClassVar[bool] = True

    def __init__(self, node_name: str = "world_simulation", **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)
        d = DEFAULT_DRIVE
        world_name = str(declare_value(self, "world", "empty_world"))
        seed = int(declare_value(self, "seed", 0))
        update_rate = float(declare_value(self, "update_rate", d.control_rate_hz))
        drive = DriveParams(
            **declare_wheel_geometry(self),
            cmd_vel_timeout=float(declare_value(self, "cmd_vel_timeout", d.cmd_vel_timeout)),
            max_linear_velocity=float(
                declare_value(self, "linear.x.max_velocity", d.max_linear_velocity)
            ),
            max_linear_acceleration=float(
                declare_value(self, "linear.x.max_acceleration", d.max_linear_acceleration)
            ),
            max_angular_velocity=float(
                declare_value(self, "angular.z.max_velocity", d.max_angular_velocity)
            ),
            max_angular_acceleration=float(
                declare_value(self, "angular.z.max_acceleration", d.max_angular_acceleration)
            ),
            control_rate_hz=update_rate,
        )
        imu_rate = float(declare_value(self, "imu_rate", DEFAULT_IMU.rate_hz))
        joint_states_rate = float(declare_value(self, "joint_states_rate", 20.0))
        ground_truth_rate = float(declare_value(self, "ground_truth_rate", 20.0))
        self._gt_frame = str(declare_value(self, "ground_truth_frame_id", d.odom_frame_id))
        slip = SlipParams(enabled=bool(declare_value(self, "slip_enabled", True)))
        encoders = EncoderParams(quantize=bool(declare_value(self, "encoder_quantize", False)))
        publish_world_statics = bool(declare_value(self, "publish_world_static_transforms", True))
        lidar_rate = float(declare_value(self, "lidar_rate", DEFAULT_LIDAR.rate_hz))
        contact_enabled = bool(declare_value(self, "contact", True))
        depth_rate = float(declare_value(self, "depth_rate", DEFAULT_DEPTH.rate_hz))

        #: The loaded world (WorldError from the loader names the problem).
        self.world: World = load_world(world_name)
        self._period_ns = period_ns(update_rate, "update_rate")
        self._dt = self._period_ns / NS
        self._n_imu = _ticks(imu_rate, self._period_ns, "imu_rate")
        self._n_joints = _ticks(joint_states_rate, self._period_ns, "joint_states_rate")
        self._n_truth = _ticks(ground_truth_rate, self._period_ns, "ground_truth_rate")
        self._n_lidar = _ticks(lidar_rate, self._period_ns, "lidar_rate")

        slip_seed, imu_seed, _ = sub_seeds(seed)
        sx, sy, syaw = self.world.spawn
        #: The simulated base (ground truth and wheel joints).
        solid = [b.collision for b in self.world.boxes] + [w.collision for w in self.world.walls]
        contact = (
            Contact(
                BoxObstacles.from_world(self.world, collision_only=True),
                WallSegments.from_world(self.world, collision_only=True),
            )
            if contact_enabled and any(solid)
            else None
        )
        self.base = RosbotBase(
            drive, slip, seed=slip_seed, x=sx, y=sy, yaw=syaw, contact=contact
        )
        self._encoders = WheelEncoders(encoders)
        self._imu = ImuModel(ImuParams(rate_hz=imu_rate), seed=imu_seed)
        lidar_seed = int(np.random.SeedSequence([seed, _LIDAR_STREAM]).generate_state(1)[0])
        #: The simulated LiDAR (its obstacles are every box of the world).
        self.lidar = Lidar(
            BoxObstacles.from_world(self.world),
            LidarParams(rate_hz=lidar_rate),
            seed=lidar_seed,
            walls=WallSegments.from_world(self.world),
        )
        self._T_base_laser = T_base_frame(self.lidar.params.frame_id)
        depth_seed = int(np.random.SeedSequence([seed, _DEPTH_STREAM]).generate_state(1)[0])
        #: The simulated OAK-D depth camera (boxes, walls and the ground).
        self.depth_camera = DepthCamera(self.world, DepthParams(rate_hz=depth_rate),
                                        seed=depth_seed)
        self._T_base_depth = T_base_frame(self.depth_camera.params.frame_id)
        #: ``(t_ns, reason)`` of the last :data:`MAX_KEPT_REJECTIONS` rejected /cmd_vel
        #: messages (a peer can send any number); :attr:`rejected_count` counts them all.
        self.rejected: deque[tuple[int, str]] = deque(maxlen=MAX_KEPT_REJECTIONS)
        self.rejected_count = 0
        # One warning per second of the node's clock, with the number suppressed meanwhile.
        self._warn_rejected = RateLimitedLog(
            self.get_logger().warning, clock=lambda: self._now_ns() / NS
        )
        self._future_warned = False

        self._cmd_sub = self.create_subscription(TwistStamped, "cmd_vel", self._on_cmd_vel, 10)
        self._joint_pub = self.create_publisher(JointState, "joint_states", 10)
        self._imu_pub = self.create_publisher(Imu, "imu/data", 10)
        self._truth_pub = self.create_publisher(Odometry, "ground_truth/odom", 10)
        self._scan_pub = self.create_publisher(LaserScan, "scan", 10)
        self._depth_pub = self.create_publisher(Image, "oak/stereo/depth", 10)
        self._points_pub = self.create_publisher(PointCloud2, "oak/stereo/depth/points", 10)
        self._tf = TransformBroadcaster(self)
        self._tf_static = StaticTransformBroadcaster(self)

        clock = self.get_clock()
        self._now_ns = clock.now_ns
        #: Time (ns) the physics has been stepped to: a multiple of the control period.
        self._sim_ns = clock.now_ns()
        statics = static_transforms(self._sim_ns / NS)
        if publish_world_statics:
            statics += self._world_static_transforms(self._sim_ns)
        self._tf_static.sendTransform(statics)
        # robot_state_publisher's /robot_description: latched for late joiners.
        latched = QoSProfile(
            depth=1, history=HistoryPolicy.KEEP_LAST, durability=DurabilityPolicy.TRANSIENT_LOCAL
        )
        self._description_pub = self.create_publisher(String, "/robot_description", latched)
        self._description_pub.publish(String(data=robot_description_urdf()))

        # Reused message objects: the bus copies on publish, so editing them later is safe.
        self._truth_msg = Odometry()
        self._truth_msg.header.frame_id = self._gt_frame
        self._truth_msg.child_frame_id = d.base_frame_id
        self._truth_msg.pose.covariance = covariance_from_diagonal((0.0,) * 6)
        self._truth_msg.twist.covariance = covariance_from_diagonal((0.0,) * 6)
        # One timer per output period; the physics catches up lazily (see _advance_to).
        outputs: dict[int, list[Any]] = {}
        for n, publish in (
            (self._n_imu, self._publish_imu),
            (self._n_joints, self._publish_joints),
            (self._n_truth, self._publish_truth),
            (self._n_lidar, self._publish_scan),
        ):
            outputs.setdefault(n * self._period_ns, []).append(publish)
        for out_period_ns, publishers in sorted(outputs.items()):
            self.create_timer(out_period_ns / NS, self._make_output_callback(publishers))
        # The depth rate (30 Hz) need not divide the update rate: its own timer.
        self.create_timer(1.0 / depth_rate, self._make_output_callback([self._publish_depth]))
        self.get_logger().info(
            f"world '{self.world.name}' ({len(self.world.boxes)} boxes, "
            f"{len(self.world.cameras)} cameras), ROSbot at ({sx:.2f}, {sy:.2f}, {syaw:.2f}), "
            f"seed {seed}"
        )

    def _world_static_transforms(self, t_ns: int) -> list[Any]:
        from posekit.msgs.geometry_msgs import Quaternion, TransformStamped, Vector3

        out = []
        for spec in self.world.static_transforms:
            tf = TransformStamped()
            tf.header.stamp = stamp_from_ns(t_ns)
            tf.header.frame_id = spec.parent
            tf.child_frame_id = spec.child
            tf.transform.translation = Vector3(x=spec.xyz[0], y=spec.xyz[1], z=spec.xyz[2])
            qx, qy, qz, qw = spec.quaternion_xyzw
            tf.transform.rotation = Quaternion(x=qx, y=qy, z=qz, w=qw)
            out.append(tf)
        return out

    # ------------------------------------------------------------------ callbacks
    def _on_cmd_vel(self, msg: TwistStamped) -> None:
        now_ns = self._now_ns()
        self._advance_to(now_ns)
        result: CommandResult = self.base.submit(msg, now_ns / NS)
        if not result.accepted:
            self.rejected.append((now_ns, result.reason))
            self.rejected_count += 1
            if result.kind != "future":
                self._warn_rejected("Rejected cmd_vel", result.reason)
            elif not self._future_warned:  # one line per run of future-stamped commands
                self._future_warned = True
                self.get_logger().warning(
                    f"Rejected cmd_vel: {result.reason}; further future-stamped commands are "
                    "ignored silently until a valid one arrives"
                )
            return
        self._future_warned = False
        if result.reason:
            self.get_logger().warning(f"cmd_vel: {result.reason}", once=True)

    def _advance_to(self, now_ns: int) -> None:
        """Step the base at the control period up to ``now_ns`` (never past it)."""
        sim_ns = self._sim_ns
        if now_ns < sim_ns:
            # The clock jumped back: continue the physics from the new time.
            self._sim_ns = now_ns
            return
        period = self._period_ns
        if now_ns - sim_ns < period:
            return
        step = self.base.step
        dt = self._dt
        while sim_ns + period <= now_ns:
            step(sim_ns / NS, dt)
            sim_ns += period
        self._sim_ns = sim_ns

    def _make_output_callback(self, publishers: list[Any]) -> Any:
        def on_output() -> None:
            now_ns = self._now_ns()
            self._advance_to(now_ns)
            for publish in publishers:
                publish(now_ns)

        return on_output

    # ------------------------------------------------------------------ sensors
    def _publish_imu(self, now_ns: int) -> None:
        v, w, ax = self.base.body_velocity
        yaw = self.base.pose[2]
        reading = self._imu.sample(now_ns / NS, yaw, w, ax, v * w)
        self._imu_pub.publish_transfer(self._imu.to_msg(reading))  # fresh: no copy

    def _publish_joints(self, now_ns: int) -> None:
        left, right = self.base.wheel_angles
        positions = (left, right, left, right)
        msg = self._encoders.joint_state(positions, self.base.wheel_velocities, now_ns / NS)
        msg.header.stamp = stamp_from_ns(now_ns)
        self._joint_pub.publish_transfer(msg)  # fresh: no copy
        if self._tf.pub_tf.get_subscription_count():
            self._tf.sendTransform(wheel_transforms(positions, now_ns / NS))

    def _publish_truth(self, now_ns: int) -> None:
        if not self._truth_pub.get_subscription_count():
            return
        x, y, yaw = self.base.pose
        v, w, _ = self.base.body_velocity
        msg = self._truth_msg
        msg.header.stamp = stamp_from_ns(now_ns)
        pose = msg.pose.pose
        pose.position.x = x
        pose.position.y = y
        pose.orientation = yaw_quaternion(wrap_angle(yaw))
        msg.twist.twist.linear.x = v
        msg.twist.twist.angular.z = w
        self._truth_pub.publish(msg)

    def _publish_scan(self, now_ns: int) -> None:
        if not self._scan_pub.get_subscription_count():
            return  # lazy: no subscriber, no ray casting
        msg = self.laser_scan(now_ns)
        self._scan_pub.publish_transfer(msg)  # fresh: no copy

    def laser_scan(self, t_ns: int) -> LaserScan:
        """The LaserScan of the robot's current true pose, stamped ``t_ns``."""
        x, y, yaw = self.base.pose
        T_world_base = Transform(Rotation.from_rpy(0.0, 0.0, yaw), (x, y, 0.0))
        scan_index = round(t_ns / (self._n_lidar * self._period_ns))
        ranges = self.lidar.scan(T_world_base * self._T_base_laser, scan_index)
        msg = self.lidar.to_msg(ranges)
        msg.header.stamp = stamp_from_ns(t_ns)
        return msg

    def _publish_depth(self, now_ns: int) -> None:
        want_image = self._depth_pub.get_subscription_count() > 0
        want_points = self._points_pub.get_subscription_count() > 0
        if not (want_image or want_points):
            return  # lazy: no subscriber, no rendering
        depth = self.depth_frame(now_ns)
        header = Header(stamp=stamp_from_ns(now_ns), frame_id=self.depth_camera.params.frame_id)
        if want_image:
            self._depth_pub.publish_transfer(depth_image_msg(depth, header))
        if want_points:
            self._points_pub.publish_transfer(depth_cloud(depth, self.depth_camera.params, header))

    def depth_frame(self, t_ns: int) -> npt.NDArray[np.float32]:
        """The depth image (H, W) float32 m of the robot's current true pose at ``t_ns``."""
        x, y, yaw = self.base.pose
        T_world_base = Transform(Rotation.from_rpy(0.0, 0.0, yaw), (x, y, 0.0))
        frame_index = round(t_ns * self.depth_camera.params.rate_hz / NS)
        T = (T_world_base * self._T_base_depth).as_matrix()
        return self.depth_camera.frame(T, frame_index)

    @property
    def true_pose(self) -> tuple[float, float, float]:
        """Ground truth ``(x, y, yaw)`` of base_link in odom now (yaw wrapped to [-pi, pi))."""
        x, y, yaw = self.base.pose
        return x, y, wrap_angle(yaw)
