"""action_msgs: goal info and status messages and the CancelGoal service of ROS 2 actions."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

from posekit.msgs.builtin_interfaces import Time
from posekit.msgs.unique_identifier_msgs import UUID

__all__ = [
    "CancelGoal",
    "CancelGoal_Request",
    "CancelGoal_Response",
    "GoalInfo",
    "GoalStatus",
    "GoalStatusArray",
]


@dataclass(slots=True)
class GoalInfo:
    """action_msgs/msg/GoalInfo: a goal's id and the time the server accepted it."""

    goal_id: UUID = field(default_factory=UUID)
    stamp: Time = field(default_factory=Time)
    __msgtype__: ClassVar[str] = "action_msgs/msg/GoalInfo"


@dataclass(slots=True)
class GoalStatus:
    """action_msgs/msg/GoalStatus: a goal and its state (the STATUS_* constants)."""

    goal_info: GoalInfo = field(default_factory=GoalInfo)
    status: int = 0
    __msgtype__: ClassVar[str] = "action_msgs/msg/GoalStatus"
    STATUS_UNKNOWN: ClassVar[int] = 0
    STATUS_ACCEPTED: ClassVar[int] = 1
    STATUS_EXECUTING: ClassVar[int] = 2
    STATUS_CANCELING: ClassVar[int] = 3
    STATUS_SUCCEEDED: ClassVar[int] = 4
    STATUS_CANCELED: ClassVar[int] = 5
    STATUS_ABORTED: ClassVar[int] = 6


@dataclass(slots=True)
class GoalStatusArray:
    """action_msgs/msg/GoalStatusArray: the ``<action>/_action/status`` topic's message."""

    status_list: list[GoalStatus] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "action_msgs/msg/GoalStatusArray"


@dataclass(slots=True)
class CancelGoal_Request:  # noqa: N801 - rosidl name
    """action_msgs/srv/CancelGoal_Request: which goals to cancel.

    A zero ``goal_id`` with a zero ``stamp`` cancels every goal; a zero ``goal_id`` with a
    stamp cancels the goals accepted at or before it; a ``goal_id`` cancels that goal (and,
    with a stamp, also those accepted at or before it).
    """

    goal_info: GoalInfo = field(default_factory=GoalInfo)
    __msgtype__: ClassVar[str] = "action_msgs/srv/CancelGoal_Request"


@dataclass(slots=True)
class CancelGoal_Response:  # noqa: N801 - rosidl name
    """action_msgs/srv/CancelGoal_Response.

    ``return_code`` (ERROR_*) and the goals now canceling.
    """

    return_code: int = 0
    goals_canceling: list[GoalInfo] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "action_msgs/srv/CancelGoal_Response"
    ERROR_NONE: ClassVar[int] = 0
    ERROR_REJECTED: ClassVar[int] = 1
    ERROR_UNKNOWN_GOAL_ID: ClassVar[int] = 2
    ERROR_GOAL_TERMINATED: ClassVar[int] = 3


class CancelGoal:
    """action_msgs/srv/CancelGoal."""

    Request = CancelGoal_Request
    Response = CancelGoal_Response
    __srvtype__: ClassVar[str] = "action_msgs/srv/CancelGoal"
