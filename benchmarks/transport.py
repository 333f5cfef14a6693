"""Messages between two processes over Zenoh and over DDS on loopback: posekit against the
raw libraries it is built on, in interleaved rounds of the same run.

Run: ``.venv/bin/python benchmarks/transport.py`` (every transport and message, 7 rounds,
about 12 minutes; with fewer rounds two runs of identical code differed by up to 1.3x on a
2-core VM, with 7 they agreed within 7 %, see docs/performance.md); ``--transport zenoh``
or ``dds``, ``--messages tf`` or ``image``, ``--rounds N``, ``--quick`` (one short round);
``--references`` adds, on DDS, the real ROS 2 rclpy (Fast DDS, needs ``make ros2-ref``) and
cyclonedds' own Python API; ``--hop`` (Zenoh) and ``--together`` are described below;
``--before SRC`` adds another checkout; ``--quiet-first``: posekit's subscriber node first
subscribes to a topic nothing is published on (a node of several subscriptions). Figures
are recorded in docs/performance.md.

Messages: ``tf``, a ``geometry_msgs/TransformStamped`` (100 B of CDR), and ``image``, a
``sensor_msgs/Image`` 128x128 rgb8 (49,152 B of pixels, 49,212 B of CDR). Both sides use
RELIABLE + KEEP_ALL, so a burst is paced by the transport's flow control, never dropped.

Modes, each a publisher process and a subscriber process of the same implementation:

* ``raw``: the library alone, doing the work a user of posekit gets done: the message is
  serialized by rosbags (``typestore.serialize_cdr``) and sent; the receiver takes the
  bytes and deserializes them into a rosbags message object (``deserialize_cdr``), then
  calls the user callback on the thread that received it. Zenoh: ``put`` with rmw_zenoh's
  attachment (which the receiver decodes), a subscriber callback (zenoh-python runs it on
  a thread of its own). DDS: cyclonedds' C layer moving the CDR bytes (``ddspy_write`` /
  ``ddspy_take``), the receiver a WaitSet loop.
* ``posekit``: a runtime ``Node`` publisher, and a ``Node`` subscription whose callback a
  ``SingleThreadedExecutor`` runs, as in rclpy (receive, checks, CDR decode into posekit's
  message classes, queue, executor thread, callback).
* ``transport``: posekit's transport layer alone, the callback run where the transport
  delivers (no executor): the same receive path as ``posekit`` up to the queue.
* with ``--hop`` on Zenoh: ``hop``, raw but received as an executor receives: zenoh's thread
  queues the sample in a channel and a Python thread blocked in ``recv()`` takes, decodes
  and calls back (the thread hand-off every executor pays, rclpy's on rmw_zenoh too: it
  waits in ``rcl_wait`` for the middleware's thread). ``posekit / hop`` is the cost of the
  rest.
* with ``--references`` on DDS: ``rclpy`` (the real Jazzy rclpy on rmw_fastrtps_cpp) and
  ``cyclone`` (cyclonedds' own Python API and serializer, reader taken in a WaitSet loop).

Phases:

* throughput: the publisher sends a burst back to back; the received rate is
  (received - 1) / (last receive - first receive), measured in the subscriber; the CPU
  time of each process (all threads) per message.
* latency: one message per millisecond (the publisher sleeps most of each period and spins
  the last 0.3 ms); one-way latency = receive wall clock minus the ``header.stamp`` written
  just before publishing (same host, same clock). p50 / p99 of all but the first 5 %
  (warm-up: discovery, reliable repairs of the first samples); ``1 kHz CPU us/msg``: the
  subscriber process's CPU time (all threads) per message, each handled alone, in caches
  that went cold since the last one (a small message then costs several times its CPU in
  a burst). With ``--together`` every
  mode's subscriber (one process each, started in the round's order) receives the same
  messages of one ``raw`` publisher at once: the modes are compared over the same seconds,
  which run to run moves a median latency far more than the code does (a subscriber
  started later may be served later; the order alternates between rounds).
  ``switches/msg``: the subscriber process's voluntary context switches (all threads,
  counted by the kernel) from the first message to the end, per message, in the burst and
  at 1 kHz: how many times a thread went to sleep and was woken for each message (at
  1 kHz, one that arrives alone). At 1 kHz, unlike times, it does not depend on what else
  the machine runs.

Each round runs every mode once per message and phase, in alternating order from round to
round, so a burst of load from other processes falls on all modes alike. Ratios are taken
within a round (posekit over raw: time per message, median latency) and summarised as the
median and the range over rounds; the best of the rounds is printed as well.
"""

