"""tf2_ros.transform_listener: ``TransformListener`` (behaviour from docs/specs/tf2.md §9).

``TransformListener(buffer, node)`` subscribes ``/tf`` (KEEP_LAST 100, VOLATILE) and
  ``/tf_static`` (KEEP_LAST 100, TRANSIENT_LOCAL, so it also receives static transforms sent
  before it existed), in a ReentrantCallbackGroup; every transform goes to
  ``buffer.set_transform(t, authority)`` / ``buffer.set_transform_static(t, authority)``.
  When the node clock jumps back in time (any backward jump, like C++ tf2_ros; bag loops
  under ``use_sim_time``) it logs ``Detected jump back in time. Clearing tf buffer.`` as a
  warning and calls ``buffer.clear()``; switching the time source (use_sim_time turned on,
  which every stepped run does at start-up) clears it too, logged at debug level only.
  ``spin_thread=False`` is posekit's default; ``True`` moves the two subscriptions to a
  hidden helper node spun by its own SingleThreadedExecutor thread, so a callback of
  ``node`` may block in ``lookup_transform(..., timeout=...)`` while transforms keep arriving.

posekit guards of the listener (the Buffer itself keeps tf2's semantics exactly):

* **Far-future stamps** (default on, ``max_future=Duration(seconds=10)``; None turns it
  off): a ``/tf`` transform stamped more than ``max_future`` ahead of the node's clock is
  not passed to the buffer, with one warning per second (and a suppressed count). tf2 would
  store it, and every later real sample of that frame older than ``stamp - cache_time``
  would then fail with ``TF_OLD_DATA``: one sample stamped years ahead would freeze the
  frame until a restart. 10 s is tf2's default cache time, so a sample that passes can never
  push current data out of the cache. Nothing is checked while the clock reads 0 (sim time
  before the first ``/clock``), and ``/tf_static`` is not checked (its stamps are unused).
* **Frame bound** (``max_frames=10_000``; None: unbounded): when the listener has fed more
  frames than that, the ones it updated least recently are forgotten
  (:meth:`posekit.tf2.BufferCore.forget_frames`), so a peer announcing endless random
  frames cannot grow the buffer forever. :meth:`TransformListener.forget_frame` forgets one
  by hand.
"""


from __future__ import annotations

import threading
from collections import OrderedDict
from typing import Any, Protocol

from posekit.msgs.tf2_msgs import TFMessage
from posekit.runtime.callback_groups import ReentrantCallbackGroup
from posekit.runtime.clock import ClockChange, JumpThreshold, TimeJump
from posekit.runtime.node import Node, node_defaults
from posekit.runtime.qos import QoSProfile
from posekit.runtime.ratelimit import RateLimitedLog
from posekit.tf2_ros.qos import DynamicListenerQoS, StaticListenerQoS
from posekit.time import Duration, stamp_to_ns

__all__ = ["DEFAULT_MAX_FRAMES", "DEFAULT_MAX_FUTURE", "TransformListener"]

#: TransformListener: /tf stamps further ahead of the node clock are held back (tf2's cache
#: time, see the module docstring).
DEFAULT_MAX_FUTURE = Duration(seconds=10)
#: TransformListener: frames fed before the least recently updated are forgotten.
DEFAULT_MAX_FRAMES = 10_000



class _BufferLike(Protocol):
    def set_transform(self, transform: Any, authority: str) -> Any: ...

    def set_transform_static(self, transform: Any, authority: str) -> Any: ...

    def clear(self) -> Any: ...


