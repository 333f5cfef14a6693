"""lifecycle_msgs: the states, transitions and services of managed (lifecycle) nodes.

Field order, constants and types as ROS 2 Jazzy's; what :mod:`posekit.runtime.lifecycle`
serves and publishes.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

__all__ = [
    "ChangeState",
    "ChangeState_Request",
    "ChangeState_Response",
    "GetAvailableStates",
    "GetAvailableStates_Request",
    "GetAvailableStates_Response",
    "GetAvailableTransitions",
    "GetAvailableTransitions_Request",
    "GetAvailableTransitions_Response",
    "GetState",
    "GetState_Request",
    "GetState_Response",
    "State",
    "Transition",
    "TransitionDescription",
    "TransitionEvent",
]


@dataclass(slots=True)
class State:
    """lifecycle_msgs/msg/State: a state's ``id`` (the constants) and ``label``."""

    id: int = 0
    label: str = ""
    __msgtype__: ClassVar[str] = "lifecycle_msgs/msg/State"
    PRIMARY_STATE_UNKNOWN: ClassVar[int] = 0
    PRIMARY_STATE_UNCONFIGURED: ClassVar[int] = 1
    PRIMARY_STATE_INACTIVE: ClassVar[int] = 2
    PRIMARY_STATE_ACTIVE: ClassVar[int] = 3
    PRIMARY_STATE_FINALIZED: ClassVar[int] = 4
    TRANSITION_STATE_CONFIGURING: ClassVar[int] = 10
    TRANSITION_STATE_CLEANINGUP: ClassVar[int] = 11
    TRANSITION_STATE_SHUTTINGDOWN: ClassVar[int] = 12
    TRANSITION_STATE_ACTIVATING: ClassVar[int] = 13
    TRANSITION_STATE_DEACTIVATING: ClassVar[int] = 14
    TRANSITION_STATE_ERRORPROCESSING: ClassVar[int] = 15


@dataclass(slots=True)
class Transition:
    """lifecycle_msgs/msg/Transition: a transition's ``id`` (the constants) and ``label``."""

    id: int = 0
    label: str = ""
    __msgtype__: ClassVar[str] = "lifecycle_msgs/msg/Transition"
    TRANSITION_CREATE: ClassVar[int] = 0
    TRANSITION_CONFIGURE: ClassVar[int] = 1
    TRANSITION_CLEANUP: ClassVar[int] = 2
    TRANSITION_ACTIVATE: ClassVar[int] = 3
    TRANSITION_DEACTIVATE: ClassVar[int] = 4
    TRANSITION_UNCONFIGURED_SHUTDOWN: ClassVar[int] = 5
    TRANSITION_INACTIVE_SHUTDOWN: ClassVar[int] = 6
    TRANSITION_ACTIVE_SHUTDOWN: ClassVar[int] = 7
    TRANSITION_DESTROY: ClassVar[int] = 8
    TRANSITION_ON_CONFIGURE_SUCCESS: ClassVar[int] = 10
    TRANSITION_ON_CONFIGURE_FAILURE: ClassVar[int] = 11
    TRANSITION_ON_CONFIGURE_ERROR: ClassVar[int] = 12
    TRANSITION_ON_CLEANUP_SUCCESS: ClassVar[int] = 20
    TRANSITION_ON_CLEANUP_FAILURE: ClassVar[int] = 21
    TRANSITION_ON_CLEANUP_ERROR: ClassVar[int] = 22
    TRANSITION_ON_ACTIVATE_SUCCESS: ClassVar[int] = 30
    TRANSITION_ON_ACTIVATE_FAILURE: ClassVar[int] = 31
    TRANSITION_ON_ACTIVATE_ERROR: ClassVar[int] = 32
    TRANSITION_ON_DEACTIVATE_SUCCESS: ClassVar[int] = 40
    TRANSITION_ON_DEACTIVATE_FAILURE: ClassVar[int] = 41
    TRANSITION_ON_DEACTIVATE_ERROR: ClassVar[int] = 42
    TRANSITION_ON_SHUTDOWN_SUCCESS: ClassVar[int] = 50
    TRANSITION_ON_SHUTDOWN_FAILURE: ClassVar[int] = 51
    TRANSITION_ON_SHUTDOWN_ERROR: ClassVar[int] = 52
    TRANSITION_ON_ERROR_SUCCESS: ClassVar[int] = 60
    TRANSITION_ON_ERROR_FAILURE: ClassVar[int] = 61
    TRANSITION_ON_ERROR_ERROR: ClassVar[int] = 62
    TRANSITION_CALLBACK_SUCCESS: ClassVar[int] = 97
    TRANSITION_CALLBACK_FAILURE: ClassVar[int] = 98
    TRANSITION_CALLBACK_ERROR: ClassVar[int] = 99


