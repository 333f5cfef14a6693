"""tf2_ros-style Buffer: timeouts on a condition variable, async futures, transform(), threads."""

from __future__ import annotations

import math
import threading
import time
from typing import Any

import numpy as np
import pytest

from posekit.msgs.geometry_msgs import (
    PointStamped,
    Pose,
    PoseStamped,
    TransformStamped,
    Vector3Stamped,
)
from posekit.tf2 import (
    Buffer,
    ConnectivityException,
    ExtrapolationException,
    LookupException,
    TimeoutException,
    TransformException,
    TypeException,
)
from posekit.time import Duration, Time

S = 1_000_000_000


def ts(
    parent: str,
    child: str,
    sec: float,
    t: tuple[float, float, float] = (0.0, 0.0, 0.0),
    yaw: float = 0.0,
) -> TransformStamped:
    m = TransformStamped()
    m.header.frame_id = parent
    m.child_frame_id = child
    m.header.stamp.sec, m.header.stamp.nanosec = divmod(round(sec * S), S)
    m.transform.translation.x, m.transform.translation.y, m.transform.translation.z = t
    m.transform.rotation.z = math.sin(yaw / 2)
    m.transform.rotation.w = math.cos(yaw / 2)
    return m


def test_constructor_and_return_values() -> None:
    b = Buffer(cache_time=Duration(seconds=3))
    assert b.cache_time == Duration(seconds=3)
    assert b.set_transform(ts("a", "b", 10), "n") is True
    assert b.set_transform(ts("a", "b", 6.9), "n") is False
    assert b.set_transform_static(ts("a", "c", 0), "n") is True
    assert Buffer().cache_time == Duration(seconds=10)


@pytest.mark.parametrize("call", ["can_transform", "lookup_transform"])
def test_a_float_timeout_is_a_clear_type_error(call: str) -> None:
    # tf2_ros in ROS 2 takes rclpy Durations only; say so instead of an AttributeError
    b = Buffer()
    b.set_transform(ts("a", "b", 1), "n")
    with pytest.raises(TypeError, match=r"expected an rclpy Duration, e\.g\. "
                                        r"Duration\(seconds=0\.1\), got float 0\.1"):
        getattr(b, call)("a", "b", Time(), timeout=0.1)


def test_lookup_without_timeout_never_blocks() -> None:
    b = Buffer()
    start = time.monotonic()
    with pytest.raises(LookupException):
        b.lookup_transform("a", "b", Time())
    assert time.monotonic() - start < 0.5


def test_timeout_wait_woken_by_writer_thread() -> None:
    b = Buffer()
    b.set_transform(ts("map", "odom", 1), "n")

    def writer() -> None:
        time.sleep(0.05)
        b.set_transform(ts("odom", "base", 1, (1, 2, 3)), "n")

    th = threading.Thread(target=writer)
    start = time.monotonic()
    th.start()
    r = b.lookup_transform("map", "base", Time(), timeout=Duration(seconds=5))
    elapsed = time.monotonic() - start
    th.join()
    assert [r.transform.translation.x, r.transform.translation.y] == [1, 2]
    assert elapsed < 2.0  # woken by the insert, not by the 5 s timeout


def test_timeout_expires_then_raises_core_exception_not_timeout() -> None:
    b = Buffer()
    b.set_transform(ts("a", "b", 1), "n")
    b.set_transform(ts("c", "d", 1), "n")
    start = time.monotonic()
    with pytest.raises(ConnectivityException) as e:
        b.lookup_transform("a", "d", Time(), timeout=Duration(seconds=0.1))
    assert not isinstance(e.value, TimeoutException)
    assert 0.09 <= time.monotonic() - start < 2.0


def test_can_transform_timeout_and_debug_tuple() -> None:
    b = Buffer()
    b.set_transform(ts("a", "b", 1), "n")
    assert b.can_transform("a", "b", Time()) is True
    ok, msg = b.can_transform(
        "a", "zz", Time(), timeout=Duration(seconds=0.02), return_debug_tuple=True
    )  # type: ignore[misc]
    assert ok is False
    assert (
        msg == 'Invalid frame ID "zz" passed to canTransform argument source_frame - '
        "frame does not exist"
    )
    assert b.can_transform_full("b", Time(), "b", Time(), "a") is True


def drive(coro: Any) -> Any:
    """Run a coroutine to completion by hand; returns its value or None if still pending."""
    try:
        coro.send(None)
    except StopIteration as stop:
        return stop.value
    return None


def test_wait_for_transform_async_resolved_by_set_transform() -> None:
    b = Buffer()
    fut = b.wait_for_transform_async("a", "b", Time(seconds=2))
    assert not fut.done()
    b.set_transform(ts("a", "b", 1), "n")
    assert not fut.done()  # 2 s not yet available (one sample at 1 s)
    b.set_transform(ts("a", "b", 3), "n")
    assert fut.done()
    assert fut.result() is True
    assert b._new_data_callbacks == []  # callback removed once done


