"""posekit_interfaces: posekit's own action type, laid out as rosidl generates actions.

``NavigateToPose`` (definition in :mod:`posekit.msgs._action_defs`): the goal is a
``geometry_msgs/PoseStamped`` (position and heading in the odometry frame), feedback and
result carry ``distance_remaining`` in metres. As with rosidl, ``NavigateToPose.Goal`` /
``.Result`` / ``.Feedback`` are the message classes and ``NavigateToPose.Impl`` holds the
``SendGoalService``, ``GetResultService``, ``FeedbackMessage``, ``CancelGoalService`` and
``GoalStatusMessage`` types the action's services and topics carry.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

from posekit.msgs.action_msgs import CancelGoal, GoalStatusArray
from posekit.msgs.builtin_interfaces import Time
from posekit.msgs.geometry_msgs import PoseStamped
from posekit.msgs.unique_identifier_msgs import UUID

__all__ = [
    "NavigateToPose",
    "NavigateToPose_Feedback",
    "NavigateToPose_FeedbackMessage",
    "NavigateToPose_GetResult",
    "NavigateToPose_GetResult_Request",
    "NavigateToPose_GetResult_Response",
    "NavigateToPose_Goal",
    "NavigateToPose_Result",
    "NavigateToPose_SendGoal",
    "NavigateToPose_SendGoal_Request",
    "NavigateToPose_SendGoal_Response",
]

_NAV = "posekit_interfaces/action/NavigateToPose"


@dataclass(slots=True)
class NavigateToPose_Goal:  # noqa: N801 - rosidl name
    """The pose to reach (``header.frame_id`` is the frame of ``pose``)."""

    pose: PoseStamped = field(default_factory=PoseStamped)
    __msgtype__: ClassVar[str] = f"{_NAV}_Goal"


@dataclass(slots=True)
class NavigateToPose_Result:  # noqa: N801 - rosidl name
    """Distance (m) from the goal position when the goal ended."""

    distance_remaining: float = 0.0
    __msgtype__: ClassVar[str] = f"{_NAV}_Result"


@dataclass(slots=True)
class NavigateToPose_Feedback:  # noqa: N801 - rosidl name
    """Distance (m) still to go to the goal position."""

    distance_remaining: float = 0.0
    __msgtype__: ClassVar[str] = f"{_NAV}_Feedback"


@dataclass(slots=True)
class NavigateToPose_FeedbackMessage:  # noqa: N801 - rosidl name
    """What the ``<action>/_action/feedback`` topic carries: goal id and feedback."""

    goal_id: UUID = field(default_factory=UUID)
    feedback: NavigateToPose_Feedback = field(default_factory=NavigateToPose_Feedback)
    __msgtype__: ClassVar[str] = f"{_NAV}_FeedbackMessage"


@dataclass(slots=True)
class NavigateToPose_SendGoal_Request:  # noqa: N801 - rosidl name
    """A new goal and the id the client chose for it."""

    goal_id: UUID = field(default_factory=UUID)
    goal: NavigateToPose_Goal = field(default_factory=NavigateToPose_Goal)
    __msgtype__: ClassVar[str] = f"{_NAV}_SendGoal_Request"


@dataclass(slots=True)
class NavigateToPose_SendGoal_Response:  # noqa: N801 - rosidl name
    """Whether the server accepted the goal, and when."""

    accepted: bool = False
    stamp: Time = field(default_factory=Time)
    __msgtype__: ClassVar[str] = f"{_NAV}_SendGoal_Response"


class NavigateToPose_SendGoal:  # noqa: N801 - rosidl name
    """The ``<action>/_action/send_goal`` service type."""

    Request = NavigateToPose_SendGoal_Request
    Response = NavigateToPose_SendGoal_Response
    __srvtype__: ClassVar[str] = f"{_NAV}_SendGoal"


@dataclass(slots=True)
class NavigateToPose_GetResult_Request:  # noqa: N801 - rosidl name
    """The goal whose result is wanted."""

    goal_id: UUID = field(default_factory=UUID)
    __msgtype__: ClassVar[str] = f"{_NAV}_GetResult_Request"


@dataclass(slots=True)
class NavigateToPose_GetResult_Response:  # noqa: N801 - rosidl name
    """The goal's final status (action_msgs/GoalStatus STATUS_*) and result."""

    status: int = 0
    result: NavigateToPose_Result = field(default_factory=NavigateToPose_Result)
    __msgtype__: ClassVar[str] = f"{_NAV}_GetResult_Response"


class NavigateToPose_GetResult:  # noqa: N801 - rosidl name
    """The ``<action>/_action/get_result`` service type."""

    Request = NavigateToPose_GetResult_Request
    Response = NavigateToPose_GetResult_Response
    __srvtype__: ClassVar[str] = f"{_NAV}_GetResult"


class NavigateToPose:
    """posekit_interfaces/action/NavigateToPose."""

    Goal = NavigateToPose_Goal
    Result = NavigateToPose_Result
    Feedback = NavigateToPose_Feedback
    __actiontype__: ClassVar[str] = _NAV

    class Impl:
        """The types of the action's services and topics (rosidl's ``Impl``)."""

        SendGoalService = NavigateToPose_SendGoal
        GetResultService = NavigateToPose_GetResult
        FeedbackMessage = NavigateToPose_FeedbackMessage
        CancelGoalService = CancelGoal
        GoalStatusMessage = GoalStatusArray
