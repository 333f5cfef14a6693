"""Buffer: tf2_ros's Python ``Buffer`` API (waits, async futures, ``transform``) over BufferCore.

Lecture code runs unchanged::

    buffer = Buffer()                       # cache_time=Duration(seconds=10)
    t = buffer.lookup_transform("odom", "base_link", Time(), timeout=Duration(seconds=0.1))

Differences from tf2_ros, all deliberate: a lookup with a timeout sleeps on a condition
variable that every accepted ``set_transform`` notifies (no 20 ms polling, wakes at once);
without a timeout it never blocks. ``set_transform*`` return True/False (stored/rejected).
As in tf2_ros, a lookup whose wait timed out raises the core's exception, never
:class:`TimeoutException`.
"""

from __future__ import annotations

import threading
import time as _time
from collections.abc import Callable
from typing import Any, ClassVar

from posekit.msgs.geometry_msgs import PointStamped, PoseStamped, TransformStamped, Vector3Stamped
from posekit.tf2.buffer_core import BufferCore, _duration_ns
from posekit.tf2.exceptions import TypeException
from posekit.tf2.future import Future
from posekit.tf2.geometry_msgs import (
    do_transform_point,
    do_transform_pose_stamped,
    do_transform_transform,
    do_transform_vector3,
)
from posekit.time import Duration

__all__ = ["Buffer", "TransformRegistration"]

_ZERO = Duration()


class TransformRegistration:
    """Which ``do_transform`` function ``Buffer.transform`` applies to which message type.

    Keys are classes or ``__msgtype__`` strings (so rosbags / rclpy messages with the same
    type name are accepted too).
    """

    _registry: ClassVar[dict[Any, Callable[[Any, Any], Any]]] = {}

    def add(self, key: Any, callback: Callable[[Any, Any], Any]) -> None:
        """Register ``callback(obj, transform_stamped)`` for objects of type ``key``."""
        self._registry[key] = callback
        msgtype = getattr(key, "__msgtype__", None)
        if isinstance(msgtype, str):
            self._registry[msgtype] = callback

    def get(self, key: Any) -> Callable[[Any, Any], Any]:
        """The function for type ``key``; TypeException (tf2_ros's text) if none."""
        fn = self._registry.get(key)
        if fn is None:
            fn = self._registry.get(getattr(key, "__msgtype__", None))
        if fn is None:
            raise TypeException(f"Type {key} is not loaded or supported")
        return fn


_registration = TransformRegistration()
_registration.add(PointStamped, do_transform_point)
_registration.add(PoseStamped, do_transform_pose_stamped)
_registration.add(Vector3Stamped, do_transform_vector3)
_registration.add(TransformStamped, do_transform_transform)