def test_lookup_transform_async_with_send_none() -> None:
    b = Buffer()
    coro = b.lookup_transform_async("a", "b", Time())
    assert drive(coro) is None  # pending: yielded
    b.set_transform(ts("a", "b", 1, (4, 0, 0)), "n")
    with pytest.raises(StopIteration) as stop:
        coro.send(None)
    assert stop.value.value.transform.translation.x == 4


def test_async_already_available_resolves_immediately() -> None:
    b = Buffer()
    b.set_transform(ts("a", "b", 1), "n")
    assert b.wait_for_transform_async("a", "b", Time()).done()
    r = drive(b.lookup_transform_full_async("b", Time(seconds=1), "b", Time(seconds=1), "a"))
    assert r.header.frame_id == "b"


def test_transform_point_pose_vector() -> None:
    b = Buffer()
    b.set_transform(ts("map", "base", 2, (1, 2, 0), yaw=math.pi / 2), "n")
    p = PointStamped()
    p.header.frame_id = "base"
    p.header.stamp.sec = 2
    p.point.x = 1.0
    out = b.transform(p, "map")
    assert out.header.frame_id == "map"
    assert out.header.stamp.sec == 2
    np.testing.assert_allclose([out.point.x, out.point.y, out.point.z], [1, 3, 0], atol=1e-12)

    v = Vector3Stamped()
    v.header.frame_id = "base"
    v.vector.x = 1.0
    vo = b.transform(v, "map", timeout=Duration(seconds=0.01))
    np.testing.assert_allclose([vo.vector.x, vo.vector.y, vo.vector.z], [0, 1, 0], atol=1e-12)

    ps = PoseStamped()
    ps.header.frame_id = "base"
    ps.pose.orientation.z = math.sin(math.pi / 4)
    ps.pose.orientation.w = math.cos(math.pi / 4)
    po = b.transform(ps, "map", new_type=PoseStamped)
    q = po.pose.orientation
    assert abs(abs(q.z) - 1.0) < 1e-12  # 90 + 90 deg about z
    np.testing.assert_allclose([po.pose.position.x, po.pose.position.y], [1, 2])


def test_transform_unknown_type_and_missing_frame() -> None:
    b = Buffer()
    with pytest.raises(TypeException, match="is not loaded or supported"):
        b.transform(Pose(), "map")
    p = PointStamped()
    p.header.frame_id = "nowhere"
    b.set_transform(ts("map", "base", 1), "n")
    with pytest.raises(LookupException):
        b.transform(p, "map")


def test_transform_full_uses_fixed_frame() -> None:
    b = Buffer()
    b.set_transform(ts("odom", "base", 1, (0, 1, 0)), "n")
    b.set_transform(ts("odom", "base", 3, (0, 3, 0)), "n")
    p = PointStamped()
    p.header.frame_id = "base"
    p.header.stamp.sec = 1
    out = b.transform_full(p, "base", Time(seconds=3), "odom")
    np.testing.assert_allclose([out.point.x, out.point.y], [0, -2])


@pytest.fixture
def busy_buffer() -> Buffer:
    b = Buffer(cache_time=Duration(seconds=2))
    b.set_transform_static(ts("world", "map", 0, (1, 0, 0)), "n")
    return b


def test_concurrent_readers_and_writer_no_deadlock(busy_buffer: Buffer) -> None:
    b = busy_buffer
    stop = threading.Event()
    errors: list[BaseException] = []
    counts = [0, 0, 0, 0]

    def writer() -> None:
        i = 0
        while not stop.is_set():
            i += 1
            sec = 1 + i * 0.001
            b.set_transform(ts("map", "odom", sec, (sec, 0, 0), yaw=0.01 * i), "w")
            b.set_transform(ts("odom", "base", sec, (0, 1, 0)), "w")
            if i % 500 == 0:
                b.clear()

    def reader(k: int) -> None:
        while not stop.is_set():
            try:
                if k == 3:
                    b.all_frames_as_yaml()
                    b.can_transform("world", "base", Time(), timeout=Duration(seconds=0.01))
                else:
                    r = b.lookup_transform("world", "base", Time(), timeout=Duration(seconds=0.01))
                    q = r.transform.rotation
                    assert abs(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w - 1.0) < 1e-12
                    assert r.transform.translation.z == 0.0
                counts[k] += 1
            except (ExtrapolationException, ConnectivityException, LookupException):
                counts[k] += 1  # expected while frames are cleared / not yet present
            except BaseException as exc:  # anything else is a bug
                errors.append(exc)
                return

    threads = [threading.Thread(target=writer)] + [
        threading.Thread(target=reader, args=(k,)) for k in range(4)
    ]
    for th in threads:
        th.start()
    time.sleep(2.0)
    stop.set()
    for th in threads:
        th.join(timeout=5)
    assert not any(th.is_alive() for th in threads), "deadlock"
    assert errors == []
    assert all(c > 0 for c in counts)


def test_exceptions_all_transform_exception() -> None:
    b = Buffer()
    with pytest.raises(TransformException):
        b.lookup_transform("", "x", Time())
