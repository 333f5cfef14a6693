"""Which world a system simulates, asked over its transport.

The ``world`` parameter of a node that declares one (the simulator's), read through the standard
parameter service (``<node>/get_parameters``, rcl_interfaces/srv/GetParameters) as ``ros2 param
get`` does.

Used by the viewer when it attaches to other processes without ``--world``, so the boxes
and markers of the simulated world appear with no flag. Every wait is bounded.
"""

from __future__ import annotations

import threading
import time
from typing import Any

from posekit.runtime.logging import RcutilsLogger
from posekit.runtime.qos import QoSProfile
from posekit.runtime.transport import ServiceInfo, Transport

__all__ = ["discover_world"]

_SUFFIX = "/get_parameters"
_TYPE = "rcl_interfaces/srv/GetParameters"
_PARAMETER_STRING = 4


def _candidates(transport: Transport, max_nodes: int) -> list[str]:
    """``get_parameters`` services, simulator-like node names first."""
    names = [name for name, types in transport.get_service_names_and_types()
             if name.endswith(_SUFFIX) and _TYPE in types]
    names.sort(key=lambda n: ("sim" not in n[: -len(_SUFFIX)].rsplit("/", 1)[-1], n))
    return names[:max_nodes]


def _ask(transport: Transport, service: str, logger: RcutilsLogger, timeout: float) -> str | None:
    from posekit.msgs.rcl_interfaces import GetParameters, GetParameters_Request

    info = ServiceInfo(service, GetParameters, QoSProfile(depth=10), "posekit_viewer", "/",
                       logger)
    client = transport.create_service_client(info)
    try:
        deadline = time.monotonic() + timeout
        while client.server_count <= 0:
            if time.monotonic() > deadline:
                return None
            time.sleep(0.02)
        done = threading.Event()
        answers: list[Any] = []

        def on_response(response: Any) -> None:
            answers.append(response)
            done.set()

        client.send_request(GetParameters_Request(names=["world"]), on_response)
        if not done.wait(max(0.0, deadline - time.monotonic())) or not answers:
            return None
        values = list(answers[0].values)
        if values and values[0].type == _PARAMETER_STRING and values[0].string_value:
            return str(values[0].string_value)
        return None
    finally:
        client.destroy()


def discover_world(transport: Transport, logger: RcutilsLogger, *, timeout: float = 1.0,
                   max_nodes: int = 16) -> str | None:
    """The first non-empty string ``world`` parameter among the nodes on ``transport``, or None.

    Among the nodes that serve parameters (nodes named like a simulator first, at most
    ``max_nodes``, ``timeout`` seconds each); None also when the transport has no services.
    """
    try:
        services = _candidates(transport, max_nodes)
    except Exception as exc:  # no services on this transport, or a failing graph query
        logger.debug(f"viewer: world discovery: no services ({exc})")
        return None
    for service in services:
        try:
            world = _ask(transport, service, logger, timeout)
        except Exception as exc:  # a vanished or broken peer: try the next one
            logger.debug(f"viewer: world discovery: {service}: {exc}")
            continue
        if world:
            return world
    return None
