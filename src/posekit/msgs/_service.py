"""What makes a class a ROS 2 service type: ``Request``/``Response`` message classes."""

from __future__ import annotations

from typing import Any

from posekit.msgs.errors import UnknownMessageTypeError

__all__ = ["is_service_type", "service_type_name"]


def is_service_type(obj: object) -> bool:
    """True for a service class (``SetBool``): it names its type and has Request/Response."""
    return (
        isinstance(getattr(obj, "__srvtype__", None), str)
        and isinstance(getattr(obj, "Request", None), type)
        and isinstance(getattr(obj, "Response", None), type)
    )


def service_type_name(srv_type: Any) -> str:
    """``std_srvs/srv/SetBool`` for a service class (posekit's ``__srvtype__``)."""
    if not is_service_type(srv_type):
        raise UnknownMessageTypeError(
            f"{srv_type!r} is not a service type (needs __srvtype__, Request and Response)"
        )
    name: str = srv_type.__srvtype__
    return name
