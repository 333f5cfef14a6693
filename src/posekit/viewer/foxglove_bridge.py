"""Serve a running posekit system to the Foxglove app (``posekit view --foxglove``).

    from posekit.viewer.foxglove_bridge import FoxgloveBridge
    bridge = FoxgloveBridge(run.context.transport(), port=8766)
    bridge.start()        # ws://127.0.0.1:8766, subprotocols foxglove.sdk.v1 and
    ...                   # foxglove.websocket.v1
    ...
    bridge.stop()

The bridge uses the optional ``foxglove-sdk`` package (``pip install 'posekit[foxglove]'``),
imported only when a bridge starts; without it :meth:`FoxgloveBridge.start` raises
:class:`~posekit.viewer.errors.ViewerError` saying what to install.

Like :class:`~posekit.viewer.taps.ViewerTap` it listens on a transport without a node in any
executor, through :class:`posekit.runtime.observe.TopicObserver`: it subscribes only to
topics that have a publisher, with a QoS every publisher matches (best effort as soon as one
publisher is, transient local when all are: latched ``/tf_static`` and
``/robot_description``), and a topic whose publishers leave is unadvertised (its channel
closed) and advertised again if it comes back. Every topic whose type has a ROS 2 Jazzy
definition (posekit's messages, and any other Jazzy message such as
``sensor_msgs/msg/PointCloud2``) becomes one Foxglove channel with schema encoding
``ros2msg`` (the definition text with its dependencies, the format ROS 2's MCAP writer uses)
and message encoding ``cdr``, so Foxglove decodes the messages natively (``LaserScan`` and
``PointCloud2`` go to its 3D and plot panels as from a ROS 2 system). Messages are logged
with ``log_time`` from the same clock as ``time``.

Both WebSocket subprotocols are accepted: ``foxglove.sdk.v1`` (the Foxglove app, foxglove-sdk)
and ``foxglove.websocket.v1`` (older clients and the open-source Lichtblick fork; the protocol
is the same, only its name changed). foxglove-sdk's server answers the first only, so it
listens on a free loopback port and a small aiohttp front on ``host:port`` accepts either
name and relays the frames both ways unchanged. The front answers only requests whose
``Host`` names this server (as the browser viewer does, :mod:`posekit.viewer.access`).

Capabilities: ``time`` (the server's clock: ``/clock`` when the system publishes it, else
``clock_ns``, else the wall clock; so Foxglove's timeline runs on simulated time in a
simulated run) and ``clientPublish`` with message encoding ``cdr`` or ``json``: a client
advertises a topic with a ROS 2 type (e.g. ``geometry_msgs/msg/PoseStamped`` on
``goal_pose``) and the bridge publishes what it sends on the transport (at most 32 client
channels at a time). A ``json`` message is an object of the message's fields (nested
messages as objects, ``header.stamp`` as ``{sec, nanosec}``); fields it leaves out keep
their defaults, and a field the type does not have or a value that does not fit is refused
with one logged line (:func:`message_from_json`).

Latched topics are re-sent to late subscribers: ``/tf_static`` keeps the newest transform per
child frame and re-sends them as one TFMessage whenever a client subscribes to it; any other
topic observed transient local (every publisher latches: ``/robot_description``) keeps its
last messages (as many as its publishers keep, at most :data:`MAX_LATCHED`) and re-sends them
to a client that subscribes (the SDK logs
to every subscriber of a channel, so earlier subscribers get the same static transforms
again, which is harmless).
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import threading
import time
from collections import deque
from collections.abc import Callable
from typing import Any

from posekit.msgs.errors import UnknownMessageTypeError
from posekit.msgs.tf2_msgs import TFMessage
from posekit.runtime.logging import RcutilsLogger, get_logger
from posekit.runtime.observe import ObservedTopic, TopicObserver, TopicSkipped
from posekit.runtime.qos import DurabilityPolicy, HistoryPolicy, QoSProfile
from posekit.runtime.ratelimit import RateLimitedLog
from posekit.runtime.transport import (
    EndpointInfo,
    MessageSink,
    PublisherEndpoint,
    TopicTypeMismatchError,
    Transport,
)
from posekit.time import stamp_to_ns
from posekit.viewer._loop_thread import LoopThread
from posekit.viewer.errors import ViewerError

__all__ = ["DEFAULT_PORT", "FOXGLOVE_SUBPROTOCOL", "FOXGLOVE_SUBPROTOCOLS", "FoxgloveBridge",
           "message_from_json"]

#: Default TCP port (the browser viewer uses 8765).
DEFAULT_PORT = 8766
#: WebSocket subprotocol of foxglove-sdk's server.
FOXGLOVE_SUBPROTOCOL = "foxglove.sdk.v1"
#: Every subprotocol name the bridge accepts (the same protocol under its old name too).
FOXGLOVE_SUBPROTOCOLS = (FOXGLOVE_SUBPROTOCOL, "foxglove.websocket.v1")
_CLOCK_TOPIC = "/clock"
_CLOCK_TYPE = "rosgraph_msgs/msg/Clock"
#: Without /clock messages for this long (wall s), ``time`` comes from the fallback clock.
_CLOCK_SILENT_S = 1.0
_TIME_PERIOD_S = 0.1
_MAX_CLIENT_CHANNELS = 32
#: Message encodings a client may publish in.
_CLIENT_ENCODINGS = ("cdr", "json")
_PUBLISH_QOS = QoSProfile(depth=10)
_STATIC_TOPIC = "/tf_static"
#: Messages kept per latched (transient-local) topic for clients that subscribe later.
MAX_LATCHED = 100
#: Topics the bridge serves at most (the viewer's bound; the topic names are the peers').
MAX_TOPICS = 200
#: Static frames kept for late clients at most (a TF listener's bound).
MAX_STATIC_FRAMES = 10_000
_NODE_NAME = "posekit_foxglove_bridge"


def _import_foxglove() -> Any:
    try:
        import foxglove
    except ImportError as exc:
        raise ViewerError(
            "the Foxglove bridge needs the foxglove-sdk package: "
            f"pip install 'posekit[foxglove]' (or foxglove-sdk>=0.30) ({exc})"
        ) from exc
    return foxglove


class FoxgloveBridge:
    """Publishes every topic of ``transport`` on a foxglove-sdk WebSocket server.

    Args:
        transport: the transport of the system to serve (``context.transport()``).
        host: bind address (default loopback: this machine only).
        port: TCP port (0: any free port; see :attr:`port` after :meth:`start`).
        clock_ns: the server's clock in ns when the system publishes no ``/clock`` (default
            the wall clock); it stamps ``log_time`` and the ``time`` messages.
        refresh_period: seconds between topic discoveries in the background (0: only when
            :meth:`refresh` is called).
        name: the server name shown by Foxglove.
        allow_hosts: more ``Host`` header values accepted (``name`` or ``name:port``;
            ``"*"``: any), as ``posekit view --allow-host``.
        allow_origins: more WebSocket ``Origin`` values accepted (``scheme://host:port``;
            ``"*"``: any), as ``posekit view --allow-origin``; a browser page from anywhere
            else is refused, since ``clientPublish`` lets a client publish on the graph.
    """

    def __init__(
        self,
        transport: Transport,
        *,
        host: str = "127.0.0.1",
        port: int = DEFAULT_PORT,
        clock_ns: Callable[[], int] | None = None,
        refresh_period: float = 1.0,
        name: str = "posekit",
        logger: RcutilsLogger | None = None,
        allow_hosts: tuple[str, ...] | list[str] = (),
        allow_origins: tuple[str, ...] | list[str] = (),
    ) -> None:
        if not 0 <= port <= 65535:
            raise ValueError(f"port must be in 0..65535, got {port}")
        if refresh_period < 0:
            raise ValueError(f"refresh_period must be >= 0, got {refresh_period}")
        self.transport = transport
        self.host = host
        self.requested_port = int(port)
        self.name = name
        self.refresh_period = float(refresh_period)
        self.logger = logger or get_logger(_NODE_NAME)
        self._clock_fn = clock_ns or time.time_ns
        self.allow_hosts = frozenset(h.strip().lower() for h in allow_hosts if h.strip())
        self.allow_origins = frozenset(
            o.strip().lower().rstrip("/") for o in allow_origins if o.strip()
        )
        self._sim_clock_ns: int | None = None  # newest /clock (ns)
        self._sim_clock_seen = 0.0  # monotonic s of the newest /clock
        self._warn = RateLimitedLog(self.logger.warning)
        # one line per skipped topic; a flood of peer-chosen names is rate limited
        self._skip_log = RateLimitedLog(self.logger.warning)
        self._publishers: dict[tuple[int, int], tuple[PublisherEndpoint, type, str]] = {}
        self._front: _SubprotocolFront | None = None
        self._lock = threading.Lock()
        self._channels: dict[str, Any] = {}
        self._observer = TopicObserver(
            transport, self._sink_for, on_removed=self._remove_channel,
            on_skipped=self._log_skip, node_name=_NODE_NAME, depth=10,
            resolve=_channel_class, logger=self.logger, max_topics=MAX_TOPICS,
            priority=(_STATIC_TOPIC, "/tf", "/clock"),  # served first when the bound is hit
        )
        self._static: dict[str, Any] = {}  # child frame -> newest static TransformStamped
        self._latched: dict[str, deque[bytes]] = {}  # transient-local topic -> last payloads
        self._fox: Any = None
        self._context: Any = None
        self._server: Any = None
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._closed = False

    # -- life cycle ------------------------------------------------------------------------
    def start(self) -> None:
        """Start the WebSocket server and subscribe to the current topics.

        Raises:
            ViewerError: foxglove-sdk is not installed, or the server cannot listen.
        """
        if self._server is not None:
            return
        if self._closed:
            raise ViewerError("the Foxglove bridge was stopped; create a new one")
        fox = _import_foxglove()
        self._fox = fox
        # A private context: channels reach this server only, not the SDK's global one.
        self._context = fox.Context()
        bridge = self

        listener_base: Any = fox.websocket.ServerListener  # its methods default to no-ops

        class _Listener(listener_base):  # type: ignore[misc]
            def on_subscribe(self, client: Any, channel: Any) -> None:
                if channel.topic == _STATIC_TOPIC:
                    bridge._resend_static()
                else:
                    bridge._resend_latched(str(channel.topic))

            def on_client_advertise(self, client: Any, channel: Any) -> None:
                bridge._client_advertise(int(client.id), channel)

            def on_client_unadvertise(self, client: Any, client_channel_id: int) -> None:
                bridge._client_unadvertise(int(client.id), int(client_channel_id))

            def on_message_data(self, client: Any, client_channel_id: int, data: bytes) -> None:
                bridge._client_message(int(client.id), int(client_channel_id), data)

        capability = fox.websocket.Capability
        try:
            # The SDK's server speaks foxglove.sdk.v1 only: on loopback, behind the front.
            self._server = fox.start_server(
                name=self.name,
                host="127.0.0.1",
                port=0,
                capabilities=[capability.Time, capability.ClientPublish],
                supported_encodings=["cdr", "json"],
                server_listener=_Listener(),
                context=self._context,
            )
        except Exception as exc:  # the SDK raises its own error types
            raise ViewerError(f"cannot start foxglove-sdk's server: {exc}") from exc
        self._front = _SubprotocolFront(self, int(self._server.port))
        try:
            self._front.start()
        except OSError as exc:
            self._server.stop()
            self._server = None
            self._front = None
            raise ViewerError(
                f"cannot serve Foxglove on {self.host}:{self.requested_port}: {exc}"
            ) from exc
        self.refresh()
        self._thread = threading.Thread(
            target=self._background, name="posekit-foxglove", daemon=True
        )
        self._thread.start()

    @property
    def port(self) -> int:
        """The port the server listens on (after :meth:`start`)."""
        if self._front is None:
            raise ViewerError("the Foxglove bridge is not started")
        return self._front.port

    @property
    def url(self) -> str:
        """``ws://host:port`` to open as a Foxglove WebSocket connection."""
        return f"ws://{self.host}:{self.port}"

    def serve_forever(self) -> None:
        """Block until :meth:`stop` (from another thread) or KeyboardInterrupt."""
        while not self._stop.wait(0.5):
            pass

    def stop(self) -> None:
        """Unsubscribe, close the channels and stop the server (idempotent)."""
        self._closed = True
        self._stop.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=5.0)
        self._observer.close()
        with self._lock:
            endpoints = [p for p, _, _ in self._publishers.values()]
            channels = list(self._channels.values())
            self._channels.clear()
            self._publishers.clear()
        if self._front is not None:
            self._front.stop()
            self._front = None
        for endpoint in endpoints:
            try:
                endpoint.destroy()
            except Exception as exc:  # closing transport: nothing more to do
                self.logger.debug(f"foxglove bridge: destroying a subscription failed: {exc}")
        for channel in channels:
            channel.close()
        if self._server is not None:
            self._server.stop()
            self._server = None

    def __enter__(self) -> FoxgloveBridge:
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()

    # -- topics ----------------------------------------------------------------------------
    def topics(self) -> list[str]:
        """Topics served as channels, sorted."""
        with self._lock:
            return sorted(self._channels)

    def skipped(self) -> dict[str, str]:
        """Topics not served, with the reason."""
        return self._observer.skipped

    def refresh(self) -> list[str]:
        """Serve topics that appeared since the last call; returns the topics added.

        Topics whose publishers left are unadvertised.
        """
        if self._closed or self._server is None:
            return []
        return self._observer.refresh()

    def _background(self) -> None:
        """Send ``time`` every 0.1 s while no /clock drives it; refresh topics periodically."""
        next_refresh = time.monotonic() + self.refresh_period
        while not self._stop.wait(_TIME_PERIOD_S):
            if time.monotonic() - self._sim_clock_seen > _CLOCK_SILENT_S:
                self._broadcast_time(self.now_ns())
            if self.refresh_period > 0 and time.monotonic() >= next_refresh:
                next_refresh = time.monotonic() + self.refresh_period
                self.refresh()

    # -- time ------------------------------------------------------------------------------
    def now_ns(self) -> int:
        """The server's clock (ns).

        The newest ``/clock`` while it is published (within the last second), else ``clock_ns``
        (the wall clock by default).
        """
        sim = self._sim_clock_ns
        if sim is not None and time.monotonic() - self._sim_clock_seen <= _CLOCK_SILENT_S:
            return sim
        return int(self._clock_fn())

    def _on_clock(self, msg: Any) -> None:
        ns = stamp_to_ns(msg.clock)
        self._sim_clock_ns = ns
        self._sim_clock_seen = time.monotonic()
        self._broadcast_time(ns)

    def _broadcast_time(self, ns: int) -> None:
        server = self._server
        if server is None or self._closed or ns < 0:
            return
        try:
            server.broadcast_time(ns)
        except Exception as exc:  # stopping server: nothing to tell
            self.logger.debug(f"foxglove bridge: time not sent: {exc}")

    # -- clientPublish ---------------------------------------------------------------------
    def _client_advertise(self, client_id: int, channel: Any) -> None:
        from posekit.msgs.cdr import serializable_type

        topic = "/" + str(channel.topic).lstrip("/")
        where = f"client channel '{topic}'"
        encoding = str(channel.encoding)
        if encoding not in _CLIENT_ENCODINGS:
            self._warn("foxglove bridge: refused a " + where,
                       f"encoding {encoding!r} (cdr or json)")
            return
        try:
            _, msg_class = serializable_type(str(channel.schema_name or ""))
        except (LookupError, ValueError, UnknownMessageTypeError):
            self._warn("foxglove bridge: refused a " + where,
                       f"type {channel.schema_name!r} has no ROS 2 message definition")
            return
        info = EndpointInfo(topic, msg_class, _PUBLISH_QOS, _NODE_NAME, "/", self.logger)
        with self._lock:
            if self._closed or len(self._publishers) >= _MAX_CLIENT_CHANNELS:
                full, known = not self._closed, False
            else:
                full, known = False, (client_id, int(channel.id)) in self._publishers
        if full:
            self._warn("foxglove bridge: refused a " + where,
                       f"already {_MAX_CLIENT_CHANNELS} client channels")
            return
        if known:
            return
        try:
            publisher = self.transport.advertise(info)
        except (TopicTypeMismatchError, ValueError) as exc:
            self._warn("foxglove bridge: refused a " + where, str(exc))
            return
        with self._lock:
            self._publishers[(client_id, int(channel.id))] = (publisher, msg_class, encoding)
        self.logger.info(f"foxglove bridge: a client publishes {channel.schema_name} on {topic}")

    def _client_unadvertise(self, client_id: int, channel_id: int) -> None:
        with self._lock:
            entry = self._publishers.pop((client_id, channel_id), None)
        if entry is not None:
            with contextlib.suppress(Exception):
                entry[0].destroy()

    def _client_message(self, client_id: int, channel_id: int, data: bytes) -> None:
        from posekit.msgs.cdr import from_cdr

        with self._lock:
            entry = self._publishers.get((client_id, channel_id))
        if entry is None:
            return
        publisher, msg_class, encoding = entry
        try:
            if encoding == "json":
                msg = message_from_json(bytes(data), msg_class)
            else:
                msg = from_cdr(bytes(data), msg_class)
            publisher.publish(msg)
        except Exception as exc:  # a malformed message from a client: one line, keep going
            self._warn("foxglove bridge: dropped a client message",
                       f"{type(exc).__name__}: {exc}")

    def _log_skip(self, topic: str, reason: str) -> None:
        self._skip_log(f"foxglove bridge: not serving '{topic}'", reason)

    def _sink_for(self, observed: ObservedTopic) -> MessageSink:
        """Advertise a channel for a topic the observer starts observing."""
        from posekit.msgs.cdr import get_typestore

        type_name = observed.type_name
        try:
            definition, _ = get_typestore().generate_msgdef(type_name, ros_version=2)
        except (LookupError, ValueError, AssertionError) as exc:
            raise TopicSkipped(f"type {type_name!r} has no ROS 2 message definition "
                               f"({exc})") from None
        fox = self._fox
        schema = fox.Schema(name=type_name, encoding="ros2msg", data=definition.encode())
        channel = fox.Channel(
            observed.name, schema=schema, message_encoding="cdr", context=self._context
        )
        latched: deque[bytes] | None = None
        if (observed.qos.durability == DurabilityPolicy.TRANSIENT_LOCAL
                and observed.name != _STATIC_TOPIC):
            keep = sum(p.depth if p.history == HistoryPolicy.KEEP_LAST else MAX_LATCHED
                       for p in observed.offered)
            latched = deque(maxlen=max(1, min(keep, MAX_LATCHED)))
        with self._lock:
            self._channels[observed.name] = channel
            if latched is not None:
                self._latched[observed.name] = latched
        return self._make_sink(observed.name, type_name, channel, latched)

    def _remove_channel(self, topic: str) -> None:
        """Unadvertise the channel of a topic no longer observed."""
        with self._lock:
            channel = self._channels.pop(topic, None)
            if topic == _STATIC_TOPIC:
                self._static.clear()
            self._latched.pop(topic, None)
        if channel is not None:
            channel.close()

    def _make_sink(self, topic: str, type_name: str, channel: Any,
                   latched: deque[bytes] | None = None) -> Callable[[Any], None]:
        from posekit.msgs.cdr import to_cdr

        is_static = topic == _STATIC_TOPIC and type_name == TFMessage.__msgtype__
        is_clock = topic == _CLOCK_TOPIC and type_name == _CLOCK_TYPE

        def sink(msg: Any) -> None:
            if self._closed:
                return
            try:
                if is_clock:
                    self._on_clock(msg)
                if is_static:
                    with self._lock:
                        for t in msg.transforms:
                            if (len(self._static) < MAX_STATIC_FRAMES
                                    or t.child_frame_id in self._static):
                                self._static[t.child_frame_id] = t
                data = to_cdr(msg, type_name)
                if latched is not None:
                    with self._lock:
                        latched.append(data)
                channel.log(data, log_time=self.now_ns())
            except Exception as exc:  # malformed message: log, keep running
                self.logger.warning(
                    f"foxglove bridge: bad message on {topic}: {type(exc).__name__}: {exc}",
                    throttle_duration_sec=5.0,
                )

        return sink

    def _resend_static(self) -> None:
        """Log every kept static transform again (a client just subscribed to /tf_static)."""
        from posekit.msgs.cdr import to_cdr

        with self._lock:
            channel = self._channels.get(_STATIC_TOPIC)
            transforms = list(self._static.values())
        if channel is None or not transforms or self._closed:
            return
        channel.log(to_cdr(TFMessage(transforms=transforms)), log_time=self.now_ns())

    def _resend_latched(self, topic: str) -> None:
        """Log a latched topic's kept messages again (a client just subscribed to it)."""
        with self._lock:
            channel = self._channels.get(topic)
            payloads = list(self._latched.get(topic, ()))
        if channel is None or self._closed:
            return
        for data in payloads:
            channel.log(data, log_time=self.now_ns())


