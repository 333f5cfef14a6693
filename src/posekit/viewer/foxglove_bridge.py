"""Serve a running posekit system to the Foxglove app (``posekit view --foxglove``).

    from posekit.viewer.foxglove_bridge import FoxgloveBridge
    bridge = FoxgloveBridge(run.context.transport(), port=8766)
    bridge.start()        # ws://127.0.0.1:8766, subprotocol foxglove.sdk.v1
    ...
    bridge.stop()

The bridge uses the optional ``foxglove-sdk`` package (``pip install 'posekit[foxglove]'``),
imported only when a bridge starts; without it :meth:`FoxgloveBridge.start` raises
:class:`~posekit.viewer.errors.ViewerError` saying what to install.

Like :class:`~posekit.viewer.taps.ViewerTap` it listens on a transport without a node in any
executor, and subscribes only to topics that have a publisher. Every topic whose type has a
ROS 2 definition becomes one Foxglove channel with schema encoding ``ros2msg`` (the
definition text with its dependencies, the format ROS 2's MCAP writer uses) and message
encoding ``cdr``, so Foxglove decodes posekit's messages natively. Messages are logged with
``log_time`` from ``clock_ns`` (the run's simulated time in process; default the wall clock,
ns).

``/tf_static`` is latched: the bridge keeps the newest transform per child frame and
re-sends them as one TFMessage whenever a client subscribes to ``/tf_static`` (the SDK logs
to every subscriber of a channel, so earlier subscribers get the same static transforms
again, which is harmless).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import Any

from posekit.msgs.errors import UnknownMessageTypeError
from posekit.msgs.tf2_msgs import TFMessage
from posekit.runtime.logging import RcutilsLogger, get_logger
from posekit.runtime.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from posekit.runtime.transport import (
    EndpointInfo,
    SubscriptionEndpoint,
    TopicTypeMismatchError,
    Transport,
)
from posekit.viewer.errors import ViewerError

__all__ = ["DEFAULT_PORT", "FOXGLOVE_SUBPROTOCOL", "FoxgloveBridge"]

#: Default TCP port (the browser viewer uses 8765).
DEFAULT_PORT = 8766
#: WebSocket subprotocol of foxglove-sdk's server.
FOXGLOVE_SUBPROTOCOL = "foxglove.sdk.v1"
_STATIC_TOPIC = "/tf_static"
_NODE_NAME = "posekit_foxglove_bridge"
# Best effort + volatile matches every publisher; /tf_static needs transient local.
_ANY_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.BEST_EFFORT)
_STATIC_QOS = QoSProfile(depth=100, durability=DurabilityPolicy.TRANSIENT_LOCAL)


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
        clock_ns: ``log_time`` source in ns (default the wall clock).
        refresh_period: seconds between topic discoveries in the background (0: only when
            :meth:`refresh` is called).
        name: the server name shown by Foxglove.
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
        self._clock_ns = clock_ns or time.time_ns
        self._lock = threading.Lock()
        self._channels: dict[str, Any] = {}
        self._endpoints: dict[str, SubscriptionEndpoint] = {}
        self._skipped: dict[str, str] = {}
        self._static: dict[str, Any] = {}  # child frame -> newest static TransformStamped
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

        class _Listener:
            def on_subscribe(self, client: Any, channel: Any) -> None:
                if channel.topic == _STATIC_TOPIC:
                    bridge._resend_static()

        try:
            self._server = fox.start_server(
                name=self.name,
                host=self.host,
                port=self.requested_port,
                server_listener=_Listener(),
                context=self._context,
            )
        except Exception as exc:  # the SDK raises its own error types (address in use...)
            raise ViewerError(
                f"cannot serve Foxglove on {self.host}:{self.requested_port}: {exc}"
            ) from exc
        self.refresh()
        if self.refresh_period > 0:
            self._thread = threading.Thread(
                target=self._refresh_loop, name="posekit-foxglove-refresh", daemon=True
            )
            self._thread.start()

    @property
    def port(self) -> int:
        """The port the server listens on (after :meth:`start`)."""
        if self._server is None:
            raise ViewerError("the Foxglove bridge is not started")
        return int(self._server.port)

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
        with self._lock:
            endpoints = list(self._endpoints.values())
            channels = list(self._channels.values())
            self._endpoints.clear()
            self._channels.clear()
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
        with self._lock:
            return dict(self._skipped)

    def refresh(self) -> list[str]:
        """Serve topics that appeared since the last call; returns the topics added."""
        if self._closed or self._server is None:
            return []
        try:
            names_and_types = self.transport.get_topic_names_and_types()
        except Exception as exc:  # a failing graph query must not kill the bridge
            self.logger.warning(f"foxglove bridge: graph query failed: {exc}")
            return []
        added = []
        for topic, types in names_and_types:
            with self._lock:
                known = topic in self._channels or topic in self._skipped
            if known or self.transport.count_publishers(topic) <= 0:
                continue
            if self._add_topic(topic, types[0] if types else ""):
                added.append(topic)
        return added

    def _refresh_loop(self) -> None:
        while not self._stop.wait(self.refresh_period):
            self.refresh()

    def _skip(self, topic: str, reason: str) -> bool:
        with self._lock:
            self._skipped[topic] = reason
        self.logger.warning(f"foxglove bridge: not serving '{topic}': {reason}")
        return False

    def _add_topic(self, topic: str, type_name: str) -> bool:
        from posekit.msgs.cdr import get_typestore, serializable_type

        try:
            type_name, msg_class = serializable_type(type_name)
            definition, _ = get_typestore().generate_msgdef(type_name, ros_version=2)
        except (LookupError, ValueError, UnknownMessageTypeError):
            return self._skip(topic, f"type {type_name!r} has no ROS 2 message definition")
        fox = self._fox
        schema = fox.Schema(name=type_name, encoding="ros2msg", data=definition.encode())
        channel = fox.Channel(
            topic, schema=schema, message_encoding="cdr", context=self._context
        )
        qos = _STATIC_QOS if topic == _STATIC_TOPIC else _ANY_QOS
        info = EndpointInfo(topic, msg_class, qos, _NODE_NAME, "/", self.logger)
        with self._lock:
            self._channels[topic] = channel
        try:
            endpoint = self.transport.subscribe(info, self._make_sink(topic, type_name, channel))
        except TopicTypeMismatchError as exc:
            with self._lock:
                self._channels.pop(topic, None)
            channel.close()
            return self._skip(topic, str(exc))
        with self._lock:
            if self._closed:  # stop() ran meanwhile
                endpoint.destroy()
                return False
            self._endpoints[topic] = endpoint
        return True

    def _make_sink(self, topic: str, type_name: str, channel: Any) -> Callable[[Any], None]:
        from posekit.msgs.cdr import to_cdr

        is_static = topic == _STATIC_TOPIC and type_name == TFMessage.__msgtype__

        def sink(msg: Any) -> None:
            if self._closed:
                return
            try:
                if is_static:
                    with self._lock:
                        for t in msg.transforms:
                            self._static[t.child_frame_id] = t
                channel.log(to_cdr(msg, type_name), log_time=self._clock_ns())
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
        channel.log(to_cdr(TFMessage(transforms=transforms)), log_time=self._clock_ns())
