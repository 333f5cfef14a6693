"""The viewer's data taps: what the browser page shows, gathered from a running system.

A :class:`ViewerTap` listens on a :class:`~posekit.runtime.transport.Transport` (the
in-process bus of a launch/scenario, or Zenoh for other processes) *without a node in any
executor*: its sinks are called directly by the transport on the publisher's thread (or the
transport's receive thread), so attaching a viewer never adds callbacks to a simulated run
and never changes its order of events. Each sink does the minimum (store a reference, feed
the tf2 buffer, count) under one lock; the server thread reads snapshots at its own pace.

What is tapped (topics are matched fully qualified):

* ``/tf`` and ``/tf_static`` (tf2_msgs/TFMessage) into a :class:`posekit.tf2.Buffer`, plus
  per frame: parent, last stamp, update rate from the stamps (tf2's ``allFramesAsYAML``
  rate: samples per stamp span), static or not; with TransformListener's guards: ``/tf``
  stamps more than 10 s ahead of the run's clock (``clock_ns``, else ``/clock``, else the
  wall clock) are ignored (one warning per second), and at most :data:`MAX_FRAMES` frames
  are kept (least recently updated forgotten);
* ``/clock`` (rosgraph_msgs/Clock): "now" for frame ages when a run is on sim time, else the
  wall clock; a backward jump of the clock (a restarted run) clears the tf buffer;
* Odometry displays (nav_msgs/Odometry): :data:`ODOMETRY_TOPICS` by default; each keeps the
  last ``trail_length`` poses that moved more than RViz2's Odometry display tolerances
  (0.1 m or 0.1 rad) from the previous kept pose, with the speed ``|v|`` for the arrow
  length;
* ``/goal_pose`` (geometry_msgs/PoseStamped): the current goal (the newest message with
  finite values), drawn as an arrow in its header frame;
* the ``sensor_msgs/Image`` topics a page shows (:meth:`ViewerTap.set_image_watches`): the
  newest message only (a reference; the in-process bus shares the frozen pixel array, so
  this costs nothing); JPEG encoding happens in the server, only for topics a client
  watches;
* every topic: the newest message (a reference), and for the topics the page's displays
  follow (:meth:`ViewerTap.set_message_watches`) the newest messages in a
  :class:`~posekit.viewer.display_feed.MessageQueue`, seeded with the newest message received
  before the display was added;
* every topic: receive rate over the last :data:`RATE_WINDOW_S` seconds (what ``ros2 topic
  hz`` prints by default) of the clock the data uses: sim time when the run is on it (the
  ``clock_ns`` given, or ``/clock``), else the wall clock. A camera publishing at 30 Hz of
  sim time reads 30 Hz even when the simulation runs below real time;
* time (:meth:`ViewerTap.time_state`): sim time, wall time and the real-time factor
  measured over the last :data:`RTF_WINDOW_S` s of wall time.

Topics are discovered and subscribed by a :class:`posekit.runtime.observe.TopicObserver`
(call :meth:`refresh` periodically): the tap subscribes only to topics that have a
publisher, so it never creates a topic of its own in the graph, with a QoS every publisher
matches (transient local when every publisher is: the latched ``/tf_static``), to at most
:data:`MAX_SUBSCRIBED_TOPICS` of them (the others are listed with the reason); a topic whose
publishers leave is unsubscribed, and leaves the topic panel when it leaves the graph.
Topics of the :data:`ON_DEMAND_TYPES` (images and point clouds) are subscribed only while a
page shows them: a display follows the topic (:meth:`set_message_watches`) or, for images,
an Image or Camera display or an open image panel watches it (:meth:`set_image_watches`),
as RViz2's displays subscribe only while enabled. A simulated sensor renders only for
subscribers: the OAK-D's depth image costs a quarter to a half of its 30 Hz frame period,
its cloud about a third more.
"""

from __future__ import annotations

import math
import threading
import time
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Any

