"""std_srvs: Empty, Trigger and SetBool, laid out as rosidl generates them.

``SetBool.Request`` / ``SetBool.Response`` are the message classes (also importable as
``SetBool_Request`` / ``SetBool_Response``); their type names are
``std_srvs/srv/SetBool_Request`` and ``..._Response``, the service's ``std_srvs/srv/SetBool``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

__all__ = [
    "Empty",
    "Empty_Request",
    "Empty_Response",
    "SetBool",
    "SetBool_Request",
    "SetBool_Response",
    "Trigger",
    "Trigger_Request",
    "Trigger_Response",
]


@dataclass(slots=True)
class Empty_Request:  # noqa: N801 - rosidl name
    """std_srvs/srv/Empty_Request (no fields; CDR carries one placeholder byte)."""

    structure_needs_at_least_one_member: int = 0
    __msgtype__: ClassVar[str] = "std_srvs/srv/Empty_Request"


@dataclass(slots=True)
class Empty_Response:  # noqa: N801 - rosidl name
    """std_srvs/srv/Empty_Response (no fields)."""

    structure_needs_at_least_one_member: int = 0
    __msgtype__: ClassVar[str] = "std_srvs/srv/Empty_Response"


class Empty:
    """std_srvs/srv/Empty."""

    Request = Empty_Request
    Response = Empty_Response
    __srvtype__: ClassVar[str] = "std_srvs/srv/Empty"


@dataclass(slots=True)
class Trigger_Request:  # noqa: N801 - rosidl name
    """std_srvs/srv/Trigger_Request (no fields)."""

    structure_needs_at_least_one_member: int = 0
    __msgtype__: ClassVar[str] = "std_srvs/srv/Trigger_Request"


@dataclass(slots=True)
class Trigger_Response:  # noqa: N801 - rosidl name
    """std_srvs/srv/Trigger_Response: ``success`` and a human-readable ``message``."""

    success: bool = False
    message: str = ""
    __msgtype__: ClassVar[str] = "std_srvs/srv/Trigger_Response"


class Trigger:
    """std_srvs/srv/Trigger."""

    Request = Trigger_Request
    Response = Trigger_Response
    __srvtype__: ClassVar[str] = "std_srvs/srv/Trigger"


@dataclass(slots=True)
class SetBool_Request:  # noqa: N801 - rosidl name
    """std_srvs/srv/SetBool_Request: the ``data`` to set."""

    data: bool = False
    __msgtype__: ClassVar[str] = "std_srvs/srv/SetBool_Request"


@dataclass(slots=True)
class SetBool_Response:  # noqa: N801 - rosidl name
    """std_srvs/srv/SetBool_Response: ``success`` and a human-readable ``message``."""

    success: bool = False
    message: str = ""
    __msgtype__: ClassVar[str] = "std_srvs/srv/SetBool_Response"


class SetBool:
    """std_srvs/srv/SetBool."""

    Request = SetBool_Request
    Response = SetBool_Response
    __srvtype__: ClassVar[str] = "std_srvs/srv/SetBool"
