"""``posekit view``: the browser viewer (RViz2's place), and attaching it to a launch run.

    posekit view [--host 127.0.0.1] [--port 8765] [--zenoh | --transport dds] [--world NAME]
                 [--fixed-frame odom] [--tf-rate 30] [--scenario NAME [--seed N]]
                 [--foxglove [--foxglove-port 8766]] [--config FILE]
                 [--allow-host NAME]... [--allow-origin ORIGIN]...

Alone (or with ``--zenoh``) it views other processes over the Zenoh transport; with
``--transport dds`` a ROS 2 system on DDS (real robots and nodes included).
``--scenario NAME`` runs a named scenario in this process, paced to the wall clock, and views
it. :func:`attach_to_run` is what ``posekit launch SCENARIO --viewer`` calls.
``--config FILE`` starts every page from a view saved with the page's *Save view*
(fixed frame, camera, displays), as ``rviz2 -d FILE`` does.
``--foxglove`` also serves the same system to the Foxglove app over its WebSocket protocol
(optional package foxglove-sdk; :mod:`posekit.viewer.foxglove_bridge`), on the same host.
The page answers only requests addressed to this machine (``Host``) and WebSockets from its
own pages (``Origin``); ``--allow-host``/``--allow-origin`` widen that (see docs/security.md).
"""

from __future__ import annotations

import argparse
import sys
import threading
import webbrowser
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from posekit.launch import LaunchRun
    from posekit.runtime.transport import Transport
    from posekit.viewer.foxglove_bridge import FoxgloveBridge
    from posekit.viewer.server import ViewerServer

__all__ = ["attach_to_run", "find_world", "main"]


def find_world(run: LaunchRun) -> str | None:
    """The world of a run, or None.

    The ``world`` parameter of the first node declaring one (the simulator's).
    """
    for node in run.nodes:
        if node.has_parameter("world"):
            value = node.get_parameter("world").value
            if isinstance(value, str) and value:
                return value
    return None


def add_access_options(parser: argparse.ArgumentParser) -> None:
    """``--allow-host`` and ``--allow-origin``: what the viewer accepts beyond its own names.

    Shared by ``posekit view`` and ``posekit launch --viewer``; see docs/security.md.
    """
    parser.add_argument("--allow-host", action="append", default=[], metavar="NAME",
                        help="also accept this HTTP Host header (name or name:port; '*': any); "
                             "by default only localhost, 127.0.0.1, [::1] and --host")
    parser.add_argument("--allow-origin", action="append", default=[], metavar="ORIGIN",
                        help="also accept WebSocket connections from pages of this origin "
                             "(e.g. http://myhost:8765; '*': any)")


def attach_to_run(
    run: LaunchRun,
    *,
    host: str = "127.0.0.1",
    port: int = 8765,
    world: str | None = None,
    open_browser: bool = False,
    **options: Any,
) -> ViewerServer:
    """Serve a viewer of ``run`` and return the started server.

    Same process, on the run's in-process bus; ``server.stop()`` when the run ends.

    The world is taken from the simulator's ``world`` parameter unless given; frame ages use
    the run's simulated time when its executor is a SimulatedTimeExecutor. Pace the run to
    the wall clock (``realtime=True`` / ``real_time_factor=1.0``) to watch it move.
    ``options`` go to :class:`posekit.viewer.server.ViewerServer`.
    """
    from posekit.runtime.sim_executor import SimulatedTimeExecutor
    from posekit.viewer import attach_viewer

    executor = run.executor
    clock = None
    if isinstance(executor, SimulatedTimeExecutor):
        sim: SimulatedTimeExecutor = executor

        def clock() -> int:
            return sim.now_ns

    server = attach_viewer(
        run.context,
        world=world if world is not None else find_world(run),
        clock_ns=clock,
        host=host,
        port=port,
        **options,
    )
    if open_browser:
        webbrowser.open(server.url)
    return server


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="posekit view",
        description="Serve the browser viewer (3D TF, robot, odometry, images, TF tree, topics).",
    )
    parser.add_argument("--host", default="127.0.0.1",
                        help="bind address (default 127.0.0.1: this machine only)")
    parser.add_argument("--port", type=int, default=8765, help="TCP port (default 8765)")
    parser.add_argument("--zenoh", action="store_true",
                        help="view other processes over Zenoh (the default without --scenario)")
    parser.add_argument("--transport", default=None, choices=("zenoh", "dds"),
                        help="view other processes over this transport (dds: a ROS 2 system "
                             "on DDS; default zenoh)")
    parser.add_argument("--scenario", default=None,
                        help="run this named scenario here (wall-clock paced) and view it")
    parser.add_argument("--seed", type=int, default=0, help="scenario seed (with --scenario)")
    parser.add_argument("--world", default=None,
                        help="world whose boxes and markers to draw (name or .json/.yaml)")
    parser.add_argument("--fixed-frame", default="odom", help="default Fixed Frame (odom)")
    parser.add_argument("--tf-rate", type=float, default=30.0,
                        help="TF updates per second sent to the page (max 100)")
    add_access_options(parser)
    parser.add_argument("--config", "-d", default=None, metavar="FILE",
                        help="start the page from this saved view (the JSON file 'Save view' "
                             "downloads), as rviz2 -d does")
    parser.add_argument("--open", action="store_true", help="open the page in a browser")
    parser.add_argument("--foxglove", action="store_true",
                        help="also serve the Foxglove app over its WebSocket protocol "
                             "(needs foxglove-sdk: pip install 'posekit[foxglove]')")
    parser.add_argument("--foxglove-port", type=int, default=8766,
                        help="TCP port of the Foxglove WebSocket server (default 8766)")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``posekit view``; returns the exit code."""
    ns = _parser().parse_args(argv)
    from posekit.cli._extras import require

    needs = [("posekit view", "viewer")]
    if ns.foxglove:
        needs.append(("--foxglove", "foxglove"))
    if not ns.scenario:
        from posekit.cli._session import tool_transport

        remote = "zenoh" if ns.zenoh else tool_transport(ns.transport)
        needs.append(("viewing other processes", "dds" if remote == "dds" else "zenoh"))
    problem = require("posekit view", needs)
    if problem:
        print(problem, file=sys.stderr)
        return 2
    from posekit.viewer.errors import ViewerError

    if not 0 <= ns.port <= 65535:
        print(f"posekit view: --port must be in 0..65535, got {ns.port}", file=sys.stderr)
        return 2
    if not 0 <= ns.foxglove_port <= 65535:
        print(f"posekit view: --foxglove-port must be in 0..65535, got {ns.foxglove_port}",
              file=sys.stderr)
        return 2
    if ns.scenario and (ns.zenoh or ns.transport):
        print("posekit view: --scenario runs in this process; it cannot be combined with "
              "--zenoh or --transport", file=sys.stderr)
        return 2
    options: dict[str, Any] = {"fixed_frame": ns.fixed_frame, "tf_rate": ns.tf_rate,
                               "allow_hosts": ns.allow_host, "allow_origins": ns.allow_origin}
    try:
        if ns.config:
            from posekit.viewer.server import load_view_config

            options["config"] = load_view_config(ns.config)
        if ns.scenario:
            return _view_scenario(ns, options)
        from posekit.cli._session import tool_transport

        return _view_remote(ns, options, "zenoh" if ns.zenoh else tool_transport(ns.transport))
    except ViewerError as exc:
        print(f"posekit view: {exc}", file=sys.stderr)
        return 1
    except ValueError as exc:
        print(f"posekit view: {exc}", file=sys.stderr)
        return 2


def _announce(server: ViewerServer, what: str) -> None:
    print(f"posekit view: {what} on {server.url} (Ctrl-C to stop)", flush=True)


def _sim_clock(run: LaunchRun) -> Callable[[], int] | None:
    """The run's simulated clock (ns) when its executor is a SimulatedTimeExecutor."""
    from posekit.runtime.sim_executor import SimulatedTimeExecutor

    executor = run.executor
    if not isinstance(executor, SimulatedTimeExecutor):
        return None
    sim: SimulatedTimeExecutor = executor
    return lambda: sim.now_ns