class TransformListener:
    """Fills a tf2 buffer from /tf and /tf_static (see the module docstring)."""

    AUTHORITY = "default_authority"

    def __init__(
        self,
        buffer: _BufferLike,
        node: Node,
        *,
        spin_thread: bool = False,
        qos: QoSProfile | int | None = None,
        static_qos: QoSProfile | int | None = None,
        tf_topic: str = "/tf",
        tf_static_topic: str = "/tf_static",
        max_future: Duration | None = DEFAULT_MAX_FUTURE,
        max_frames: int | None = DEFAULT_MAX_FRAMES,
    ) -> None:
        if max_frames is not None and max_frames < 1:
            raise ValueError(f"max_frames must be >= 1 (or None), got {max_frames}")
        if max_future is not None and max_future.nanoseconds < 0:
            raise ValueError(f"max_future must be >= 0 (or None), got {max_future}")
        self.buffer = buffer
        self.node = node
        self._max_future_ns = None if max_future is None else max_future.nanoseconds
        self._max_frames = max_frames
        # Frames this listener fed, least recently updated first (for max_frames).
        self._fed: OrderedDict[str, None] = OrderedDict()
        self._fed_lock = threading.Lock()
        #: /tf transforms not passed to the buffer because of their far-future stamp.
        self.future_dropped = 0
        self._warn = RateLimitedLog(node.get_logger().warning)
        self._thread: threading.Thread | None = None
        self._executor: Any = None
        self._helper: Node | None = None
        sub_node = node
        if spin_thread:
            from posekit.runtime.executors import SingleThreadedExecutor

            # A fresh scope: a launch's name/remapping overrides are for the user's node.
            with node_defaults(context=node.context):
                self._helper = Node(
                    f"{node.get_name()}_tf_listener",
                    namespace=node.get_namespace(),
                    context=node.context,
                    parameter_overrides={
                        "use_sim_time": node.get_parameter("use_sim_time").value
                    },
                )
            sub_node = self._helper
        self.group = ReentrantCallbackGroup()
        self.tf_sub = sub_node.create_subscription(
            TFMessage,
            tf_topic,
            self.callback,
            qos if qos is not None else DynamicListenerQoS(),
            callback_group=self.group,
        )
        self.tf_static_sub = sub_node.create_subscription(
            TFMessage,
            tf_static_topic,
            self.static_callback,
            static_qos if static_qos is not None else StaticListenerQoS(),
            callback_group=self.group,
        )
        self._jump_handle = node.get_clock().create_jump_callback(
            JumpThreshold(min_backward=Duration(nanoseconds=-1), on_clock_change=True),
            post_callback=self._on_jump,
        )
        if spin_thread and self._helper is not None:
            self._executor = SingleThreadedExecutor(context=node.context)
            self._executor.add_node(self._helper)
            self._thread = threading.Thread(
                target=self._executor.spin, name="posekit-tf-listener", daemon=True
            )
            self._thread.start()

    def callback(self, msg: TFMessage) -> None:
        """/tf: each transform -> buffer.set_transform (far-future stamps held back)."""
        limit = self._max_future_ns
        now = self.node.get_clock().now_ns() if limit is not None else 0
        horizon = now + limit if limit is not None and now > 0 else None
        for t in msg.transforms:
            if horizon is not None:
                stamp_ns = stamp_to_ns(t.header.stamp)
                if stamp_ns > horizon:
                    self.future_dropped += 1
                    self._warn(
                        "Ignoring transforms stamped far in the future",
                        f"frame {t.child_frame_id[:120]!r} at {stamp_ns / 1e9:.3f} s is more "
                        f"than {(horizon - now) / 1e9:g} s ahead of this node's clock "
                        f"({now / 1e9:.3f} s)",
                    )
                    continue
            if self.buffer.set_transform(t, self.AUTHORITY):
                self._fed_frame(t.child_frame_id)

    def static_callback(self, msg: TFMessage) -> None:
        """/tf_static: each transform -> buffer.set_transform_static."""
        for t in msg.transforms:
            if self.buffer.set_transform_static(t, self.AUTHORITY):
                self._fed_frame(t.child_frame_id)

    def _fed_frame(self, child: str) -> None:
        if self._max_frames is None:
            return
        with self._fed_lock:
            fed = self._fed
            if child in fed:
                fed.move_to_end(child)
                return
            fed[child] = None
            if len(fed) <= self._max_frames:
                return
            # Forget a tenth at once: compacting the buffer costs the same for one or many.
            count = max(1, self._max_frames // 10)
            stale = [fed.popitem(last=False)[0] for _ in range(count)]
        self._forget(stale)

    def _forget(self, frames: list[str]) -> None:
        forget = getattr(self.buffer, "forget_frames", None)
        if forget is not None:
            forget(frames)

    def forget_frame(self, frame: str) -> None:
        """Forget ``frame`` in the buffer (its transforms and, unless another frame hangs
        off it, its name); it comes back if it is sent again."""
        with self._fed_lock:
            self._fed.pop(frame, None)
        self._forget([frame])

    def _on_jump(self, jump: TimeJump) -> None:
        if jump.clock_change in (ClockChange.ROS_TIME_ACTIVATED, ClockChange.ROS_TIME_DEACTIVATED):
            # Normal at start-up (use_sim_time switched on): debug, not a warning.
            self.node.get_logger().debug("Detected time source change. Clearing tf buffer.")
        else:
            self.node.get_logger().warning("Detected jump back in time. Clearing tf buffer.")
        self.buffer.clear()

    def unregister(self) -> None:
        """Stop listening (subscriptions destroyed, jump callback removed, thread stopped)."""
        self._jump_handle.unregister()
        owner = self._helper or self.node
        owner.destroy_subscription(self.tf_sub)
        owner.destroy_subscription(self.tf_static_sub)
        if self._executor is not None:
            self._executor.shutdown()
        if self._thread is not None:
            self._thread.join(timeout=1.0)
            self._thread = None
        if self._helper is not None:
            self._helper.destroy_node()
            self._helper = None