@dataclass(slots=True)
class TransitionDescription:
    """lifecycle_msgs/msg/TransitionDescription: a transition and the states it joins."""

    transition: Transition = field(default_factory=Transition)
    start_state: State = field(default_factory=State)
    goal_state: State = field(default_factory=State)
    __msgtype__: ClassVar[str] = "lifecycle_msgs/msg/TransitionDescription"


@dataclass(slots=True)
class TransitionEvent:
    """lifecycle_msgs/msg/TransitionEvent: a node went from one state to another."""

    timestamp: int = 0
    transition: Transition = field(default_factory=Transition)
    start_state: State = field(default_factory=State)
    goal_state: State = field(default_factory=State)
    __msgtype__: ClassVar[str] = "lifecycle_msgs/msg/TransitionEvent"


@dataclass(slots=True)
class ChangeState_Request:  # noqa: N801 - rosidl name
    """The transition to take (by ``label`` when it is set, else by ``id``)."""

    transition: Transition = field(default_factory=Transition)
    __msgtype__: ClassVar[str] = "lifecycle_msgs/srv/ChangeState_Request"


@dataclass(slots=True)
class ChangeState_Response:  # noqa: N801 - rosidl name
    """Whether the transition's callback succeeded."""

    success: bool = False
    __msgtype__: ClassVar[str] = "lifecycle_msgs/srv/ChangeState_Response"


class ChangeState:
    """lifecycle_msgs/srv/ChangeState."""

    Request = ChangeState_Request
    Response = ChangeState_Response
    __srvtype__: ClassVar[str] = "lifecycle_msgs/srv/ChangeState"


@dataclass(slots=True)
class GetState_Request:  # noqa: N801 - rosidl name
    """No fields."""

    structure_needs_at_least_one_member: int = 0
    __msgtype__: ClassVar[str] = "lifecycle_msgs/srv/GetState_Request"


@dataclass(slots=True)
class GetState_Response:  # noqa: N801 - rosidl name
    """The node's current state."""

    current_state: State = field(default_factory=State)
    __msgtype__: ClassVar[str] = "lifecycle_msgs/srv/GetState_Response"


class GetState:
    """lifecycle_msgs/srv/GetState."""

    Request = GetState_Request
    Response = GetState_Response
    __srvtype__: ClassVar[str] = "lifecycle_msgs/srv/GetState"


@dataclass(slots=True)
class GetAvailableStates_Request:  # noqa: N801 - rosidl name
    """No fields."""

    structure_needs_at_least_one_member: int = 0
    __msgtype__: ClassVar[str] = "lifecycle_msgs/srv/GetAvailableStates_Request"


@dataclass(slots=True)
class GetAvailableStates_Response:  # noqa: N801 - rosidl name
    """Every state of the state machine."""

    available_states: list[State] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "lifecycle_msgs/srv/GetAvailableStates_Response"


class GetAvailableStates:
    """lifecycle_msgs/srv/GetAvailableStates."""

    Request = GetAvailableStates_Request
    Response = GetAvailableStates_Response
    __srvtype__: ClassVar[str] = "lifecycle_msgs/srv/GetAvailableStates"


@dataclass(slots=True)
class GetAvailableTransitions_Request:  # noqa: N801 - rosidl name
    """No fields."""

    structure_needs_at_least_one_member: int = 0
    __msgtype__: ClassVar[str] = "lifecycle_msgs/srv/GetAvailableTransitions_Request"


@dataclass(slots=True)
class GetAvailableTransitions_Response:  # noqa: N801 - rosidl name
    """The transitions (from the current state, or the whole graph)."""

    available_transitions: list[TransitionDescription] = field(default_factory=list)
    __msgtype__: ClassVar[str] = "lifecycle_msgs/srv/GetAvailableTransitions_Response"


class GetAvailableTransitions:
    """lifecycle_msgs/srv/GetAvailableTransitions (also ``~/get_transition_graph``'s type)."""

    Request = GetAvailableTransitions_Request
    Response = GetAvailableTransitions_Response
    __srvtype__: ClassVar[str] = "lifecycle_msgs/srv/GetAvailableTransitions"
