"""The viewer's HTTP and WebSocket server (aiohttp), running in its own thread.

Routes:

* ``GET /``: the page (``web/index.html``); ``/app/...``: its scripts and styles;
  ``/vendor/three/...``: the three.js vendored in the package (``web/vendor/three``, a pinned
  release with its licence; nothing is fetched at install or run time). Files are looked up
  per request, so a repaired installation is served without a restart; if three.js is
  missing the page falls back to its 2D canvas and names the fix;
* ``GET /ws``: the WebSocket (protocol below);
* ``GET /api/displays``: the display modules the page loads (``web/app/displays/*.js``);
* ``GET /api/state``: a JSON snapshot (frames in the default fixed frame, TF tree, topics,
  odometry trails) for scripts and tests.

WebSocket protocol (server -> client, JSON text unless noted):

* ``hello``: defaults (fixed frame, rates), the world's boxes/markers, display topics;
* ``tf``: ``{fixed, error, now, frames: [[name, parent, x, y, z, qx, qy, qz, qw, age_s,
  static, ok], ...]}``: every frame's pose in the client's fixed frame (m, quaternion x y z
  w), at up to ``tf_rate`` Hz (default 30, at most 100) while TF changes, else 2 Hz;
* ``odom``: ``{displays: {topic: {frame, child, received, trail: [[x, y, z, qx, qy, qz, qw,
  speed], ...]}}}`` at up to 10 Hz when a trail changed;
* ``graph``: ``{tree: [...], topics: [...], images: [...], clock: {source, sim, wall, rtf,
  rate_clock}, goal: {frame, pose, stamp} | null}`` at 2 Hz (``clock``:
  :meth:`ViewerTap.time_state`; topic rates are on its ``rate_clock``);
* ``display``: ``{topic, messages: [...]}``: new messages of a topic a display of this
  client follows, converted by :func:`posekit.viewer.display_feed.message_to_json`, oldest
  first, at most the display's ``queue`` of them (newest only by default), each at most
  once, at up to ``tf_rate`` Hz;
* binary: one JPEG frame: 4-byte big-endian header length, the UTF-8 JSON header ``{topic,
  seq, stamp, width, height, encoding, frame_id}``, then the JPEG bytes. Only for topics the
  client watches, newest only, at up to ``image_rate`` Hz (default 15). The server
  subscribes to an image topic only while some client watches it (the page watches the
  topics of its enabled Image and Camera displays and of its open image panels), so a
  simulated camera renders nothing for a page that shows none of its images.

Client -> server: ``{"op": "fixed_frame", "frame": NAME}``, ``{"op": "watch", "topics":
[...]}``, ``{"op": "pause", "paused": BOOL}``, ``{"op": "goal", "frame": NAME, "x": M, "y": M,
"yaw": RAD}`` (publishes a ``geometry_msgs/PoseStamped`` on ``/goal_pose``, answered by
``{"type": "goal_sent", ...}``: :meth:`ViewerServer.publish_goal`), ``{"op":
"initial_pose", "frame", "x", "y", "yaw"}`` (publishes a
``geometry_msgs/PoseWithCovarianceStamped`` on ``/initialpose``, answered by
``initial_pose_sent``: :meth:`ViewerServer.publish_initial_pose`),
``{"op": "display_subscribe", "topic": NAME, "type": "pkg/msg/Name", "queue": N}`` (send
this client the topic's messages; ``queue``: messages kept between two sends, 1..1000,
default 1; answered by ``{"type": "display_subscribed", "topic", "msg_type", "queue"}``
once the server keeps the topic's messages), ``{"op": "display_unsubscribe", "topic":
NAME}``. A malformed request gets
``{"type": "error", "message": ...}`` and the connection stays open.

Who may talk to it (against other web pages in the user's browser and DNS rebinding, as
local development servers check): every HTTP request's ``Host`` header must name this
server, i.e. ``localhost``, ``127.0.0.1``, ``[::1]`` or the bound host, with the served port
(plus any ``allow_hosts``); a WebSocket whose ``Origin`` header is present must come from such
an address (``http://localhost:PORT`` ...; plus any ``allow_origins``). Otherwise 403.
Clients that are not browsers send no ``Origin`` and are accepted. ``"*"`` in either list
turns that check off.

Slow clients: each client has one slot per channel (``tf``, ``odom``, ``graph``, one per
image topic) holding the newest payload not yet sent; a new payload replaces an unsent one
(counted in :attr:`ViewerServer.stats` as ``dropped``), so memory stays bounded however slow
the client is, and a client always gets the newest state.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import math
import re
import struct
import threading
import time
from collections.abc import Callable, Iterable, Mapping
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from aiohttp import WSMsgType, web

from posekit.runtime.qos import QoSProfile
from posekit.runtime.ratelimit import RateLimitedLog
from posekit.runtime.transport import EndpointInfo, PublisherEndpoint
from posekit.viewer._loop_thread import LoopThread
from posekit.viewer.access import host_allowed, origin_allowed, own_hosts
from posekit.viewer.display_feed import MAX_QUEUE, message_to_json
from posekit.viewer.errors import ViewerError, ViewerOptionError
from posekit.viewer.images import encode_jpeg
from posekit.viewer.taps import GOAL_TOPIC, ViewerTap
from posekit.viewer.world import world_payload
from posekit.worlds import World

__all__ = ["DEFAULT_HOST", "DEFAULT_PORT", "THREE_ROOT", "WEB_ROOT", "ViewerServer",
           "load_view_config"]

DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 8765
#: The page sources.
WEB_ROOT = Path(__file__).parent / "web"
#: three.js, vendored (see ``VERSION`` there and ``scripts/vendor_three.sh``).
THREE_ROOT = WEB_ROOT / "vendor" / "three"
_MAX_TF_RATE = 100.0
_ODOM_PERIOD = 0.1
_GRAPH_PERIOD = 0.5
_IDLE_TF_PERIOD = 0.5
_MAX_NAME = 256
_MAX_WATCH = 16
_RESTART_DELAY_S = 0.5
_MAX_GOAL_M = 10_000.0
_WORLD_RETRY_S = 2.0
_MAX_DISPLAYS = 64
#: RViz2's "2D Pose Estimate" topic and the variances it sends (x, y: (0.5 m)², yaw:
#: (pi/12 rad)²).
INITIAL_POSE_TOPIC = "/initialpose"
INITIAL_POSE_VARIANCES = (0.25, 0.25, (math.pi / 12.0) ** 2)
_TYPE_NAME = re.compile(r"[A-Za-z][\w]*/msg/[A-Za-z][\w]*")


#: The saved view configuration's version (the page's ``posekit_view`` key).
VIEW_CONFIG_VERSION = 1
_MAX_CONFIG_BYTES = 1 << 20


def load_view_config(path: str | Path) -> dict[str, Any]:
    """A saved view configuration read from ``path``.

    What the page's *Save view* downloads; what the page cannot use in it is skipped there and
    named in a note.

    Raises:
        ViewerOptionError: the file cannot be read, is larger than 1 MiB, is not JSON, or is
            not a posekit view configuration (``"posekit_view": 1``).
    """
    path = Path(path)
    try:
        if path.stat().st_size > _MAX_CONFIG_BYTES:
            raise ViewerOptionError(f"{path}: larger than 1 MiB, not a view configuration")
        config = json.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise ViewerOptionError(f"cannot read the view configuration {path}: "
                                f"{exc.strerror or exc}") from exc
    except (ValueError, UnicodeDecodeError) as exc:
        raise ViewerOptionError(f"{path}: not JSON ({exc})") from exc
    if not isinstance(config, dict) or config.get("posekit_view") != VIEW_CONFIG_VERSION:
        raise ViewerOptionError(f"{path}: not a posekit view configuration "
                                f"(version {VIEW_CONFIG_VERSION}, saved by 'Save view')")
    return config


@dataclass(eq=False)
class _Client:
    """One WebSocket client: its choices and its newest-only outbox."""

    ws: web.WebSocketResponse
    fixed_frame: str
    watched: set[str] = field(default_factory=set)
    paused: bool = False
    slots: dict[str, str | bytes] = field(default_factory=dict)
    wake: asyncio.Event = field(default_factory=asyncio.Event)
    sent: int = 0
    dropped: int = 0
    image_seq: dict[str, int] = field(default_factory=dict)
    #: Display topics: topic -> (type, messages kept per send), and the newest sent.
    displays: dict[str, tuple[str, int]] = field(default_factory=dict)
    display_seq: dict[str, int] = field(default_factory=dict)
    #: Display messages not sent yet per topic (JSON texts, at most the display's queue).
    display_out: dict[str, list[str]] = field(default_factory=dict)

    def put(self, channel: str, payload: str | bytes) -> None:
        if channel in self.slots:
            self.dropped += 1
        self.slots[channel] = payload
        self.wake.set()

    def put_display(self, topic: str, messages: list[str], keep: int) -> None:
        """Queue display messages of ``topic``, keeping up to ``keep`` unsent ones.

        The oldest beyond it are dropped, so a queued display (markers) loses nothing a fast
        enough client could have drawn, and memory stays bounded.
        """
        pending = self.display_out.setdefault(topic, [])
        pending.extend(messages)
        if len(pending) > keep:
            self.dropped += len(pending) - keep
            del pending[: len(pending) - keep]
        self.slots["display:" + topic] = topic
        self.wake.set()


@dataclass
class _Feed:
    """What the producer last sent (versions) and when it sends next (monotonic s)."""

    tf_version: int = -1
    tf_sent: float = 0.0
    odom_version: int = -1
    next_odom: float = 0.0
    next_graph: float = 0.0
    next_image: float = 0.0
    encoding: set[str] = field(default_factory=set)  # image topics being encoded now


def _finite(obj: Any) -> Any:
    """``obj`` with every non-finite float replaced by None (JSON has no inf/NaN)."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, Mapping):
        return {k: _finite(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_finite(v) for v in obj]
    return obj


def _dumps(obj: Any) -> str:
    """Compact JSON; a non-finite number anywhere becomes ``null`` instead of failing."""
    try:
        return json.dumps(obj, separators=(",", ":"), allow_nan=False)
    except ValueError:  # "Out of range float values are not JSON compliant"
        return json.dumps(_finite(obj), separators=(",", ":"), allow_nan=False)


class ViewerServer:
    """Serve the viewer page for ``tap`` on ``http://host:port`` from a background thread.

    Args:
        tap: where the data comes from.
        host: bind address (loopback by default: the page has no authentication).
        port: TCP port; 0 picks a free one (see :attr:`port` after :meth:`start`).
        world: the world whose boxes and markers to draw (a :class:`World` or a name).
        fixed_frame: the page's default Fixed Frame.
        tf_rate: TF updates per second per client (capped at 100).
        image_rate: JPEG frames per second per watched topic.
        jpeg_quality: cv2 JPEG quality 0..100.
        max_image_width: wider images are downscaled before encoding (px).
        fps: the page's rendering cap (frames per second).
        close_tap: close ``tap`` in :meth:`stop` (when the server owns it).
        allow_hosts: more ``Host`` header values accepted (``name`` or ``name:port``;
            ``"*"``: any), e.g. when the page is reached through a proxy or a host name.
        allow_origins: more WebSocket ``Origin`` values accepted (``scheme://host:port``;
            ``"*"``: any).
        discover_world: when no ``world`` is given, ask the system for it (the ``world``
            parameter of its simulator, :func:`~posekit.viewer.world_discovery.
            discover_world`) every 2 s until one answers, and send the pages a new ``hello``
            with it. Default: when the tap's transport crosses processes.
        config: a saved view configuration (the page's *Save view* JSON, or the path of
            such a file: :func:`load_view_config`) every page starts from, as
            ``rviz2 -d FILE`` does; a ``?view=`` in the page's URL takes precedence.
    """

    def __init__(
        self,
        tap: ViewerTap,
        *,
        host: str = DEFAULT_HOST,
        port: int = DEFAULT_PORT,
        world: World | str | None = None,
        fixed_frame: str = "odom",
        tf_rate: float = 30.0,
        image_rate: float = 15.0,
        jpeg_quality: int = 80,
        max_image_width: int = 1280,
        fps: float = 30.0,
        close_tap: bool = False,
        allow_hosts: Iterable[str] = (),
        allow_origins: Iterable[str] = (),
        discover_world: bool | None = None,
        config: Mapping[str, Any] | str | Path | None = None,
    ) -> None:
        if not 0 < tf_rate <= _MAX_TF_RATE:
            raise ViewerOptionError(f"tf_rate must be in (0, {_MAX_TF_RATE:g}] Hz, got {tf_rate}")
        if not image_rate > 0:
            raise ViewerOptionError(f"image_rate must be > 0 Hz, got {image_rate}")
        if not 0 <= jpeg_quality <= 100:
            raise ViewerOptionError(f"jpeg_quality must be in [0, 100], got {jpeg_quality}")
        if not 0 <= port <= 65535:
            raise ViewerOptionError(f"port must be in [0, 65535], got {port}")
        if not fps > 0:
            raise ViewerOptionError(f"fps must be > 0, got {fps}")
        self.tap = tap
        self.host = host
        self.port = port
        self.fixed_frame = fixed_frame
        self.tf_rate = float(tf_rate)
        self.image_rate = float(image_rate)
        self.jpeg_quality = int(jpeg_quality)
        self.max_image_width = int(max_image_width)
        self.fps = float(fps)
        self.close_tap = close_tap
        self.allow_hosts = frozenset(h.strip().lower() for h in allow_hosts if h.strip())
        self.allow_origins = frozenset(
            o.strip().lower().rstrip("/") for o in allow_origins if o.strip()
        )
        self._world = world_payload(world)
        self.config = (load_view_config(config) if isinstance(config, (str, Path))
                       else None if config is None else dict(config))
        if discover_world is None:
            discover_world = tap.transport.crosses_processes
        self.discover_world = world is None and discover_world
        self._clients: set[_Client] = set()
        self._runner_thread: LoopThread | None = None
        self._thread: threading.Thread | None = None
        self._runner: web.AppRunner | None = None
        self._encoder = ThreadPoolExecutor(max_workers=1, thread_name_prefix="posekit-jpeg")
        self._stopping = False
        self._image_tasks: set[asyncio.Task[None]] = set()
        self._counters = {"tf": 0, "odom": 0, "graph": 0, "images_encoded": 0, "clients": 0,
                          "producer_errors": 0, "producer_restarts": 0, "forbidden": 0,
                          "goals": 0, "initial_poses": 0}
        self._tool_lock = threading.Lock()
        self._tool_pubs: dict[str, PublisherEndpoint] = {}
        self._producers: set[asyncio.Task[None]] = set()
        self._warn = RateLimitedLog(tap.logger.warning)

    # -- lifecycle ---------------------------------------------------------------------------
    @property
    def url(self) -> str:
        """``http://host:port/`` (IPv6 hosts bracketed)."""
        host = f"[{self.host}]" if ":" in self.host else self.host
        return f"http://{host}:{self.port}/"

    def start(self) -> str:
        """Bind and serve in a daemon thread; returns :attr:`url`.

        Raises :class:`ViewerError` when the address cannot be bound.
        """
        if self._thread is not None:
            raise ViewerError("viewer server already started")
        runner = LoopThread(
            "posekit-viewer", self._startup, self._cleanup,
            pending=lambda: [*self._producers, *self._image_tasks],
            on_started=self._on_started,
        )
        try:
            runner.start()
        except TimeoutError as exc:
            raise ViewerError("viewer server did not start within 15 s") from exc
        except Exception as exc:
            raise ViewerError(f"cannot serve the viewer on {self.host}:{self.port}: {exc}") from exc
        self._runner_thread = runner
        self._thread = runner.thread
        return self.url

    def _on_started(self, loop: asyncio.AbstractEventLoop) -> None:
        self._start_producer(loop)
        if self.discover_world:
            self._producers.add(loop.create_task(self._discover_world()))

    async def _discover_world(self) -> None:
        """Ask the system for its world every 2 s until one answers (see ``discover_world``)."""
        from posekit.viewer.world_discovery import discover_world

        loop = asyncio.get_running_loop()
        while not self._stopping and self._world is None:
            name = await loop.run_in_executor(
                None, discover_world, self.tap.transport, self.tap.logger)
            if name:
                try:
                    self._world = world_payload(name)
                except Exception as exc:  # an unknown or broken world: say so once, stop
                    self._warn("viewer: the system's world cannot be drawn",
                               f"{name!r}: {exc}")
                    return
                self.tap.logger.info(f"viewer: drawing the system's world '{name}'")
                hello = _dumps(self._hello())
                for client in list(self._clients):
                    client.put("hello", hello)
                return
            await asyncio.sleep(_WORLD_RETRY_S)

    def _start_producer(self, loop: asyncio.AbstractEventLoop) -> None:
        """Run :meth:`_produce`, restarting it (after one logged line) if it ever fails."""
        task = loop.create_task(self._produce())
        self._producers.add(task)

        def on_done(done: asyncio.Task[None]) -> None:
            self._producers.discard(done)
            if self._stopping or done.cancelled():
                return
            exc = done.exception()
            if exc is not None:
                self._counters["producer_restarts"] += 1
                self._warn("viewer: producer failed, restarted",
                           f"{type(exc).__name__}: {exc}")
                loop.call_later(_RESTART_DELAY_S, self._start_producer, loop)

        task.add_done_callback(on_done)

    # -- who may connect ---------------------------------------------------------------------
    def _own_hosts(self) -> set[str]:
        """``host:port`` values that name this server (loopback names and the bound host)."""
        return own_hosts(self.host, self.port)

    def host_allowed(self, host: str | None) -> bool:
        """Whether a request's ``Host`` header names this server (see the module docstring)."""
        return host_allowed(host, self.host, self.port, self.allow_hosts)

    def origin_allowed(self, origin: str | None) -> bool:
        """Whether a WebSocket ``Origin`` may connect (absent: not a browser, allowed)."""
        return origin_allowed(origin, self.host, self.port, self.allow_origins)

    @web.middleware
    async def _guard(self, request: web.Request, handler: Any) -> web.StreamResponse:
        if not self.host_allowed(request.headers.get("Host")):
            self._counters["forbidden"] += 1
            self._warn("viewer: request refused (Host header names another server)",
                       f"{request.headers.get('Host', '')[:_MAX_NAME]!r}; "
                       "posekit view --allow-host NAME accepts it")
            return web.Response(status=403, text="Host not allowed\n")
        if request.path == "/ws" and not self.origin_allowed(request.headers.get("Origin")):
            self._counters["forbidden"] += 1
            self._warn("viewer: WebSocket refused (page from another origin)",
                       f"{request.headers.get('Origin', '')[:_MAX_NAME]!r}; "
                       "posekit view --allow-origin ORIGIN accepts it")
            return web.Response(status=403, text="Origin not allowed\n")
        response: web.StreamResponse = await handler(request)
        return response

    async def _startup(self) -> None:
        app = web.Application(middlewares=[self._guard])
        app.router.add_get("/", self._index)
        app.router.add_get("/ws", self._websocket)
        app.router.add_get("/api/state", self._state)
        app.router.add_get("/api/displays", self._display_modules)
        app.router.add_get("/favicon.ico", self._no_content)
        app.router.add_static("/app/", WEB_ROOT / "app", follow_symlinks=False)
        app.router.add_get("/vendor/three/{path:.+}", self._three)
        self._runner = web.AppRunner(app, access_log=None)
        await self._runner.setup()
        site = web.TCPSite(self._runner, self.host, self.port)
        await site.start()
        if self.port == 0:
            server = site._server  # aiohttp exposes the bound sockets only here
            sockets = getattr(server, "sockets", None) or []
            if sockets:
                self.port = int(sockets[0].getsockname()[1])

    async def _cleanup(self) -> None:
        for client in list(self._clients):
            with contextlib.suppress(Exception):
                await client.ws.close()
        if self._runner is not None:
            await self._runner.cleanup()

    def stop(self) -> None:
        """Close every connection, stop serving and join the thread."""
        self._stopping = True
        if self._runner_thread is not None:
            self._runner_thread.stop()
        self._thread = None
        self._encoder.shutdown(wait=False, cancel_futures=True)
        with self._tool_lock:
            publishers, self._tool_pubs = list(self._tool_pubs.values()), {}
        for publisher in publishers:
            with contextlib.suppress(Exception):  # a closing transport: nothing to undo
                publisher.destroy()
        if self.close_tap:
            self.tap.close()

    def serve_forever(self) -> None:
        """:meth:`start` (if needed) and block until Ctrl-C, then :meth:`stop`."""
        if self._thread is None:
            self.start()
        try:
            while self._thread is not None and self._thread.is_alive():
                self._thread.join(timeout=0.5)
        except KeyboardInterrupt:
            pass
        finally:
            self.stop()

    def __enter__(self) -> ViewerServer:
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()

    @property
    def stats(self) -> dict[str, int]:
        """Messages produced per kind, clients connected, and payloads dropped for slow clients.

        A dropped payload was replaced before it was sent.
        """
        out = dict(self._counters)
        out["connected"] = len(self._clients)
        out["dropped"] = sum(c.dropped for c in self._clients)
        return out

    # -- HTTP --------------------------------------------------------------------------------
    async def _index(self, request: web.Request) -> web.StreamResponse:
        del request
        return web.FileResponse(WEB_ROOT / "index.html", headers={"Cache-Control": "no-cache"})

    async def _three(self, request: web.Request) -> web.StreamResponse:
        root = THREE_ROOT.resolve()
        path = (root / request.match_info["path"]).resolve()
        if not path.is_relative_to(root) or not path.is_file():
            raise web.HTTPNotFound(text=f"{request.path} is not part of the vendored three.js")
        return web.FileResponse(path)

    async def _display_modules(self, request: web.Request) -> web.Response:
        """The page's display modules, as module paths the page imports.

        Every ``web/app/displays/*.js`` not starting with ``_`` (helpers); see docs/viewer.md.
        """
        del request
        root = WEB_ROOT / "app" / "displays"
        names = sorted(p.name for p in root.glob("*.js") if not p.name.startswith("_"))
        return web.json_response({"modules": [f"/app/displays/{n}" for n in names]},
                                 headers={"Cache-Control": "no-cache"})

    async def _no_content(self, request: web.Request) -> web.Response:
        del request
        return web.Response(status=204)

    async def _state(self, request: web.Request) -> web.Response:
        fixed = request.query.get("fixed_frame", self.fixed_frame)[:_MAX_NAME]
        try:
            error, frames = self.tap.frames_in(fixed)
            state = {
                "fixed_frame": fixed,
                "error": error,
                "frames": frames,
                "tree": self.tap.tree(),
                "topics": self.tap.topics(),
                "odometry": self.tap.trails(),
                "clock": self.tap.time_state(),
                "stats": self.stats,
            }
        except Exception as exc:  # whatever the data, the API answers
            self._warn("viewer: /api/state failed", f"{type(exc).__name__}: {exc}")
            return web.json_response(
                {"fixed_frame": fixed, "error": f"state unavailable: {exc}"},
                status=503, dumps=_dumps,
            )
        return web.json_response(state, dumps=_dumps)

    def _hello(self) -> dict[str, Any]:
        return {
            "type": "hello",
            "version": 1,
            "fixed_frame": self.fixed_frame,
            "tf_rate": self.tf_rate,
            "image_rate": self.image_rate,
            "fps": self.fps,
            "world": self._world,
            "odometry_topics": list(self.tap.odometry_topics),
            "ground_truth_topic": self.tap.ground_truth_topic,
            "base_frame": "base_link",
            "config": self.config,
        }

    async def _websocket(self, request: web.Request) -> web.StreamResponse:
        ws = web.WebSocketResponse(heartbeat=20.0, max_msg_size=64 * 1024)
        await ws.prepare(request)
        client = _Client(ws, self.fixed_frame)
        self._clients.add(client)
        self._counters["clients"] += 1
        client.put("hello", _dumps(self._hello()))
        client.put("graph", self._graph_message())
        client.put("tf", self._tf_message(client.fixed_frame))
        sender = asyncio.get_running_loop().create_task(self._sender(client))
        try:
            async for msg in ws:
                if msg.type == WSMsgType.TEXT:
                    self._on_request(client, msg.data)
                elif msg.type == WSMsgType.ERROR:
                    break
        finally:
            self._clients.discard(client)
            if client.displays:
                self._update_message_watches()
            if client.watched:
                self._update_image_watches()
            sender.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await sender
        return ws

    async def _sender(self, client: _Client) -> None:
        ws = client.ws
        while not ws.closed:
            await client.wake.wait()
            client.wake.clear()
            while client.slots and not ws.closed:
                channel = next(iter(client.slots))
                payload = client.slots.pop(channel)
                if channel.startswith("display:"):
                    messages = client.display_out.pop(str(payload), [])
                    if not messages or payload not in client.displays:
                        continue
                    payload = (f'{{"type":"display","topic":{json.dumps(payload)},'
                               f'"messages":[{",".join(messages)}]}}')
                try:
                    if isinstance(payload, bytes):
                        await ws.send_bytes(payload)
                    else:
                        await ws.send_str(payload)
                except (ConnectionError, RuntimeError):
                    return
                client.sent += 1

    def _on_request(self, client: _Client, text: str) -> None:
        """Answer one JSON request of a page; a bad one gets an ``error`` message back."""
        handlers: dict[str, Callable[[_Client, Mapping[str, Any]], None]] = {
            "fixed_frame": self._set_fixed_frame,
            "watch": self._watch_images,
            "pause": self._pause,
            "goal": self._send_goal,
            "initial_pose": self._send_initial_pose,
            "display_subscribe": self._display_subscribe,
            "display_unsubscribe": self._display_unsubscribe,
        }
        try:
            request = json.loads(text)
            if not isinstance(request, Mapping):
                raise ValueError("expected a JSON object")
            op = request.get("op")
            handler = handlers.get(op) if isinstance(op, str) else None
            if handler is None:
                raise ValueError(f"unknown op {op!r} (fixed_frame, watch, pause, goal, "
                                 "initial_pose, display_subscribe, display_unsubscribe)")
            handler(client, request)
        except (ValueError, TypeError) as exc:
            client.put("error", _dumps({"type": "error", "message": f"bad request: {exc}"}))

    def _set_fixed_frame(self, client: _Client, request: Mapping[str, Any]) -> None:
        """``{"op": "fixed_frame", "frame"}``: the page's fixed frame, and its TF at once."""
        frame = request.get("frame")
        if not isinstance(frame, str) or not frame or len(frame) > _MAX_NAME:
            raise ValueError("'frame' must be a non-empty string")
        client.fixed_frame = frame.lstrip("/")
        client.put("tf", self._tf_message(client.fixed_frame))

    def _watch_images(self, client: _Client, request: Mapping[str, Any]) -> None:
        """``{"op": "watch", "topics"}``: the image topics the page shows (replaces the last)."""
        topics = request.get("topics")
        if not isinstance(topics, list) or not all(
            isinstance(t, str) and 0 < len(t) <= _MAX_NAME for t in topics
        ):
            raise ValueError("'topics' must be a list of topic names")
        if len(topics) > _MAX_WATCH:
            raise ValueError(f"at most {_MAX_WATCH} image topics can be watched")
        client.watched = set(topics)
        for stale in [c for c in client.slots if c.startswith("image:")]:
            if stale[6:] not in client.watched:
                del client.slots[stale]
        client.image_seq = {t: s for t, s in client.image_seq.items() if t in topics}
        self._update_image_watches()

    def _pause(self, client: _Client, request: Mapping[str, Any]) -> None:
        """``{"op": "pause", "paused"}``: stop or resume the page's updates."""
        client.paused = bool(request.get("paused"))

    def _send_goal(self, client: _Client, request: Mapping[str, Any]) -> None:
        """``{"op": "goal", "frame", "x", "y", "yaw"}``: publish a navigation goal."""
        goal = self.publish_goal(request.get("frame"), request.get("x"),
                                 request.get("y"), request.get("yaw"))
        client.put("goal_sent", _dumps({"type": "goal_sent", **goal}))

    def _send_initial_pose(self, client: _Client, request: Mapping[str, Any]) -> None:
        """``{"op": "initial_pose", "frame", "x", "y", "yaw"}``: publish an initial pose."""
        pose = self.publish_initial_pose(request.get("frame"), request.get("x"),
                                         request.get("y"), request.get("yaw"))
        client.put("initial_pose_sent", _dumps({"type": "initial_pose_sent", **pose}))

    def _display_unsubscribe(self, client: _Client, request: Mapping[str, Any]) -> None:
        """``{"op": "display_unsubscribe", "topic"}``: stop sending the topic to the page."""
        topic = request.get("topic")
        if not isinstance(topic, str):
            raise ValueError("'topic' must be a topic name")
        client.displays.pop(topic, None)
        client.display_seq.pop(topic, None)
        client.display_out.pop(topic, None)
        self._update_message_watches()

    # -- displays --------------------------------------------------------------------------
    def _display_subscribe(self, client: _Client, request: Mapping[str, Any]) -> None:
        """Handle ``{"op": "display_subscribe", "topic", "type", "queue"}``.

        Send this client the topic's messages as JSON (``display`` messages;
        :mod:`posekit.viewer.display_feed`).
        """
        topic, type_name = request.get("topic"), request.get("type")
        queue = request.get("queue", 1)
        if not isinstance(topic, str) or not topic.startswith("/") or len(topic) > _MAX_NAME:
            raise ValueError("'topic' must be a fully qualified topic name")
        if not isinstance(type_name, str) or not _TYPE_NAME.fullmatch(type_name):
            raise ValueError("'type' must be a ROS type name like pkg/msg/Name")
        if isinstance(queue, bool) or not isinstance(queue, int) or not 1 <= queue <= MAX_QUEUE:
            raise ValueError(f"'queue' must be an integer in [1, {MAX_QUEUE}]")
        known = self.tap.topic_type(topic)
        if known and known != type_name:
            raise ValueError(f"{topic} carries {known}, not {type_name}")
        if topic not in client.displays and len(client.displays) >= _MAX_DISPLAYS:
            raise ValueError(f"at most {_MAX_DISPLAYS} display topics per page")
        client.displays[topic] = (type_name, queue)
        client.display_seq.setdefault(topic, 0)
        self._update_message_watches()
        client.put("display_subscribed:" + topic, _dumps(
            {"type": "display_subscribed", "topic": topic, "msg_type": type_name,
             "queue": queue}))

    def _update_message_watches(self) -> None:
        """Tell the tap which topics' messages the open pages' displays want.

        And how many of them to keep between two sends (the largest queue any page asked for).
        """
        depths: dict[str, int] = {}
        for c in self._clients:
            for topic, (_, queue) in c.displays.items():
                depths[topic] = max(queue, depths.get(topic, 1))
        self.tap.set_message_watches(depths)

    def _update_image_watches(self) -> None:
        """Tell the tap which image topics the open pages watch (it follows only those)."""
        self.tap.set_image_watches({t for c in self._clients for t in c.watched})

    def _display_round(self, active: list[_Client]) -> dict[_Client, dict[str, list[str]]]:
        """The display messages each active client has not had yet, converted to JSON.

        Converted in a worker thread: a large message takes a while. A message that cannot be
        converted is logged (rate-limited) and skipped.
        """
        wanted: dict[str, int] = {}
        for c in active:
            for topic in c.displays:
                seq = c.display_seq.get(topic, 0)
                wanted[topic] = min(seq, wanted.get(topic, seq))
        texts: dict[str, list[tuple[int, str]]] = {}
        for topic, seq in wanted.items():
            out = texts[topic] = []
            for number, msg in self.tap.messages_after(topic, seq):
                try:
                    out.append((number, _dumps(message_to_json(msg))))
                except Exception as exc:  # a message that cannot be converted: skip it
                    self._warn(f"viewer: cannot convert a message on {topic}",
                               f"{type(exc).__name__}: {exc}")
        result: dict[_Client, dict[str, list[str]]] = {}
        for c in active:
            for topic, (_, queue) in list(c.displays.items()):
                seq = c.display_seq.get(topic, 0)
                new = [(n, t) for n, t in texts.get(topic, []) if n > seq][-queue:]
                if new:
                    c.display_seq[topic] = new[-1][0]
                    result.setdefault(c, {})[topic] = [t for _, t in new]
        return result

    # -- goals and pose estimates ------------------------------------------------------------
    def _tool_pose(self, frame: Any, x: Any, y: Any, yaw: Any) -> tuple[str, float, float, float]:
        """A pose from the page's tools, checked: ``(frame, x, y, yaw)``.

        Raises:
            ValueError: a non-string or over-long frame, non-numeric or non-finite values,
                or a position beyond 10 km.
        """
        if not isinstance(frame, str) or not frame.strip("/") or len(frame) > _MAX_NAME:
            raise ValueError("'frame' must be a non-empty frame name")
        values = []
        for name, v in (("x", x), ("y", y), ("yaw", yaw)):
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise ValueError(f"pose '{name}' must be a finite number, got {v!r}")
            values.append(float(v))
        px, py, pyaw = values
        if max(abs(px), abs(py)) > _MAX_GOAL_M:
            raise ValueError(f"position beyond {_MAX_GOAL_M:g} m")
        return frame.lstrip("/"), px, py, pyaw

    def _publish_tool(self, topic: str, msg: Any, what: str,
                      pose: tuple[str, float, float, float]) -> dict[str, Any]:
        """Publish ``msg`` on ``topic``, count and log it; returns the pose as the page is answered.

        ``msg`` carries the tool's ``pose`` (frame, x, y, yaw). The publisher is created on
        first use (the viewer adds no topic until a tool is used) and kept until :meth:`stop`.
        """
        with self._tool_lock:
            publisher = self._tool_pubs.get(topic)
            created = publisher is None
            if publisher is None:
                publisher = self._tool_pubs[topic] = self.tap.transport.advertise(EndpointInfo(
                    topic, type(msg), QoSProfile(depth=10), "posekit_viewer", "/",
                    self.tap.logger))
        if created:
            self.tap.refresh()  # the displays subscribe now that the topic has a publisher
        publisher.publish(msg)
        self._counters["goals" if topic == GOAL_TOPIC else "initial_poses"] += 1
        frame_id, x, y, yaw = pose
        self.tap.logger.info(f"viewer: {what} sent on {topic}: x={x:.2f}, y={y:.2f}, "
                             f"yaw={yaw:.2f} in {frame_id}")
        return {"frame": frame_id, "x": x, "y": y, "yaw": yaw}

    def _stamp(self, header: Any, frame: str) -> None:
        header.frame_id = frame
        header.stamp.sec, header.stamp.nanosec = divmod(self.tap.now_ns(), 1_000_000_000)

    def publish_goal(self, frame: Any, x: Any, y: Any, yaw: Any) -> dict[str, Any]:
        """Publish a ``geometry_msgs/PoseStamped`` on ``/goal_pose``; returns what was published.

        RViz2's "2D Goal Pose": position ``(x, y, 0)`` m and heading ``yaw`` rad about z in
        ``frame``, stamped with the tap's "now". The publisher is created on first use (the
        viewer adds no topic until a goal is sent).

        Raises:
            ValueError: see :meth:`_tool_pose`.
        """
        from posekit.msgs.geometry_msgs import PoseStamped

        frame_id, gx, gy, gyaw = self._tool_pose(frame, x, y, yaw)
        msg = PoseStamped()
        self._stamp(msg.header, frame_id)
        msg.pose.position.x, msg.pose.position.y = gx, gy
        msg.pose.orientation.z, msg.pose.orientation.w = math.sin(gyaw / 2), math.cos(gyaw / 2)
        return self._publish_tool(GOAL_TOPIC, msg, "goal", (frame_id, gx, gy, gyaw))

    def publish_initial_pose(self, frame: Any, x: Any, y: Any, yaw: Any) -> dict[str, Any]:
        """Publish a ``geometry_msgs/PoseWithCovarianceStamped`` on ``/initialpose``.

        RViz2's "2D Pose Estimate": position ``(x, y, 0)`` m, heading ``yaw`` rad in ``frame``,
        stamped with the tap's "now", with RViz2's covariance (:data:`INITIAL_POSE_VARIANCES` on
        x, y and yaw, zero elsewhere). Returns what was published.

        Raises:
            ValueError: see :meth:`_tool_pose`.
        """
        from posekit.msgs.geometry_msgs import PoseWithCovarianceStamped

        frame_id, px, py, pyaw = self._tool_pose(frame, x, y, yaw)
        msg = PoseWithCovarianceStamped()
        self._stamp(msg.header, frame_id)
        msg.pose.pose.position.x, msg.pose.pose.position.y = px, py
        msg.pose.pose.orientation.z = math.sin(pyaw / 2)
        msg.pose.pose.orientation.w = math.cos(pyaw / 2)
        vx, vy, vyaw = INITIAL_POSE_VARIANCES
        msg.pose.covariance[0], msg.pose.covariance[7], msg.pose.covariance[35] = vx, vy, vyaw
        return self._publish_tool(INITIAL_POSE_TOPIC, msg, "pose estimate",
                                  (frame_id, px, py, pyaw))

    # -- producers ---------------------------------------------------------------------------
    def _tf_message(self, fixed: str) -> str:
        error, frames = self.tap.frames_in(fixed)
        self._counters["tf"] += 1
        return _dumps(
            {
                "type": "tf",
                "fixed": fixed,
                "error": error,
                "now": round(self.tap.now_ns() / 1e9, 3),
                "frames": frames,
            }
        )

    def _graph_message(self) -> str:
        self._counters["graph"] += 1
        return _dumps(
            {
                "type": "graph",
                "tree": self.tap.tree(),
                "topics": self.tap.topics(),
                "images": self.tap.image_topics(),
                "clock": self.tap.time_state(),
                "goal": self.tap.goal(),
            }
        )

    async def _produce(self) -> None:
        """Feed every client.

        A failing round is logged (rate-limited) and skipped, so no data (a non-finite pose, a
        broken message) can stop the feed.
        """
        period = 1.0 / self.tf_rate
        feed = _Feed()
        while not self._stopping:
            try:
                await self._produce_round(feed)
            except Exception as exc:
                self._counters["producer_errors"] += 1
                self._warn("viewer: update failed", f"{type(exc).__name__}: {exc}")
            await asyncio.sleep(period)

    async def _produce_round(self, feed: _Feed) -> None:
        """One round of :meth:`_produce`: graph, TF, odometry, display and image slots."""
        loop = asyncio.get_running_loop()
        now = time.monotonic()
        active = [c for c in self._clients if not c.paused and not c.ws.closed]
        if now >= feed.next_graph:
            feed.next_graph = now + _GRAPH_PERIOD
            await loop.run_in_executor(None, self.tap.refresh)
            if active:
                graph = self._graph_message()
                for c in active:
                    c.put("graph", graph)
        if not active:
            return
        self._tf_slot(feed, active, now)
        if now >= feed.next_odom:
            self._odom_slot(feed, active, now)
        if any(c.displays for c in active):
            batches = await loop.run_in_executor(None, self._display_round, active)
            for c, topics in batches.items():
                for topic, messages in topics.items():
                    display = c.displays.get(topic)  # unsubscribed meanwhile: nothing to send
                    if display is not None:
                        c.put_display(topic, messages, display[1])
        if now >= feed.next_image:
            self._image_slot(feed, active, now, loop)

    def _tf_slot(self, feed: _Feed, active: list[_Client], now: float) -> None:
        """TF to every active client, per fixed frame: on a change, else every idle period."""
        version = self.tap.tf_version
        if version == feed.tf_version and now - feed.tf_sent < _IDLE_TF_PERIOD:
            return
        feed.tf_version, feed.tf_sent = version, now
        by_frame: dict[str, str] = {}
        for c in active:
            if c.fixed_frame not in by_frame:
                by_frame[c.fixed_frame] = self._tf_message(c.fixed_frame)
            c.put("tf", by_frame[c.fixed_frame])

    def _odom_slot(self, feed: _Feed, active: list[_Client], now: float) -> None:
        """The odometry trails to every active client when they changed (the slot is due)."""
        feed.next_odom = now + _ODOM_PERIOD
        odom_version = self.tap.trails_version()
        if odom_version == feed.odom_version:
            return
        feed.odom_version = odom_version
        self._counters["odom"] += 1
        odom = _dumps({"type": "odom", "displays": self.tap.trails()})
        for c in active:
            c.put("odom", odom)

    def _image_slot(
        self, feed: _Feed, active: list[_Client], now: float, loop: asyncio.AbstractEventLoop
    ) -> None:
        """Start encoding each watched topic's newest image that a watcher has not had yet.

        One encoding per topic at a time (``feed.encoding``); the slot is due.
        """
        feed.next_image = now + 1.0 / self.image_rate
        encoding = feed.encoding
        for topic in {t for c in active for t in c.watched} - encoding:
            latest = self.tap.latest_image(topic)
            if latest is None:
                continue
            seq, msg = latest
            watchers = [c for c in active if topic in c.watched
                        and c.image_seq.get(topic, 0) < seq]
            if watchers:
                encoding.add(topic)
                task = loop.create_task(self._send_image(topic, seq, msg, watchers, encoding))
                self._image_tasks.add(task)  # keep a reference until it is done
                task.add_done_callback(self._image_tasks.discard)

    async def _send_image(
        self, topic: str, seq: int, msg: Any, watchers: list[_Client], encoding: set[str]
    ) -> None:
        loop = asyncio.get_running_loop()
        try:
            jpeg = await loop.run_in_executor(
                self._encoder, encode_jpeg, msg, self.jpeg_quality, self.max_image_width
            )
        except Exception as exc:  # a malformed image must not stop the viewer
            self.tap.logger.warning(
                f"viewer: cannot encode image on {topic}: {exc}", throttle_duration_sec=5.0
            )
            return
        finally:
            encoding.discard(topic)
        self._counters["images_encoded"] += 1
        stamp = msg.header.stamp
        header = _dumps(
            {
                "topic": topic,
                "seq": seq,
                "stamp": round(int(stamp.sec) + int(stamp.nanosec) * 1e-9, 6),
                "width": int(msg.width),
                "height": int(msg.height),
                "encoding": str(msg.encoding),
                "frame_id": str(msg.header.frame_id),
            }
        ).encode()
        payload = struct.pack(">I", len(header)) + header + jpeg
        for c in watchers:
            if topic in c.watched and not c.ws.closed:
                c.image_seq[topic] = seq
                c.put("image:" + topic, payload)