from posekit.msgs.errors import UnknownMessageTypeError
from posekit.msgs.registry import find_message_class
from posekit.runtime.logging import RcutilsLogger, get_logger
from posekit.runtime.observe import ObservedTopic, TopicObserver
from posekit.runtime.ratelimit import RateLimitedLog
from posekit.runtime.transport import MessageSink, Transport
from posekit.tf2 import Buffer, TransformException
from posekit.tf2_ros.transform_listener import DEFAULT_MAX_FRAMES, DEFAULT_MAX_FUTURE
from posekit.time import NS_PER_S, Duration, stamp_to_ns
from posekit.viewer.display_feed import MessageQueue

__all__ = [
    "GOAL_TOPIC",
    "GROUND_TRUTH_TOPIC",
    "IMAGE_TYPE",
    "ODOMETRY_TOPICS",
    "RATE_WINDOW_S",
    "RTF_WINDOW_S",
    "FrameInfo",
    "OdometryTrail",
    "TopicInfo",
    "ViewerTap",
]

NS = NS_PER_S
TF_TYPE = "tf2_msgs/msg/TFMessage"
ODOM_TYPE = "nav_msgs/msg/Odometry"
IMAGE_TYPE = "sensor_msgs/msg/Image"
CLOCK_TYPE = "rosgraph_msgs/msg/Clock"
POSE_STAMPED_TYPE = "geometry_msgs/msg/PoseStamped"
#: The goal display's topic (what RViz2's "2D Goal Pose" tool publishes on).
GOAL_TOPIC = "/goal_pose"
#: Odometry displays shown by default (RViz2 config of the lecture) and the simulator's truth.
ODOMETRY_TOPICS = ("/odometry/filtered", "/odometry/wheels")
GROUND_TRUTH_TOPIC = "/ground_truth/odom"
#: Window (s of the data's clock) of the per-topic receive rate.
RATE_WINDOW_S = 2.0
#: Window (s of wall time) over which the real-time factor is measured.
RTF_WINDOW_S = 3.0
#: RViz2 Odometry display defaults: keep a new arrow only past these tolerances.
TRAIL_POSITION_TOLERANCE_M = 0.1
TRAIL_ANGLE_TOLERANCE_RAD = 0.1
#: A clock jump backwards larger than this (ns) clears the buffer (restarted run / bag loop).
_BACKWARD_JUMP_NS = NS // 2
#: Stamps kept per frame for its rate.
_FRAME_STAMPS = 100
#: Frames shown at most; beyond that the least recently updated are forgotten (a peer can
#: announce any number of frames).
MAX_FRAMES = DEFAULT_MAX_FRAMES
#: Topics the tap subscribes to at most (each costs a subscription; a peer can announce any
#: number): /tf, /tf_static, /clock and the odometry displays first, then graph order.
MAX_SUBSCRIBED_TOPICS = 200
#: Types subscribed only while a page shows the topic (listed in the panel meanwhile).
ON_DEMAND_TYPES = frozenset({"sensor_msgs/msg/PointCloud2", IMAGE_TYPE})
#: The topic panel's note for such a topic while no display follows it.
ON_DEMAND_NOTE = "subscribed while a display shows it"
#: /tf stamps further ahead of "now" are ignored (as TransformListener does).
_MAX_FUTURE_NS = DEFAULT_MAX_FUTURE.nanoseconds


@dataclass
class FrameInfo:
    """What the TF tree panel shows about one frame (the rqt_tf_tree / view_frames fields)."""

    name: str
    parent: str
    static: bool
    stamps_ns: deque[int] = field(default_factory=lambda: deque(maxlen=_FRAME_STAMPS))

    @property
    def last_stamp_ns(self) -> int:
        """Stamp of the newest transform received (ns)."""
        return self.stamps_ns[-1] if self.stamps_ns else 0

    def rate_hz(self) -> float:
        """Updates per second of stamp time (0 for static frames or a single sample)."""
        if self.static or len(self.stamps_ns) < 2:
            return 0.0
        span = self.stamps_ns[-1] - self.stamps_ns[0]
        return (len(self.stamps_ns) - 1) * NS / span if span > 0 else 0.0