from __future__ import annotations

import argparse
import json
import os
import socket
import statistics
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from typing import Any

LATENCY_RATE_HZ = 1000.0
#: The latency publisher spins (rather than sleeps) for this long before each message.
PACING_SPIN_S = 0.0003
IDLE_END_S = 0.6
#: The first 1/WARM_UP_SHARE of the latency phase's messages are not counted.
WARM_UP_SHARE = 20
FIRST_MESSAGE_TIMEOUT_S = 30.0
ROS2_VENV = os.environ.get(
    "POSEKIT_ROS2_VENV",
    os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".venv-ros2"))

TYPES = {"tf": "geometry_msgs/msg/TransformStamped", "image": "sensor_msgs/msg/Image"}
TOPICS = {"tf": "/bench_tf", "image": "/bench_image"}
IMAGE_H, IMAGE_W = 128, 128
#: (throughput burst, latency messages) per message, full run and --quick.
SIZES = {"tf": (20_000, 2_000), "image": (2_000, 2_000)}
QUICK_SIZES = {"tf": (5_000, 1_000), "image": (500, 1_000)}
#: Fast DDS fails a KEEP_ALL publish once ~5000 samples wait for a slow rclpy reader.
RCLPY_BURST = 5_000

Publish = Callable[[], None]
#: ``serve(done)``: receive (run the callbacks) until ``done()`` is true.
Spin = Callable[[Callable[[], bool]], None]
Close = Callable[[], None]
OnStamp = Callable[[int, int], None]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


# ---------------------------------------------------------------------------------------
# the messages, built once per process; publish() only writes the stamp