class Buffer(BufferCore):
    """tf2_ros.Buffer: BufferCore plus timeouts, async waits and ``transform``.

    Args:
        cache_time: how long dynamic samples are kept (default 10 s).
        node: accepted for tf2_ros compatibility; the tf2 layer does not use it.

    Examples:
        ``base_link`` moves in ``odom`` from x = 1 m (yaw 0) at t = 1 s to x = 3 m (yaw
        π/2) at t = 2 s; a camera sits 0.5 m ahead of it (static):

        >>> import math
        >>> from posekit.msgs.geometry_msgs import TransformStamped
        >>> from posekit.tf2 import Buffer, LookupException
        >>> from posekit.time import Time
        >>> def stamped(parent, child, seconds, x, yaw):
        ...     t = TransformStamped()
        ...     t.header.frame_id, t.child_frame_id = parent, child
        ...     t.header.stamp = Time(seconds=seconds).to_msg()
        ...     t.transform.translation.x = x
        ...     t.transform.rotation.z = math.sin(yaw / 2)
        ...     t.transform.rotation.w = math.cos(yaw / 2)
        ...     return t
        >>> buffer = Buffer()
        >>> buffer.set_transform(stamped("odom", "base_link", 1.0, 1.0, 0.0), "doc")
        True
        >>> buffer.set_transform(stamped("odom", "base_link", 2.0, 3.0, math.pi / 2), "doc")
        True
        >>> buffer.set_transform_static(stamped("base_link", "camera", 0.0, 0.5, 0.0), "doc")
        True

        Between two samples, the translation is interpolated linearly and the rotation by
        slerp: at t = 1.5 s, x = 2 m and yaw = π/4, the quaternion (0, 0, sin π/8, cos π/8):

        >>> t = buffer.lookup_transform("odom", "base_link", Time(seconds=1.5))
        >>> round(t.transform.translation.x, 9)
        2.0
        >>> q = t.transform.rotation
        >>> [round(c, 6) for c in (q.x, q.y, q.z, q.w)]
        [0.0, 0.0, 0.382683, 0.92388]

        ``Time()`` asks for the latest time common to the chain (2 s here); the camera is
        then at ``(3, 0, 0) + Rz(π/2) (0.5, 0, 0) = (3, 0.5, 0)`` in ``odom``:

        >>> t = buffer.lookup_transform("odom", "camera", Time())
        >>> p = t.transform.translation
        >>> t.header.stamp.sec, [round(c, 9) for c in (p.x, p.y, p.z)]
        (2, [3.0, 0.5, 0.0])
        >>> try:
        ...     buffer.lookup_transform("odom", "map", Time())
        ... except LookupException as error:
        ...     print(str(error).strip())
        "map" passed to lookupTransform argument source_frame does not exist.
    """

    def __init__(self, cache_time: Duration | None = None, node: Any = None) -> None:
        super().__init__(cache_time)
        self._cond = threading.Condition(self._lock)
        self._waiters = 0
        self._new_data_callbacks: list[Callable[[], None]] = []
        self._callbacks_lock = threading.Lock()
        self.node = node
        self.registration = _registration

    # -- notification hooks ------------------------------------------------------------------
    def _on_new_data_locked(self) -> None:
        if self._waiters:
            self._cond.notify_all()

    def _on_new_data(self) -> None:
        if self._new_data_callbacks:
            with self._callbacks_lock:
                callbacks = list(self._new_data_callbacks)
            for cb in callbacks:
                cb()

    def _remove_callback(self, callback: Callable[[], None]) -> None:
        with self._callbacks_lock:
            if callback in self._new_data_callbacks:
                self._new_data_callbacks.remove(callback)

    def _wait_until(self, check: Callable[[], bool], timeout_ns: int) -> bool:
        """Block until ``check()`` or the timeout (wall clock); woken by each new transform."""
        deadline = _time.monotonic() + timeout_ns * 1e-9
        with self._cond:
            self._waiters += 1
            try:
                while True:
                    if check():
                        return True
                    remaining = deadline - _time.monotonic()
                    if remaining <= 0.0:
                        return False
                    self._cond.wait(remaining)
            finally:
                self._waiters -= 1

    # -- lookups -------------------------------------------------------------------------------
    def lookup_transform(
        self, target_frame: str, source_frame: str, time: Any, timeout: Any = _ZERO
    ) -> TransformStamped:
        """T_target_source at ``time`` (``Time()`` = latest common time), waiting up to
        ``timeout`` for the data; raises tf2's exception if still impossible."""
        if timeout is not _ZERO and _duration_ns(timeout) > 0:
            self.can_transform(target_frame, source_frame, time, timeout)
        return self.lookup_transform_core(target_frame, source_frame, time)

    def lookup_transform_full(
        self,
        target_frame: str,
        target_time: Any,
        source_frame: str,
        source_time: Any,
        fixed_frame: str,
        timeout: Any = _ZERO,
    ) -> TransformStamped:
        """Time travel lookup through ``fixed_frame`` (see ``lookup_transform_full_core``)."""
        if timeout is not _ZERO and _duration_ns(timeout) > 0:
            self.can_transform_full(
                target_frame, target_time, source_frame, source_time, fixed_frame, timeout
            )
        return self.lookup_transform_full_core(
            target_frame, target_time, source_frame, source_time, fixed_frame
        )

    def can_transform(
        self,
        target_frame: str,
        source_frame: str,
        time: Any,
        timeout: Any = _ZERO,
        return_debug_tuple: bool = False,
    ) -> bool | tuple[bool, str]:
        """Whether the lookup would succeed, waiting up to ``timeout``; with
        ``return_debug_tuple=True`` returns ``(bool, tf2's reason)``."""
        result = self._probe_waiting(
            lambda: self.can_transform_core(target_frame, source_frame, time), timeout
        )
        return result if return_debug_tuple else result[0]

    def can_transform_full(
        self,
        target_frame: str,
        target_time: Any,
        source_frame: str,
        source_time: Any,
        fixed_frame: str,
        timeout: Any = _ZERO,
        return_debug_tuple: bool = False,
    ) -> bool | tuple[bool, str]:
        """can_transform for the time-travel lookup."""
        args = (target_frame, target_time, source_frame, source_time, fixed_frame)
        result = self._probe_waiting(lambda: self.can_transform_full_core(*args), timeout)
        return result if return_debug_tuple else result[0]

    def _probe_waiting(
        self, probe: Callable[[], tuple[bool, str]], timeout: Any
    ) -> tuple[bool, str]:
        """``probe()``; if it fails, re-run it on new data for up to ``timeout`` until it
        succeeds, and return its last answer."""
        timeout_ns = _duration_ns(timeout)
        result = probe()
        if not result[0] and timeout_ns > 0:
            holder = [result]

            def check() -> bool:
                holder[0] = probe()
                return holder[0][0]

            self._wait_until(check, timeout_ns)
            result = holder[0]
        return result

    # -- async ---------------------------------------------------------------------------------
    def _future_when(self, check: Callable[[], bool]) -> Future[bool]:
        fut: Future[bool] = Future()
        if check():
            fut.set_result(True)
            return fut

        def on_new_data() -> None:
            try:
                if check():
                    fut.set_result(True)
            except BaseException as exc:  # surfaced through the future, as tf2_ros does
                fut.set_exception(exc)

        with self._callbacks_lock:
            self._new_data_callbacks.append(on_new_data)
        fut.add_done_callback(lambda _: self._remove_callback(on_new_data))
        # data may have arrived between the first check and the registration
        on_new_data()
        return fut

    def wait_for_transform_async(
        self, target_frame: str, source_frame: str, time: Any
    ) -> Future[bool]:
        """A future resolved (True) by the first ``set_transform*`` that makes the lookup
        possible. No timeout (as tf2_ros); cancel it to stop waiting."""
        return self._future_when(
            lambda: self.can_transform_core(target_frame, source_frame, time)[0]
        )

    def wait_for_transform_full_async(
        self,
        target_frame: str,
        target_time: Any,
        source_frame: str,
        source_time: Any,
        fixed_frame: str,
    ) -> Future[bool]:
        """Async wait for the time-travel lookup."""
        return self._future_when(
            lambda: self.can_transform_full_core(
                target_frame, target_time, source_frame, source_time, fixed_frame
            )[0]
        )

    async def lookup_transform_async(
        self, target_frame: str, source_frame: str, time: Any
    ) -> TransformStamped:
        """Coroutine: await the data, then return the lookup (drive with await or send(None))."""
        await self.wait_for_transform_async(target_frame, source_frame, time)
        return self.lookup_transform_core(target_frame, source_frame, time)

    async def lookup_transform_full_async(
        self,
        target_frame: str,
        target_time: Any,
        source_frame: str,
        source_time: Any,
        fixed_frame: str,
    ) -> TransformStamped:
        """Coroutine version of :meth:`lookup_transform_full`."""
        await self.wait_for_transform_full_async(
            target_frame, target_time, source_frame, source_time, fixed_frame
        )
        return self.lookup_transform_full_core(
            target_frame, target_time, source_frame, source_time, fixed_frame
        )

    # -- transform -----------------------------------------------------------------------------
    def transform(
        self, object_stamped: Any, target_frame: str, timeout: Any = _ZERO, new_type: Any = None
    ) -> Any:
        """``object_stamped`` (PointStamped, PoseStamped, Vector3Stamped, TransformStamped)
        expressed in ``target_frame``, looked up at its own ``header.stamp``."""
        do_transform = self.registration.get(type(object_stamped))
        header = object_stamped.header
        res = do_transform(
            object_stamped,
            self.lookup_transform(target_frame, header.frame_id, header.stamp, timeout),
        )
        return _convert(res, new_type)

    def transform_full(
        self,
        object_stamped: Any,
        target_frame: str,
        target_time: Any,
        fixed_frame: str,
        timeout: Any = _ZERO,
        new_type: Any = None,
    ) -> Any:
        """``object_stamped`` in ``target_frame`` at ``target_time``, via ``fixed_frame``."""
        do_transform = self.registration.get(type(object_stamped))
        header = object_stamped.header
        res = do_transform(
            object_stamped,
            self.lookup_transform_full(
                target_frame, target_time, header.frame_id, header.stamp, fixed_frame, timeout
            ),
        )
        return _convert(res, new_type)


def _convert(res: Any, new_type: Any) -> Any:
    if new_type is None or isinstance(res, new_type):
        return res
    raise TypeException(f"Type {new_type} is not loaded or supported")