@dataclass
class TopicInfo:
    """One topic of the graph as the topic panel lists it."""

    name: str
    type_name: str
    receipts: deque[float] = field(default_factory=deque)
    #: The clock ``receipts`` are on ("sim" or "wall"); a change restarts the rate.
    clock: str = "wall"
    count: int = 0
    subscribed: bool = False
    error: str = ""

    def rate_hz(self, now: float) -> float:
        """Messages per second over the last :data:`RATE_WINDOW_S` s before ``now``.

        ``now`` is in s, on the clock of ``receipts``.
        """
        r = self.receipts
        while r and (now - r[0] > RATE_WINDOW_S or r[0] > now):
            r.popleft()
        if len(r) < 2:
            return 0.0
        span = r[-1] - r[0]
        return (len(r) - 1) / span if span > 0 else 0.0


@dataclass
class OdometryTrail:
    """The kept poses of one Odometry display, in the message's ``header.frame_id``.

    Each entry is ``(x, y, z, qx, qy, qz, qw, speed)``: position (m), orientation of the
    child frame as a quaternion (x, y, z, w), and ``|twist.linear|`` (m/s).
    """

    topic: str
    frame_id: str = ""
    child_frame_id: str = ""
    poses: deque[tuple[float, ...]] = field(default_factory=deque)
    received: int = 0
    version: int = 0

    def add(self, pose: tuple[float, ...], frame_id: str, child: str, maxlen: int) -> None:
        """Append ``pose`` unless it is within the tolerances of the last kept pose."""
        self.received += 1
        if frame_id != self.frame_id:
            self.poses.clear()  # a trail in two frames would be meaningless
            self.frame_id = frame_id
        self.child_frame_id = child
        if self.poses:
            last = self.poses[-1]
            moved = math.dist(last[:3], pose[:3])
            dot = abs(sum(a * b for a, b in zip(last[3:7], pose[3:7], strict=True)))
            turned = 2.0 * math.acos(min(1.0, dot))
            if moved < TRAIL_POSITION_TOLERANCE_M and turned < TRAIL_ANGLE_TOLERANCE_RAD:
                # Keep the arrow where it is but show the current speed.
                self.poses[-1] = (*last[:7], pose[7])
                self.version += 1
                return
        self.poses.append(pose)
        while len(self.poses) > maxlen:
            self.poses.popleft()
        self.version += 1


def _resolve_class(type_name: str) -> type:
    """The class for a ROS type name: posekit's registry, else rosbags' typestore.

    Raises LookupError if neither knows it. Type names come from other peers, so nothing is ever
    imported by name here.
    """
    try:
        return find_message_class(type_name)
    except UnknownMessageTypeError:
        raise LookupError(f"unknown message type {type_name!r}") from None


