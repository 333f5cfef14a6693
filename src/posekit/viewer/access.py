"""Who may talk to the viewer's servers: the ``Host`` and WebSocket ``Origin`` checks.

Shared by the page server and the Foxglove bridge. Against DNS rebinding: a page from another
site that resolves its own name to 127.0.0.1 still sends its own name in ``Host``; and against a
page open in the user's browser connecting to the local WebSocket: it sends its own ``Origin``.
"""

from __future__ import annotations

from collections.abc import Iterable

__all__ = ["host_allowed", "origin_allowed", "own_hosts"]


def own_hosts(bound_host: str, port: int) -> set[str]:
    """``host:port`` values that name a server bound to ``bound_host``:``port``, lower case.

    The loopback names, and the bound host unless it is a wildcard address.
    """
    names = {"localhost", "127.0.0.1", "[::1]"}
    if bound_host not in ("", "0.0.0.0", "::"):
        names.add(f"[{bound_host}]" if ":" in bound_host else bound_host)
    return {f"{n.lower()}:{port}" for n in names}


def host_allowed(header: str | None, bound_host: str, port: int,
                 allow_hosts: Iterable[str] = ()) -> bool:
    """Whether a request's ``Host`` header names this server.

    One of :func:`own_hosts`, or listed in ``allow_hosts`` (``name`` or ``name:port``, lower
    case; ``"*"``: any).
    """
    allowed = frozenset(allow_hosts)
    if "*" in allowed:
        return True
    if not header:
        return False
    host = header.strip().lower()
    if host in allowed or host in own_hosts(bound_host, port):
        return True
    name = host.rsplit(":", 1)[0] if not host.endswith("]") else host
    return name in allowed


def origin_allowed(origin: str | None, bound_host: str, port: int,
                   allow_origins: Iterable[str] = ()) -> bool:
    """Whether a WebSocket ``Origin`` may connect.

    Absent (not a browser), a page served by this server (``http(s)://`` one of
    :func:`own_hosts`), or listed in ``allow_origins`` (``scheme://host[:port]``, lower case;
    ``"*"``: any).
    """
    allowed = frozenset(allow_origins)
    if origin is None or "*" in allowed:
        return True
    origin = origin.strip().lower().rstrip("/")
    if origin in allowed:
        return True
    return any(origin == f"{scheme}://{h}" for h in own_hosts(bound_host, port)
               for scheme in ("http", "https"))