def _rosbags_message(message: str) -> tuple[Any, Any]:
    """(message, its Time class) of rosbags' generated types."""
    import numpy as np

    from posekit.msgs.cdr import get_typestore

    T = get_typestore().types
    time_cls = T["builtin_interfaces/msg/Time"]
    header = T["std_msgs/msg/Header"](stamp=time_cls(sec=0, nanosec=0), frame_id="odom")
    if message == "tf":
        return T[TYPES["tf"]](
            header=header, child_frame_id="base_link",
            transform=T["geometry_msgs/msg/Transform"](
                translation=T["geometry_msgs/msg/Vector3"](x=1.0, y=2.0, z=3.0),
                rotation=T["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0)),
        ), time_cls
    header.frame_id = "camera"
    return T[TYPES["image"]](
        header=header, height=IMAGE_H, width=IMAGE_W, encoding="rgb8", is_bigendian=0,
        step=3 * IMAGE_W, data=np.arange(3 * IMAGE_H * IMAGE_W, dtype=np.uint8),
    ), time_cls


def _posekit_message(message: str) -> Any:
    import numpy as np

    if message == "tf":
        from posekit.msgs.geometry_msgs import TransformStamped

        tf = TransformStamped(child_frame_id="base_link")
        tf.header.frame_id = "odom"
        tf.transform.translation.x, tf.transform.translation.y = 1.0, 2.0
        tf.transform.translation.z = 3.0
        return tf
    from posekit.msgs.sensor_msgs import Image

    img = Image(height=IMAGE_H, width=IMAGE_W, encoding="rgb8", step=3 * IMAGE_W,
                data=np.arange(3 * IMAGE_H * IMAGE_W, dtype=np.uint8))
    img.header.frame_id = "camera"
    return img


def _stamp_now(stamp: Any) -> None:
    stamp.sec, stamp.nanosec = divmod(time.time_ns(), 1_000_000_000)


# ---------------------------------------------------------------------------------------
# endpoints: (publish, serve, close) of one mode, transport and message


def _loop(step: Callable[[float], Any]) -> Spin:
    """``serve`` from a step that waits up to the given seconds for data and handles it."""

    def serve(done: Callable[[], bool]) -> None:
        while not done():
            step(0.02)

    return serve


def _posekit_endpoints(transport: str, mode: str, message: str, role: str,
                       on_stamp: OnStamp | None) -> tuple[Publish | None, Spin | None, Close]:
    from posekit.runtime.context import Context
    from posekit.runtime.executors import SingleThreadedExecutor
    from posekit.runtime.node import Node
    from posekit.runtime.qos import HistoryPolicy, QoSProfile

    ctx = Context()
    ctx.init(transport=transport)
    node = Node(f"bench_{role}", context=ctx)
    keep_all = QoSProfile(history=HistoryPolicy.KEEP_ALL, depth=0)
    cls = type(_posekit_message(message))
    topic = TOPICS[message]
    if role == "sub":
        assert on_stamp is not None

        def callback(msg: Any) -> None:
            stamp = msg.header.stamp
            on_stamp(stamp.sec, stamp.nanosec)

        if mode == "transport":  # the transport layer alone: no executor
            from posekit.runtime.transport import EndpointInfo

            endpoint = node.transport.subscribe(
                EndpointInfo(topic, cls, keep_all, node.get_name(), node.get_namespace(),
                             node.get_logger()), callback)
            return None, _loop(time.sleep), lambda: (endpoint.destroy(), ctx.shutdown())[1]
        if os.environ.get("BENCH_QUIET_FIRST"):  # a subscription nothing is published on
            node.create_subscription(cls, topic + "_quiet", lambda _msg: None, keep_all)
        node.create_subscription(cls, topic, callback, keep_all)
        executor = SingleThreadedExecutor(context=ctx)
        executor.add_node(node)

        def serve(done: Callable[[], bool]) -> None:
            # executor.spin(), as a user calls it (rclpy.spin); a watcher thread ends it
            def watch() -> None:
                while not done():
                    time.sleep(0.02)
                executor.shutdown()

            threading.Thread(target=watch, daemon=True).start()
            executor.spin()

        return None, serve, ctx.shutdown
    pub = node.create_publisher(cls, topic, keep_all)
    msg = _posekit_message(message)
    stamp = msg.header.stamp

    def publish() -> None:
        _stamp_now(stamp)
        pub.publish(msg)

    _wait_matched(pub.get_subscription_count)
    return publish, None, ctx.shutdown


def _zenoh_raw_endpoints(message: str, role: str, endpoint: str, on_stamp: OnStamp | None,
                         *, hop: bool = False) -> tuple[Publish | None, Spin | None, Close]:
    import itertools

    import zenoh

    from posekit.msgs.cdr import get_typestore
    from posekit.transport.zenoh_session import SessionOptions, build_peer_config
    from posekit.transport.zenoh_wire import data_key, decode_attachment, encode_attachment

    type_name = TYPES[message]
    store = get_typestore()
    session = zenoh.open(build_peer_config(SessionOptions(router_endpoint=endpoint)))
    key = data_key(int(os.environ.get("ROS_DOMAIN_ID", "0")), TOPICS[message], type_name)
    if role == "sub":
        assert on_stamp is not None
        deserialize = store.deserialize_cdr

        def callback(sample: Any) -> None:
            att = sample.attachment
            if att is None:
                return
            decode_attachment(att.to_bytes())
            stamp = deserialize(sample.payload.to_bytes(), type_name).header.stamp
            on_stamp(stamp.sec, stamp.nanosec)

        if not hop:
            sub = session.declare_subscriber(key, callback)
            return None, _loop(time.sleep), lambda: (sub.undeclare(), session.close())[1]
        # the hand-off an executor pays: zenoh's thread queues, this thread takes and decodes
        channel = session.declare_subscriber(key, zenoh.handlers.FifoChannel(1 << 16))

        def serve(done: Callable[[], bool]) -> None:
            def watch() -> None:
                while not done():
                    time.sleep(0.02)
                # a DELETE for this session only ends the recv() below (posekit's poke)
                session.delete(key, allowed_destination=zenoh.Locality.SESSION_LOCAL)

            threading.Thread(target=watch, daemon=True).start()
            while (sample := channel.recv()).kind == zenoh.SampleKind.PUT:
                callback(sample)

        return None, serve, lambda: (channel.undeclare(), session.close())[1]
    pub = session.declare_publisher(key, reliability=zenoh.Reliability.RELIABLE,
                                    congestion_control=zenoh.CongestionControl.BLOCK)
    msg, time_cls = _rosbags_message(message)
    serialize = store.serialize_cdr
    gid = bytes(16)
    seq = itertools.count(1)

    def publish() -> None:
        now = time.time_ns()
        msg.header.stamp = time_cls(sec=now // 1_000_000_000, nanosec=now % 1_000_000_000)
        pub.put(bytes(serialize(msg, type_name)), attachment=encode_attachment(next(seq), now,
                                                                               gid))

    time.sleep(1.0)  # let the peers link (the subscriber is already declared)
    return publish, None, session.close


def _cyclone_endpoints(mode: str, message: str, role: str,
                       on_stamp: OnStamp | None) -> tuple[Publish | None, Spin | None, Close]:
    """``raw``: cyclonedds' C layer moving CDR bytes, (de)serialized by rosbags.
    ``cyclone``: cyclonedds' own API and serializer."""
    from cyclonedds._clayer import ddspy_take, ddspy_write
    from cyclonedds.core import DDSStatus, InstanceState, SampleState, ViewState, WaitSet
    from cyclonedds.domain import DomainParticipant
    from cyclonedds.pub import DataWriter
    from cyclonedds.qos import Policy, Qos
    from cyclonedds.sub import DataReader
    from cyclonedds.topic import Topic
    from cyclonedds.util import duration

    from posekit.msgs.cdr import get_typestore
    from posekit.transport.dds_transport import configure_domain
    from posekit.transport.dds_types import idl_struct
    from posekit.transport.dds_wire import DiscoveryOptions

    options = DiscoveryOptions.from_env()
    configure_domain(options)  # the same loopback discovery settings as posekit
    type_name = TYPES[message]
    participant = DomainParticipant(options.domain_id)
    topic = Topic(participant, "rt" + TOPICS[message], idl_struct(type_name))
    qos = Qos(Policy.Reliability.Reliable(duration(seconds=1)), Policy.History.KeepAll)
    store = get_typestore()
    if role == "sub":
        assert on_stamp is not None
        reader = DataReader(participant, topic, qos)
        reader.set_status_mask(DDSStatus.DataAvailable)  # wake on data only
        waitset = WaitSet(participant)
        waitset.attach(reader)
        mask = SampleState.Any | ViewState.Any | InstanceState.Any
        deserialize, ref = store.deserialize_cdr, reader._ref

        def spin(seconds: float) -> None:
            waitset.wait(duration(seconds=seconds))
            if mode == "raw":
                for data, info in ddspy_take(ref, mask, 256):
                    if info.valid_data:
                        stamp = deserialize(data, type_name).header.stamp
                        on_stamp(stamp.sec, stamp.nanosec)
                return
            for m in reader.take(N=256):
                if m.sample_info.valid_data:
                    on_stamp(m.header.stamp.sec, m.header.stamp.nanosec)

        return None, _loop(spin), lambda: None
    writer = DataWriter(participant, topic, qos)
    _wait_matched(lambda: len(writer.get_matched_subscriptions()))
    if mode == "raw":
        msg, time_cls = _rosbags_message(message)
        serialize, wref = store.serialize_cdr, writer._ref

        def publish_raw() -> None:
            sec, nsec = divmod(time.time_ns(), 1_000_000_000)
            msg.header.stamp = time_cls(sec=sec, nanosec=nsec)
            ddspy_write(wref, bytes(serialize(msg, type_name)))

        publish_raw.writer = writer  # type: ignore[attr-defined]  # alive as long as used
        return publish_raw, None, lambda: None
    cy_msg = _cyclone_message(message)

    def publish_cyclone() -> None:
        _stamp_now(cy_msg.header.stamp)
        writer.write(cy_msg)

    return publish_cyclone, None, lambda: None


def _cyclone_message(message: str) -> Any:
    """The message as cyclonedds IdlStruct objects, built from the rosbags one."""
    from posekit.transport.dds_types import idl_struct

    def convert(value: Any, type_name: str) -> Any:
        import numpy as np

        from posekit.msgs.cdr import get_typestore

        _, fields = get_typestore().fielddefs[type_name]
        kwargs = {}
        for name, node in fields:
            field = getattr(value, name)
            if int(node[0]) == 2:  # a nested message
                kwargs[name] = convert(field, node[1])
            elif isinstance(field, np.ndarray):
                kwargs[name] = field.tolist()
            else:
                kwargs[name] = field
        return idl_struct(type_name)(**kwargs)

    return convert(_rosbags_message(message)[0], TYPES[message])


def _rclpy_endpoints(message: str, role: str,
                     on_stamp: OnStamp | None) -> tuple[Publish | None, Spin | None, Close]:
    import rclpy  # noqa: I001 - the real rclpy, from .venv-ros2
    from geometry_msgs.msg import TransformStamped
    from rclpy.qos import HistoryPolicy, QoSProfile
    from sensor_msgs.msg import Image

    rclpy.init()
    node = rclpy.create_node(f"bench_{role}")
    qos = QoSProfile(history=HistoryPolicy.KEEP_ALL, depth=0)
    cls: Any = TransformStamped if message == "tf" else Image
    if role == "sub":
        assert on_stamp is not None
        node.create_subscription(cls, TOPICS[message], lambda m: on_stamp(
            m.header.stamp.sec, m.header.stamp.nanosec), qos)
        return None, _loop(lambda s: rclpy.spin_once(node, timeout_sec=s)), rclpy.shutdown
    pub = node.create_publisher(cls, TOPICS[message], qos)
    msg = cls()
    if message == "tf":
        msg.header.frame_id, msg.child_frame_id = "odom", "base_link"
        msg.transform.translation.x, msg.transform.translation.y = 1.0, 2.0
        msg.transform.translation.z, msg.transform.rotation.w = 3.0, 1.0
    else:
        msg.header.frame_id, msg.encoding = "camera", "rgb8"
        msg.height, msg.width, msg.step = IMAGE_H, IMAGE_W, 3 * IMAGE_W
        msg.data = bytes(i % 256 for i in range(3 * IMAGE_H * IMAGE_W))
    stamp = msg.header.stamp

    def publish() -> None:
        _stamp_now(stamp)
        pub.publish(msg)

    _wait_matched(pub.get_subscription_count)
    return publish, None, rclpy.shutdown


def _endpoints(transport: str, mode: str, message: str, role: str, endpoint: str,
               on_stamp: OnStamp | None = None) -> tuple[Publish | None, Spin | None, Close]:
    if mode in ("posekit", "transport", "before"):
        mode = "posekit" if mode == "before" else mode
        return _posekit_endpoints(transport, mode, message, role, on_stamp)
    if mode == "rclpy":
        return _rclpy_endpoints(message, role, on_stamp)
    if transport == "dds":
        return _cyclone_endpoints(mode, message, role, on_stamp)
    return _zenoh_raw_endpoints(message, role, endpoint, on_stamp, hop=mode == "hop")


def _wait_matched(count: Callable[[], int]) -> None:
    """Until ``count()`` reaches the subscribers the parent started (BENCH_SUBSCRIBERS)."""
    expected = int(os.environ.get("BENCH_SUBSCRIBERS", "1"))
    deadline = time.monotonic() + 15
    while count() < expected and time.monotonic() < deadline:
        time.sleep(0.05)
    time.sleep(0.5)  # let reliable delivery settle (the peers' locators, links)


# ---------------------------------------------------------------------------------------
# child processes


def _voluntary_switches() -> int:
    """Voluntary context switches of this process so far, all threads (a thread that
    blocks, e.g. to wait for the next message, and is woken again counts one)."""
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_nvcsw


def child_sub(transport: str, mode: str, message: str, endpoint: str) -> None:
    """Receive until the stream has been idle for IDLE_END_S after the first message."""
    recv: list[int] = []
    lat: list[int] = []
    now_wall, now_mono = time.time_ns, time.monotonic_ns

    cpu_first = [0.0]  # process CPU time at the first message
    switches_first = [0]  # the process's voluntary context switches then

    def on_stamp(sec: int, nsec: int) -> None:
        t = now_wall()
        if not recv:
            cpu_first[0] = time.process_time()
            switches_first[0] = _voluntary_switches()
        recv.append(now_mono())
        lat.append(t - (sec * 1_000_000_000 + nsec))

    _, serve, close = _endpoints(transport, mode, message, "sub", endpoint, on_stamp)
    assert serve is not None
    print("ready", flush=True)
    give_up = time.monotonic() + FIRST_MESSAGE_TIMEOUT_S
    state = {"count": 0, "since": 0.0}

    def done() -> bool:
        """Idle for IDLE_END_S after the first message (or no message at all)."""
        now = time.monotonic()
        if not state["since"]:
            if not recv and now < give_up:
                return False
            state["since"] = now
        if len(recv) != state["count"]:
            state.update(count=len(recv), since=now)
        return now - state["since"] >= IDLE_END_S

    serve(done)
    cpu = time.process_time() - cpu_first[0]
    switches = _voluntary_switches() - switches_first[0]
    close()
    out: dict[str, Any] = {"count": len(recv), "cpu_s": cpu,
                           "switches": switches / max(1, len(recv))}
    if len(recv) >= 2:
        out["rate"] = (len(recv) - 1) / ((recv[-1] - recv[0]) * 1e-9)
    lat = lat[len(lat) // WARM_UP_SHARE:]  # discovery and first-sample repairs excluded
    if lat:
        lat.sort()
        out.update(p50=lat[len(lat) // 2], p99=lat[int(len(lat) * 0.99)])
    print(json.dumps(out), flush=True)


def child_pub(transport: str, mode: str, message: str, endpoint: str, phase: str,
              count: int) -> None:
    """Publish ``count`` messages (throughput: back to back; latency: at 1 kHz)."""
    publish, _, close = _endpoints(transport, "posekit" if mode == "transport" else mode,
                                   message, "pub", endpoint)
    assert publish is not None
    cpu = 0.0
    if phase == "throughput":
        cpu0 = time.process_time()
        for _ in range(count):
            publish()
        cpu = time.process_time() - cpu0
    else:
        period = 1.0 / LATENCY_RATE_HZ
        next_at = time.perf_counter()
        for _ in range(count):
            publish()
            next_at += period
            # sleep most of the period (the cores stay free for the receivers), then spin
            # the rest: a sleep alone overshoots by up to 0.1 ms here
            ahead = next_at - time.perf_counter() - PACING_SPIN_S
            if ahead > 0:
                time.sleep(ahead)
            while time.perf_counter() < next_at:
                pass
    print(json.dumps({"send_cpu_us": 1e6 * cpu / count}), flush=True)
    # Stay connected until the subscriber is done (the parent closes our stdin then):
    # what is still queued for a slower subscriber must not be dropped by closing.
    sys.stdin.read()
    close()


# ---------------------------------------------------------------------------------------
# orchestration


def run_pair(transport: str, mode: str, message: str, phase: str, count: int,
             domain_id: int, before_src: str | None = None) -> dict[str, Any]:
    """One publisher process and one subscriber process of ``mode``: the subscriber's
    figures plus the publisher's CPU per message. Mode ``before`` is ``posekit`` importing
    posekit from ``before_src`` (another checkout's ``src``)."""
    return run_group(transport, [mode], mode, message, phase, count, domain_id,
                     before_src)[mode]


def run_group(transport: str, sub_modes: list[str], pub_mode: str, message: str, phase: str,
              count: int, domain_id: int, before_src: str | None = None
              ) -> dict[str, dict[str, Any]]:
    """A subscriber process per mode of ``sub_modes`` (started in that order), all receiving
    the messages of one publisher process of ``pub_mode``: each subscriber's figures plus the
    publisher's CPU per message."""
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("ZENOH_", "ROS_", "RMW_", "POSEKIT_", "CYCLONEDDS_"))}
    env.update(ROS_DOMAIN_ID=str(domain_id), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
               RMW_IMPLEMENTATION="rmw_fastrtps_cpp", PYTHONUNBUFFERED="1",
               BENCH_SUBSCRIBERS=str(len(sub_modes)))

    def command(mode: str, *args: str) -> tuple[list[str], dict[str, str]]:
        python = os.path.join(ROS2_VENV, "bin", "python") if mode == "rclpy" else sys.executable
        own = dict(env)
        if mode == "before" and before_src:
            own["PYTHONPATH"] = os.path.abspath(before_src)
        return [python, os.path.abspath(__file__), "--child", *args], own

    router = None
    endpoint = "-"
    if transport == "zenoh":
        from posekit.transport.zenoh_session import open_router

        endpoint = f"tcp/127.0.0.1:{free_port()}"
        router = open_router(endpoint)  # the role rmw_zenohd plays
        env.update(POSEKIT_ZENOH_ROUTER=endpoint)
    subs: dict[str, subprocess.Popen[str]] = {}
    pub = None
    try:
        for mode in sub_modes:
            argv, own_env = command(mode, "sub", transport, mode, message, endpoint)
            subs[mode] = sub = subprocess.Popen(argv, env=own_env, stdout=subprocess.PIPE,
                                                text=True)
            assert sub.stdout is not None
            if sub.stdout.readline().strip() != "ready":
                raise RuntimeError(f"{transport} {mode} subscriber did not start")
        argv, own_env = command(pub_mode, "pub", transport, pub_mode, message, endpoint, phase,
                                str(count))
        pub = subprocess.Popen(argv, env=own_env, stdin=subprocess.PIPE,
                               stdout=subprocess.PIPE, text=True)
        assert pub.stdin is not None
        assert pub.stdout is not None
        # the publisher's figures once it has sent everything, the subscribers' once the
        # stream went idle; then the publisher may disconnect
        procs = [pub, *subs.values()]
        give_up = threading.Timer(300, lambda: [p.kill() for p in procs])
        give_up.start()
        try:
            pub_line = pub.stdout.readline()
            lines = {mode: sub.stdout.readline() for mode, sub in subs.items()
                     if sub.stdout is not None}
            pub.stdin.close()
            for proc in procs:
                proc.wait(timeout=60)
        finally:
            give_up.cancel()
        if not pub_line or not all(lines.values()):
            raise RuntimeError(f"{transport} {sub_modes}: a child ended without its figures")
        results = {}
        for mode, line in lines.items():
            results[mode] = dict(json.loads(line))
            results[mode].update(json.loads(pub_line))
        return results
    finally:
        for proc in [pub, *subs.values()]:
            if proc is not None and proc.poll() is None:
                proc.kill()
                proc.wait()
        if router is not None:
            router.close()


def _spread(values: list[float], fmt: str) -> str:
    if not values:
        return "-"
    med = statistics.median(values)
    if len(values) == 1:
        return format(med, fmt)
    return f"{format(med, fmt)} ({format(min(values), fmt)}-{format(max(values), fmt)})"


def _cpu_per_msg(figures: dict[str, dict[str, Any]], phase: str = "throughput") -> float:
    """The subscriber process's CPU µs (all threads) per message received in ``phase``."""
    part = figures[phase]
    return float(part["cpu_s"]) * 1e6 / max(1, int(part["count"]))


def report(transport: str, message: str, modes: list[str], sizes: tuple[int, int],
           rounds: list[dict[str, dict[str, dict[str, Any]]]]) -> None:
    """One table per transport and message: each mode's median (range) over the rounds,
    then posekit's ratios to raw taken within each round (> 1: posekit costs more)."""
    burst, n_lat = sizes
    print(f"\n== {transport}, {message} ({TYPES[message]}); throughput: burst of {burst}; "
          f"latency: {n_lat} msgs at {LATENCY_RATE_HZ:.0f} Hz; {len(rounds)} round(s): "
          "median (min-max)")
    print(f"{'mode':<10}{'recv msgs/s':>26}{'recv CPU us/msg':>24}{'send CPU us/msg':>24}"
          f"{'burst switches/msg':>22}{'p50 us':>24}{'p99 us':>24}{'1 kHz switches/msg':>22}"
          f"{'1 kHz CPU us/msg':>22}")

    def col(mode: str, phase: str, key: str, scale: float = 1.0) -> list[float]:
        return [r[mode][phase][key] * scale for r in rounds
                if key in r.get(mode, {}).get(phase, {})]

    for mode in modes:
        cpu = [_cpu_per_msg(r[mode]) for r in rounds if mode in r]
        lone_cpu = [_cpu_per_msg(r[mode], "latency") for r in rounds if mode in r]
        counts = {r[mode]["throughput"]["count"] for r in rounds if mode in r}
        short = "" if counts <= {burst} else f"  received {sorted(counts)} of {burst}"
        print(f"{mode:<10}{_spread(col(mode, 'throughput', 'rate'), ',.0f'):>26}"
              f"{_spread(cpu, '.1f'):>24}"
              f"{_spread(col(mode, 'throughput', 'send_cpu_us'), '.1f'):>24}"
              f"{_spread(col(mode, 'throughput', 'switches'), '.2f'):>22}"
              f"{_spread(col(mode, 'latency', 'p50', 1e-3), '.0f'):>24}"
              f"{_spread(col(mode, 'latency', 'p99', 1e-3), '.0f'):>24}"
              f"{_spread(col(mode, 'latency', 'switches'), '.2f'):>22}"
              f"{_spread(lone_cpu, '.1f'):>22}"
              f"{short}")
    pairs = [(mode, "raw") for mode in modes if mode != "raw"]
    pairs += [("posekit", "hop")] if "hop" in modes else []
    for mode, base in pairs:
        both = [r for r in rounds if mode in r and base in r]
        tput = [r[base]["throughput"]["rate"] / r[mode]["throughput"]["rate"] for r in both]
        cpu_ratio = [_cpu_per_msg(r[mode]) / _cpu_per_msg(r[base]) for r in both]
        lone_cpu = [_cpu_per_msg(r[mode], "latency") / _cpu_per_msg(r[base], "latency")
                    for r in both]
        p50 = [r[mode]["latency"]["p50"] / r[base]["latency"]["p50"] for r in both]
        best_t = (max(col(base, "throughput", "rate"))
                  / max(col(mode, "throughput", "rate")))
        best_l = min(col(mode, "latency", "p50")) / min(col(base, "latency", "p50"))
        print(f"  {mode} / {base}, per round: time per message {_spread(tput, '.2f')}, median "
              f"latency {_spread(p50, '.2f')}; best of rounds: {best_t:.2f}, {best_l:.2f}; "
              f"receive CPU per message {_spread(cpu_ratio, '.2f')}, at 1 kHz "
              f"{_spread(lone_cpu, '.2f')}")
        # The subscriber started first is served first (--together): the per-round ratios
        # fall in two groups by the order, so also compare the medians of each order.
        by_order: dict[str, list[dict[str, dict[str, dict[str, Any]]]]] = {}
        for r in both:
            by_order.setdefault(" first" if list(r).index(mode) < list(r).index(base)
                                else " second", []).append(r)
        if len(by_order) == 2 and all(len(v) > 1 for v in by_order.values()):
            ratios = {place: statistics.median(r[mode]["latency"]["p50"] for r in group)
                      / statistics.median(r[base]["latency"]["p50"] for r in group)
                      for place, group in sorted(by_order.items())}
            # Each order favours one side by about as much: their geometric mean is the
            # ratio with the order balanced out.
            print(f"    median latency, ratio of the medians of the rounds where {mode} was "
                  "started" + ";".join(f"{place}: {ratio:.2f}" for place, ratio in ratios.items())
                  + f"; both orders balanced (geometric mean): "
                  f"{statistics.geometric_mean(ratios.values()):.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--transport", choices=("zenoh", "dds", "all"), default="all")
    parser.add_argument("--messages", default="tf,image", help="comma-separated: tf,image")
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--quick", action="store_true", help="one round of short runs")
    parser.add_argument("--no-transport-mode", action="store_true",
                        help="skip the transport-layer-alone mode")
    parser.add_argument("--references", action="store_true",
                        help="DDS: add the real rclpy (Fast DDS) and cyclonedds' Python API")
    parser.add_argument("--before", metavar="SRC",
                        help="add mode 'before': posekit imported from SRC, another checkout's "
                             "src directory (e.g. git worktree add /tmp/before <commit>)")
    parser.add_argument("--hop", action="store_true",
                        help="Zenoh: add mode 'hop', raw with the executor's thread hand-off")
    parser.add_argument("--together", action="store_true",
                        help="latency: every mode's subscriber receives one raw publisher's "
                             "messages at the same time (paired in time, not in turn)")
    parser.add_argument("--quiet-first", action="store_true",
                        help="posekit's subscriber node creates a subscription of a silent "
                             "topic before the measured one")
    parser.add_argument("--child", nargs="+", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        role, transport, mode, message, endpoint, *rest = args.child
        if role == "sub":
            child_sub(transport, mode, message, endpoint)
        else:
            child_pub(transport, mode, message, endpoint, rest[0], int(rest[1]))
        return
    messages = [m for m in args.messages.split(",") if m]
    if args.quiet_first:
        os.environ["BENCH_QUIET_FIRST"] = "1"  # inherited by the children
    transports = ["zenoh", "dds"] if args.transport == "all" else [args.transport]
    rounds_n = 1 if args.quick else args.rounds
    import platform
    from importlib.metadata import version

    print(f"python {platform.python_version()}, eclipse-zenoh {version('eclipse-zenoh')}, "
          f"cyclonedds {version('cyclonedds')}, rosbags {version('rosbags')}; load average "
          f"at start "
          f"{os.getloadavg()[0]:.1f}")
    domain = 180
    for transport in transports:
        modes = ["raw", "posekit"] + ([] if args.no_transport_mode else ["transport"])
        modes += ["before"] if args.before else []
        modes += ["hop"] if args.hop and transport == "zenoh" else []
        if args.references and transport == "dds":
            modes += ["cyclone", "rclpy"]
        for message in messages:
            sizes = (QUICK_SIZES if args.quick else SIZES)[message]
            rounds: list[dict[str, dict[str, dict[str, Any]]]] = []
            for i in range(rounds_n):
                order = modes if i % 2 == 0 else modes[::-1]
                this: dict[str, dict[str, dict[str, Any]]] = {m: {} for m in order}
                if args.together:  # every mode's subscriber on the same messages at once
                    domain = 180 + (domain - 179) % 50
                    group = run_group(transport, order, "raw", message, "latency", sizes[1],
                                      domain, args.before)
                    for mode in order:
                        this[mode]["latency"] = group[mode]
                for phase, n in (("throughput", sizes[0]), ("latency", sizes[1])):
                    if phase == "latency" and args.together:
                        continue
                    for mode in order:
                        if mode == "rclpy" and phase == "throughput":
                            n = min(n, RCLPY_BURST)
                        domain = 180 + (domain - 179) % 50  # each pair on its own domain
                        this[mode][phase] = run_pair(transport, mode, message, phase, n,
                                                     domain, args.before)
                rounds.append(this)
                print(f"   round {i + 1}: " + ", ".join(
                    f"{m} {this[m]['throughput'].get('rate', 0):,.0f}/s "
                    f"{this[m]['latency'].get('p50', 0) / 1e3:.0f}us" for m in order),
                    flush=True)
            report(transport, message, modes, sizes, rounds)
    print(f"\nload average at end {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