class ViewerTap:
    """Listens on a transport and keeps what the viewer shows (see the module docstring).

    Args:
        transport: the transport of the system to view (``context.transport()``).
        odometry_topics: Odometry displays (fully qualified names).
        ground_truth_topic: the simulator's true pose (nav_msgs/Odometry), drawn separately.
        trail_length: poses kept per Odometry display (RViz2's "Keep", default 100).
        tf_cache_time: seconds of /tf history kept in the buffer.
        clock_ns: "now" in ns for frame ages (in process: the SimulatedTimeExecutor's
            ``now_ns``); default: see :meth:`now_ns`.
    """

    def __init__(
        self,
        transport: Transport,
        *,
        odometry_topics: Iterable[str] = ODOMETRY_TOPICS,
        ground_truth_topic: str | None = GROUND_TRUTH_TOPIC,
        trail_length: int = 100,
        tf_cache_time: float = 10.0,
        logger: RcutilsLogger | None = None,
        clock_ns: Callable[[], int] | None = None,
    ) -> None:
        if trail_length < 1:
            raise ValueError(f"trail_length must be >= 1, got {trail_length}")
        self.transport = transport
        self.logger = logger or get_logger("posekit_viewer")
        self.trail_length = int(trail_length)
        self.odometry_topics = tuple(odometry_topics)
        self.ground_truth_topic = ground_truth_topic
        self.buffer = Buffer(cache_time=Duration(seconds=tf_cache_time))
        self._lock = threading.Lock()
        self._frames: dict[str, FrameInfo] = {}
        self._topics: dict[str, TopicInfo] = {}
        # The topics the page draws first: a graph with endless topics must not crowd them out.
        shown = {"/tf", "/tf_static", "/clock", GOAL_TOPIC, *self.odometry_topics}
        if ground_truth_topic:
            shown.add(ground_truth_topic)
        self._observer = TopicObserver(
            transport, self._sink_for, on_removed=self._unsubscribed,
            on_skipped=self._not_shown, select=self._wanted, node_name="posekit_viewer",
            depth=1,
            max_topics=MAX_SUBSCRIBED_TOPICS, priority=shown, resolve=_resolve_class,
            logger=self.logger,
        )
        self._trails: dict[str, OdometryTrail] = {}
        self._images: dict[str, tuple[int, Any]] = {}
        self._latest: dict[str, Any] = {}
        self._queues: dict[str, MessageQueue] = {}
        #: Image topics a page shows (see :meth:`set_image_watches`).
        self._image_watches: frozenset[str] = frozenset()
        self._goal: dict[str, Any] | None = None
        self._clock_ns: int | None = None
        self._clock_fn = clock_ns
        # Newest stamp seen on /tf and when (monotonic s): "now" when there is no clock.
        self._newest_stamp: tuple[int, float] | None = None
        # (monotonic s, sim ns) samples for the real-time factor.
        self._rtf_samples: deque[tuple[float, int]] = deque(maxlen=256)
        self._tf_version = 0
        self._closed = False
        #: Number of transforms the tf2 buffer refused (logged once each by reason).
        self.rejected_transforms = 0
        #: Data problems (non-finite poses, bad messages): one line per second per reason.
        self._warn = RateLimitedLog(self.logger.warning)

    # -- discovery -------------------------------------------------------------------------
    def refresh(self) -> None:
        """Follow the graph.

        List its topics, subscribe to new ones that have a publisher, let go of those whose
        publishers left.
        """
        if self._closed:
            return
        self._observer.refresh()
        graph = self._observer.graph()
        skipped = self._observer.skipped
        names = {name for name, _ in graph}
        with self._lock:
            for name, type_name in graph:
                info = self._topics.get(name)
                if info is None or (info.type_name != type_name and not info.subscribed):
                    info = self._topics[name] = TopicInfo(name, type_name)
                if not info.subscribed:
                    info.error = skipped.get(name, "") or (
                        ON_DEMAND_NOTE if type_name in ON_DEMAND_TYPES else "")
            for name in [n for n, i in self._topics.items()
                         if n not in names and not i.subscribed]:
                del self._topics[name]

    def _topic_info(self, name: str, type_name: str) -> TopicInfo:
        with self._lock:
            info = self._topics.get(name)
            if info is None or info.type_name != type_name:
                info = self._topics[name] = TopicInfo(name, type_name)
            return info

    def _sink_for(self, observed: ObservedTopic) -> MessageSink:
        info = self._topic_info(observed.name, observed.type_name)
        info.subscribed, info.error = True, ""
        return self._make_sink(info)

    def _wanted(self, topic: str, type_name: str) -> bool:
        """Whether the observer subscribes ``topic`` (on-demand types: while a page shows it)."""
        if type_name not in ON_DEMAND_TYPES:
            return True
        with self._lock:
            return topic in self._queues or topic in self._image_watches

    def _on_demand_followed(self) -> set[str]:
        """The on-demand topics a page shows now (call with the lock held)."""
        return {t for t in (*self._queues, *self._image_watches)
                if (info := self._topics.get(t)) is not None
                and info.type_name in ON_DEMAND_TYPES}

    def _follow(self, before: set[str]) -> None:
        """Let go of the on-demand topics followed ``before`` and no more; subscribe new ones."""
        with self._lock:
            after = self._on_demand_followed()
            for topic in before - after:
                if topic in self._images:  # a later watch starts with a new image
                    self._images[topic] = (self._images[topic][0], None)
        for topic in before - after:
            self._observer.release(topic)
        if before != after:
            self.refresh()  # subscribe the newly shown ones now

    def _unsubscribed(self, topic: str) -> None:
        with self._lock:
            info = self._topics.get(topic)
            if info is not None:
                info.subscribed = False

    def _not_shown(self, topic: str, reason: str) -> None:
        """A topic the observer does not subscribe; its reason shows in the topic panel.

        Set by :meth:`refresh`; a type conflict is worth a log line too.
        """
        if not reason.startswith(("unknown message type", "not subscribed")):
            self.logger.warning(f"viewer: not showing {topic}: {reason}")

    def _topic_handler(self, info: TopicInfo) -> Callable[[Any], None] | None:
        """What the viewer does with a topic's messages besides counting them, if anything.

        TF, clock, odometry, goal and image topics each have their handler.
        """
        handler: Callable[[Any], None] | None = None
        name = info.name
        if info.type_name == TF_TYPE and name in ("/tf", "/tf_static"):
            is_static = name == "/tf_static"

            def handler(msg: Any) -> None:
                self._on_tf(msg, is_static)
        elif info.type_name == CLOCK_TYPE and name == "/clock":
            handler = self._on_clock
        elif info.type_name == ODOM_TYPE and (
            name in self.odometry_topics or name == self.ground_truth_topic
        ):
            def handler(msg: Any) -> None:
                self._on_odometry(name, msg)
        elif info.type_name == POSE_STAMPED_TYPE and name == GOAL_TOPIC:
            handler = self._on_goal
        elif info.type_name == IMAGE_TYPE:
            def handler(msg: Any) -> None:
                with self._lock:
                    seq = self._images.get(name, (0, None))[0] + 1
                    self._images[name] = (seq, msg)
        return handler

    def _make_sink(self, info: TopicInfo) -> Callable[[Any], None]:
        """The subscription callback of a topic: counts, rates, latest message, handler."""
        handler = self._topic_handler(info)
        name = info.name

        def sink(msg: Any) -> None:
            if self._closed:
                return
            clock, now = self._data_time()
            with self._lock:
                info.count += 1
                if info.clock != clock:
                    info.clock = clock
                    info.receipts.clear()
                info.receipts.append(now)
                if len(info.receipts) > 4096:  # bounded even without readers
                    info.receipts.popleft()
                self._latest[name] = msg
                queue = self._queues.get(name)
            if queue is not None:
                queue.append(msg)
            if handler is not None:
                try:
                    handler(msg)
                except Exception as exc:  # malformed input: log, keep running
                    self.logger.warning(
                        f"viewer: bad message on {name}: {type(exc).__name__}: {exc}",
                        throttle_duration_sec=5.0,
                    )

        return sink

    # -- sinks ------------------------------------------------------------------------------
    def _on_tf(self, msg: Any, is_static: bool) -> None:
        horizon = None
        if not is_static:
            # The run's clock if there is one, else the wall clock (not now_ns()'s guess
            # from the stamps themselves, which a sample could steer).
            if self._clock_fn is not None:
                now = int(self._clock_fn())
            elif self._clock_ns is not None:
                now = self._clock_ns
            else:
                now = time.time_ns()
            horizon = now + _MAX_FUTURE_NS if now > 0 else None
        stale: list[str] = []
        for t in msg.transforms:
            if horizon is not None and stamp_to_ns(t.header.stamp) > horizon:
                # What TransformListener does: one sample stamped years ahead would make
                # every later real sample of the frame TF_OLD_DATA in the buffer.
                self.rejected_transforms += 1
                self._warn("viewer: ignoring transforms stamped far in the future",
                           f"frame {t.child_frame_id[:120]!r}")
                continue
            if is_static:
                ok = self.buffer.set_transform_static(t, "posekit_viewer")
            else:
                ok = self.buffer.set_transform(t, "posekit_viewer")
            if not ok:
                self.rejected_transforms += 1
                continue
            child = t.child_frame_id.lstrip("/")
            with self._lock:
                info = self._frames.pop(child, None)  # re-inserted last: least recent first
                if info is None or info.static != is_static:
                    info = FrameInfo(child, "", is_static)
                self._frames[child] = info
                if len(self._frames) > MAX_FRAMES:
                    for _ in range(MAX_FRAMES // 10):
                        stale.append(self._frames.pop(next(iter(self._frames))).name)
                info.parent = t.header.frame_id.lstrip("/")
                stamp = stamp_to_ns(t.header.stamp)
                if not is_static and (
                    self._newest_stamp is None or stamp > self._newest_stamp[0]
                ):
                    self._newest_stamp = (stamp, time.monotonic())
                if not info.stamps_ns or stamp != info.stamps_ns[-1]:
                    info.stamps_ns.append(stamp)
                self._tf_version += 1
        if stale:
            self.buffer.forget_frames(stale)

    def _on_clock(self, msg: Any) -> None:
        ns = stamp_to_ns(msg.clock)
        jumped = self._clock_ns is not None and ns < self._clock_ns - _BACKWARD_JUMP_NS
        self._clock_ns = ns
        if jumped:
            self.buffer.clear()
            with self._lock:
                for info in self._frames.values():
                    if not info.static:
                        info.stamps_ns.clear()
                for trail in self._trails.values():
                    trail.poses.clear()
                    trail.version += 1

    def _on_odometry(self, topic: str, msg: Any) -> None:
        p = msg.pose.pose.position
        q = msg.pose.pose.orientation
        v = msg.twist.twist.linear
        pose = (
            float(p.x), float(p.y), float(p.z),
            float(q.x), float(q.y), float(q.z), float(q.w),
            math.sqrt(float(v.x) ** 2 + float(v.y) ** 2 + float(v.z) ** 2),
        )
        if not all(math.isfinite(x) for x in pose):
            raise ValueError(f"non-finite pose or twist {pose}")
        with self._lock:
            trail = self._trails.get(topic)
            if trail is None:
                trail = self._trails[topic] = OdometryTrail(topic)
            trail.add(pose, msg.header.frame_id.lstrip("/"), msg.child_frame_id, self.trail_length)

    def _on_goal(self, msg: Any) -> None:
        p, q = msg.pose.position, msg.pose.orientation
        values = [float(v) for v in (p.x, p.y, p.z, q.x, q.y, q.z, q.w)]
        if not all(math.isfinite(v) for v in values):
            self._warn("viewer: goal not drawn (non-finite pose)", GOAL_TOPIC)
            return
        goal = {"frame": msg.header.frame_id.lstrip("/") or "odom", "pose": values,
                "stamp": stamp_to_ns(msg.header.stamp) / NS}
        with self._lock:
            self._goal = goal

    # -- snapshots for the server -----------------------------------------------------------
    def goal(self) -> dict[str, Any] | None:
        """The current goal from the newest ``/goal_pose``, or None.

        ``{frame, pose: [x, y, z, qx, qy, qz, qw], stamp}`` (m, quaternion, s).
        """
        with self._lock:
            return None if self._goal is None else dict(self._goal)

    def now_ns(self) -> int:
        """"Now" (ns) for frame ages.

        The ``clock_ns`` given, else ``/clock`` when the system publishes it, else the wall
        clock; but when the newest /tf stamp is more than an hour away from the wall clock (sim
        time without /clock), that stamp plus the wall time elapsed since it arrived.
        """
        if self._clock_fn is not None:
            return int(self._clock_fn())
        if self._clock_ns is not None:
            return self._clock_ns
        wall = time.time_ns()
        newest = self._newest_stamp
        if newest is not None and abs(wall - newest[0]) > 3600 * NS:
            return newest[0] + int((time.monotonic() - newest[1]) * NS)
        return wall

    @property
    def tf_version(self) -> int:
        """Increases with every transform stored (lets the server skip unchanged sends)."""
        return self._tf_version

    def frames_in(self, fixed_frame: str) -> tuple[str | None, list[list[Any]]]:
        """Pose of every frame in ``fixed_frame`` at the latest common time.

        Returns ``(error, rows)``: ``error`` is a message when ``fixed_frame`` does not exist
        (yet), else None; each row is ``[name, parent, x, y, z, qx, qy, qz, qw, age_s,
        static, ok]`` with the pose of ``name`` in ``fixed_frame`` (T_fixed_name; zeros and
        ``ok`` false when it cannot be looked up, e.g. another tree) and the age of its
        newest transform (s, by :meth:`now_ns`).
        """
        now = self.now_ns()
        with self._lock:
            frames = {n: (f.parent, f.static, f.last_stamp_ns) for n, f in self._frames.items()}
        names = set(frames)
        names.update(p for p, _, _ in frames.values() if p)
        if fixed_frame not in names:
            if not names:
                return f"No tf data. Fixed Frame [{fixed_frame}] does not exist", []
            error: str | None = f"Fixed Frame [{fixed_frame}] does not exist"
        else:
            error = None
        rows: list[list[Any]] = []
        for name in sorted(names):
            parent, static, stamp = frames.get(name, ("", True, 0))
            age = 0.0 if static or name not in frames else max(0.0, (now - stamp) / NS)
            pose: list[float] = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]
            ok = False
            if error is None:
                try:
                    t = self.buffer.lookup_transform_core(fixed_frame, name, 0)
                except TransformException:
                    pass
                else:
                    tr, rot = t.transform.translation, t.transform.rotation
                    pose = [tr.x, tr.y, tr.z, rot.x, rot.y, rot.z, rot.w]
                    ok = True
            if ok and not all(math.isfinite(v) for v in pose):
                # inf/NaN (an infinite static, or finite ones composing past 1e308): shown
                # as not available; JSON has no such numbers and the page could not draw it.
                pose, ok = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0], False
                self._warn("viewer: non-finite pose not shown",
                           f"{name} in {fixed_frame}")
            rows.append([name, parent, *(round(v, 5) for v in pose), round(age, 3), static, ok])
        return error, rows

    def tree(self) -> list[dict[str, Any]]:
        """The TF tree panel: every frame with its parent, rate (Hz), age (s) and kind."""
        now = self.now_ns()
        with self._lock:
            out = [
                {
                    "name": f.name,
                    "parent": f.parent,
                    "rate": round(f.rate_hz(), 2),
                    "age": None if f.static else round(max(0.0, (now - f.last_stamp_ns) / NS), 3),
                    "static": f.static,
                }
                for f in self._frames.values()
            ]
        return sorted(out, key=lambda d: d["name"])

    def _sim_ns(self) -> int | None:
        """Sim time (ns): the ``clock_ns`` given, else the newest ``/clock``.

        None on the wall clock.
        """
        if self._clock_fn is not None:
            return int(self._clock_fn())
        return self._clock_ns

    def _data_time(self) -> tuple[str, float]:
        """``(clock, seconds)`` on the clock the data uses.

        ``("sim", sim time)`` when there is one, else ``("wall", monotonic time)``.
        """
        sim = self._sim_ns()
        return ("sim", sim / NS) if sim is not None else ("wall", time.monotonic())

    def time_state(self) -> dict[str, Any]:
        """What the page's clock shows.

        ``source`` (``"executor"``: the run's simulated time in this process; ``"/clock"``; or
        ``"wall"``), ``sim`` (s, None on the wall clock), ``wall`` (Unix time, s), ``rtf`` (sim
        seconds per wall second over the last :data:`RTF_WINDOW_S` s; 1.0 on the wall clock;
        None until measured) and ``rate_clock`` (the clock topic rates are measured on:
        ``"sim"`` or ``"wall"``).
        """
        mono, wall = time.monotonic(), time.time()
        sim = self._sim_ns()
        if sim is None:
            return {"source": "wall", "sim": None, "wall": wall, "rtf": 1.0,
                    "rate_clock": "wall"}
        with self._lock:
            samples = self._rtf_samples
            if samples and sim < samples[-1][1]:
                samples.clear()  # the clock went back (restarted run): measure afresh
            samples.append((mono, sim))
            while len(samples) > 2 and mono - samples[1][0] >= RTF_WINDOW_S:
                samples.popleft()
            first = samples[0]
        span = mono - first[0]
        rtf = (sim - first[1]) / NS / span if span >= 0.25 else None
        source = "executor" if self._clock_fn is not None else "/clock"
        return {"source": source, "sim": sim / NS, "wall": wall, "rtf": rtf,
                "rate_clock": "sim"}

    def topics(self) -> list[dict[str, Any]]:
        """The topic panel: name, type, rate, messages received, publisher count.

        The rate is in Hz, on the clock the data uses (see :meth:`time_state`).
        """
        clock, now = self._data_time()
        with self._lock:
            infos = list(self._topics.values())
            rows = [
                {
                    "name": i.name,
                    "type": i.type_name,
                    "rate": round(i.rate_hz(now) if i.clock == clock else 0.0, 2),
                    "count": i.count,
                    "error": i.error,
                }
                for i in infos
            ]
        for row in rows:
            try:
                row["publishers"] = self.transport.count_publishers(str(row["name"]))
            except Exception:  # graph query failure: show unknown
                row["publishers"] = None
        return sorted(rows, key=lambda d: d["name"])

    def image_topics(self) -> list[str]:
        """Topics carrying sensor_msgs/Image."""
        with self._lock:
            return sorted(n for n, i in self._topics.items() if i.type_name == IMAGE_TYPE)

    def latest_image(self, topic: str) -> tuple[int, Any] | None:
        """``(sequence number, newest Image message)`` of ``topic``, or None.

        None too when no page has shown the topic since its last message.
        """
        with self._lock:
            latest = self._images.get(topic)
        return None if latest is None or latest[1] is None else latest

    def set_image_watches(self, topics: Iterable[str]) -> None:
        """Follow the image topics of ``topics`` (what the pages show); let go of the others.

        An image topic is subscribed only while watched here or followed by a display (see
        the module doc); one let go keeps no image, so a new watch waits for a new message.
        """
        with self._lock:
            before = self._on_demand_followed()
            self._image_watches = frozenset(topics)
        self._follow(before)

    def set_message_watches(self, depths: dict[str, int]) -> None:
        """Keep the newest ``depths[topic]`` messages of each topic for the displays.

        A new watch starts with the newest message already received; other topics' queues go.
        """
        with self._lock:
            before = self._on_demand_followed()
            for topic in [t for t in self._queues if t not in depths]:
                del self._queues[topic]
            for topic, depth in depths.items():
                queue = self._queues.get(topic)
                if queue is None:
                    queue = self._queues[topic] = MessageQueue(depth)
                    if topic in self._latest:
                        queue.append(self._latest[topic])
                else:
                    queue.resize(depth)
        self._follow(before)

    def messages_after(self, topic: str, seq: int) -> list[tuple[int, Any]]:
        """``(number, message)`` of the kept messages of a watched ``topic`` newer than ``seq``.

        Oldest first; empty when the topic is not watched.
        """
        with self._lock:
            queue = self._queues.get(topic)
        return [] if queue is None else queue.after(seq)

    def topic_type(self, topic: str) -> str | None:
        """The type of ``topic`` as the graph announced it, or None when not seen yet."""
        with self._lock:
            info = self._topics.get(topic)
        return None if info is None else info.type_name

    def trails(self) -> dict[str, dict[str, Any]]:
        """Every Odometry display: frame, child frame, kept poses, messages received."""
        with self._lock:
            return {
                topic: {
                    "frame": t.frame_id,
                    "child": t.child_frame_id,
                    "received": t.received,
                    "version": t.version,
                    "trail": [[round(v, 4) for v in p] for p in t.poses],
                }
                for topic, t in self._trails.items()
            }

    def trails_version(self) -> int:
        """Changes whenever any trail changes."""
        with self._lock:
            return sum(t.version for t in self._trails.values())

    def close(self) -> None:
        """Destroy every subscription; sinks ignore late messages."""
        self._closed = True
        self._observer.close()