def message_from_json(data: bytes, msg_class: type) -> Any:
    """A message of ``msg_class`` from a client's ``json`` payload.

    A UTF-8 JSON object of the message's fields; those left out keep their defaults.

    Raises:
        ValueError: not UTF-8 JSON (``UnicodeDecodeError`` and ``json.JSONDecodeError`` are
            ValueErrors).
        posekit.msgs.yaml_io.MessageFieldError: a field the type does not have, or a value
            that does not fit it (the text names the field).
    """
    from posekit.msgs.registry import message_type_name
    from posekit.msgs.yaml_io import default_message, set_message_fields

    values = json.loads(data.decode("utf-8"))
    msg = default_message(message_type_name(msg_class))
    set_message_fields(msg, values)
    return msg


def _channel_class(type_name: str) -> type:
    """The class of a type the bridge can serve (a message type with a ROS 2 definition)."""
    from posekit.msgs.cdr import serializable_type

    try:
        return serializable_type(type_name)[1]
    except (LookupError, ValueError, UnknownMessageTypeError) as exc:
        raise LookupError(f"type {type_name!r} has no ROS 2 message definition ({exc})") \
            from None


class _SubprotocolFront:
    """A WebSocket server that accepts every Foxglove subprotocol and relays to foxglove-sdk.

    It listens on the bridge's ``host:port``, accepts every name of
    :data:`FOXGLOVE_SUBPROTOCOLS` and relays each connection, frame by frame and unchanged, to
    foxglove-sdk's server on ``127.0.0.1:backend_port`` (which accepts only the first).
    """

    def __init__(self, bridge: FoxgloveBridge, backend_port: int) -> None:
        self.bridge = bridge
        self.backend_url = f"ws://127.0.0.1:{backend_port}"
        self.port = bridge.requested_port
        self._runner: Any = None
        self._session: Any = None
        self._tasks: set[asyncio.Task[Any]] = set()
        self._loop_thread = LoopThread("posekit-foxglove-front", self._startup, self._cleanup,
                                       pending=lambda: list(self._tasks))

    def start(self) -> None:
        """Bind and serve in a daemon thread. Raises OSError when the address is taken."""
        try:
            self._loop_thread.start()
        except TimeoutError as exc:
            raise OSError(str(exc)) from exc
        except OSError:
            raise
        except Exception as exc:
            raise OSError(str(exc)) from exc

    async def _startup(self) -> None:
        from aiohttp import ClientSession, web

        app = web.Application()
        app.router.add_get("/{tail:.*}", self._handle)
        self._runner = web.AppRunner(app, access_log=None)
        await self._runner.setup()
        site = web.TCPSite(self._runner, self.bridge.host, self.port)
        await site.start()
        sockets = getattr(site._server, "sockets", None) or []  # the bound port (port 0)
        if sockets:
            self.port = int(sockets[0].getsockname()[1])
        self._session = ClientSession()

    async def _cleanup(self) -> None:
        if self._session is not None:
            await self._session.close()
        if self._runner is not None:
            await self._runner.cleanup()

    def stop(self) -> None:
        self._loop_thread.stop()

    async def _handle(self, request: Any) -> Any:
        from aiohttp import web

        from posekit.viewer.access import host_allowed, origin_allowed

        bridge = self.bridge
        if not host_allowed(request.headers.get("Host"), bridge.host, self.port,
                            bridge.allow_hosts):
            bridge._warn("foxglove bridge: connection refused (Host header names another "
                         "server)", f"{request.headers.get('Host', '')[:256]!r}; "
                         "posekit view --allow-host NAME accepts it")
            return web.Response(status=403, text="Host not allowed\n")
        origin = request.headers.get("Origin")
        if not origin_allowed(origin, bridge.host, self.port, bridge.allow_origins):
            bridge._warn("foxglove bridge: connection refused (a web page of another origin)",
                         f"{(origin or '')[:256]!r}; posekit view --allow-origin ORIGIN "
                         "accepts it (e.g. https://app.foxglove.dev)")
            return web.Response(status=403, text="Origin not allowed\n")
        ws = web.WebSocketResponse(protocols=FOXGLOVE_SUBPROTOCOLS, max_msg_size=0)
        ready = ws.can_prepare(request)
        if not ready.ok or ready.protocol is None:
            return web.Response(
                status=400,
                text="a Foxglove WebSocket client is expected (subprotocol "
                     + " or ".join(FOXGLOVE_SUBPROTOCOLS) + ")\n",
            )
        try:
            upstream = await self._session.ws_connect(
                self.backend_url, protocols=(FOXGLOVE_SUBPROTOCOL,), max_msg_size=0
            )
        except Exception as exc:  # the SDK server is gone (stopping)
            return web.Response(status=503, text=f"Foxglove server unavailable: {exc}\n")
        await ws.prepare(request)
        task = asyncio.current_task()
        if task is not None:
            self._tasks.add(task)
        try:
            pumps = [asyncio.ensure_future(_pump(ws, upstream)),
                     asyncio.ensure_future(_pump(upstream, ws))]
            await asyncio.wait(pumps, return_when=asyncio.FIRST_COMPLETED)
            for pump in pumps:
                pump.cancel()
            await asyncio.gather(*pumps, return_exceptions=True)
        finally:
            if task is not None:
                self._tasks.discard(task)
            with contextlib.suppress(Exception):
                await upstream.close()
            with contextlib.suppress(Exception):
                await ws.close()
        return ws


async def _pump(source: Any, sink: Any) -> None:
    """Copy text and binary frames from ``source`` to ``sink`` until either closes."""
    from aiohttp import WSMsgType

    async for msg in source:
        if msg.type == WSMsgType.TEXT:
            await sink.send_str(msg.data)
        elif msg.type == WSMsgType.BINARY:
            await sink.send_bytes(msg.data)
        else:
            return
