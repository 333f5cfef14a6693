"""posekit's browser viewer, in RViz2's place (see docs/viewer.md).

    from posekit.viewer import attach_viewer
    server = attach_viewer(run.context, world="empty_world", clock_ns=lambda: run.executor.now_ns)
    print(server.url)            # http://127.0.0.1:8765/
    ...
    server.stop()

:class:`ViewerTap` gathers TF, odometry, images and topic rates from a transport without a
node in any executor; :class:`ViewerServer` serves the page and streams to it (aiohttp).
aiohttp and OpenCV are imported only by the server and image modules.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from posekit.viewer.errors import ViewerError
from posekit.viewer.taps import ViewerTap

if TYPE_CHECKING:
    from posekit.runtime.context import Context
    from posekit.runtime.transport import Transport
    from posekit.viewer.server import ViewerServer
    from posekit.worlds import World

__all__ = ["ViewerError", "ViewerServer", "ViewerTap", "attach_viewer"]


def __getattr__(name: str) -> Any:
    if name == "ViewerServer":
        from posekit.viewer.server import ViewerServer

        return ViewerServer
    raise AttributeError(f"module 'posekit.viewer' has no attribute {name!r}")


def attach_viewer(
    source: Context | Transport,
    *,
    world: World | str | None = None,
    clock_ns: Callable[[], int] | None = None,
    host: str = "127.0.0.1",
    port: int = 8765,
    **options: Any,
) -> ViewerServer:
    """Tap ``source`` (a context: its selected transport; or a transport) and start serving.

    ``options`` go to :class:`ViewerServer` (``fixed_frame``, ``tf_rate``, ``image_rate``,
    ``jpeg_quality``, ``max_image_width``, ``fps``). Returns the started server; call
    ``stop()`` when done (the tap is closed with it).
    """
    try:
        from posekit.viewer.server import ViewerServer
    except ImportError as exc:
        raise ViewerError(
            f"the viewer needs aiohttp and OpenCV: pip install 'posekit[viewer]' ({exc})"
        ) from exc
    from posekit.runtime.transport import Transport

    transport = source if isinstance(source, Transport) else source.transport()
    tap = ViewerTap(transport, clock_ns=clock_ns)
    tap.refresh()
    server = ViewerServer(tap, host=host, port=port, world=world, close_tap=True, **options)
    try:
        server.start()
    except BaseException:
        tap.close()
        raise
    return server