def _start_foxglove(
    ns: argparse.Namespace, transport: Transport, clock: Callable[[], int] | None = None
) -> FoxgloveBridge | None:
    """The started Foxglove bridge when ``--foxglove`` was given, else None."""
    if not ns.foxglove:
        return None
    from posekit.viewer.foxglove_bridge import FoxgloveBridge

    bridge = FoxgloveBridge(transport, host=ns.host, port=ns.foxglove_port, clock_ns=clock,
                            allow_hosts=ns.allow_host, allow_origins=ns.allow_origin)
    bridge.start()
    print(f"posekit view: Foxglove WebSocket on {bridge.url}", flush=True)
    return bridge


def _view_scenario(ns: argparse.Namespace, options: dict[str, Any]) -> int:
    import posekit.robot.scenarios  # noqa: F401 - registers the robot's scenarios
    from posekit.launch.scenarios import ScenarioError, start_scenario

    try:
        run = start_scenario(ns.scenario, seed=ns.seed, realtime=True)
    except ScenarioError as exc:
        print(f"posekit view: {exc}", file=sys.stderr)
        return 2
    server = None
    bridge = None
    try:
        server = attach_to_run(run, host=ns.host, port=ns.port, world=ns.world,
                               open_browser=ns.open, **options)
        _announce(server, f"scenario {ns.scenario}")
        bridge = _start_foxglove(ns, run.context.transport(), _sim_clock(run))
        spinner = threading.Thread(target=run.executor.spin, name="posekit-scenario", daemon=True)
        spinner.start()
        server.serve_forever()
    except KeyboardInterrupt:
        pass
    finally:
        if bridge is not None:
            bridge.stop()
        if server is not None:
            server.stop()
        run.shutdown()
    return 0


def _view_remote(ns: argparse.Namespace, options: dict[str, Any], transport_name: str) -> int:
    from posekit.runtime.context import Context
    from posekit.runtime.transport import UnknownTransportError
    from posekit.viewer import attach_viewer

    context = Context()
    context.init(transport=transport_name)
    try:
        try:
            transport = context.transport()
        except UnknownTransportError as exc:
            print(f"posekit view: cannot view other processes: {exc}", file=sys.stderr)
            return 1
        server = attach_viewer(transport, world=ns.world, host=ns.host, port=ns.port, **options)
        bridge = None
        try:
            if ns.open:
                webbrowser.open(server.url)
            _announce(server, f"viewing the {'DDS' if transport_name == 'dds' else 'Zenoh'} graph")
            bridge = _start_foxglove(ns, transport)
            server.serve_forever()
        finally:
            if bridge is not None:
                bridge.stop()
            server.stop()
    finally:
        context.try_shutdown()
    return 0
