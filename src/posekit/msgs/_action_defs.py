"""ROS 2 action definitions (``.action`` text) of posekit's action types.

For an action ``pkg/action/Name`` rosidl generates, and posekit registers in its private
typestore (:func:`posekit.msgs.cdr.get_typestore`): the messages ``Name_Goal``,
``Name_Result``, ``Name_Feedback``; the services ``Name_SendGoal`` (request: ``goal_id`` +
``goal``; response: ``accepted`` + ``stamp``) and ``Name_GetResult`` (request: ``goal_id``;
response: ``status`` + ``result``), each with its request/response/event messages; and the
feedback topic's ``Name_FeedbackMessage`` (``goal_id`` + ``feedback``); and ``Name`` itself,
the description its type hash is computed from (fields ``goal``, ``result``, ``feedback``,
``send_goal_service``, ``get_result_service``, ``feedback_message``). Cancelling and
status use ``action_msgs/srv/CancelGoal`` and ``action_msgs/msg/GoalStatusArray``.
"""

from __future__ import annotations

from typing import Any

from posekit.msgs._srv_defs import service_message_definitions, typedefs_from_texts

__all__ = ["ACTION_DEFINITIONS", "action_message_definitions", "action_typedefs"]

_UUID = "unique_identifier_msgs/msg/UUID"

#: ``pkg/action/Name`` -> (goal text, result text, feedback text).
ACTION_DEFINITIONS: dict[str, tuple[str, str, str]] = {
    # Drive to a pose (the P controller's action): goal pose in the odometry frame; feedback
    # and result give the remaining straight-line distance to the goal position, metres.
    "posekit_interfaces/action/NavigateToPose": (
        "geometry_msgs/msg/PoseStamped pose\n",
        "float64 distance_remaining\n",
        "float64 distance_remaining\n",
    ),
}


def action_message_definitions(action: str) -> dict[str, str]:
    """Message texts rosidl derives from ``action`` (``pkg/action/Name``), by type name."""
    goal, result, feedback = ACTION_DEFINITIONS[action]
    texts = {
        f"{action}_Goal": goal,
        f"{action}_Result": result,
        f"{action}_Feedback": feedback,
        f"{action}_FeedbackMessage": (
            f"{_UUID} goal_id\n{action}_Feedback feedback\n"
        ),
    }
    texts.update(service_message_definitions(
        f"{action}_SendGoal",
        f"{_UUID} goal_id\n{action}_Goal goal\n",
        "bool accepted\nbuiltin_interfaces/msg/Time stamp\n",
    ))
    texts.update(service_message_definitions(
        f"{action}_GetResult",
        f"{_UUID} goal_id\n",
        f"int8 status\n{action}_Result result\n",
    ))
    # the action's own description (what its RIHS01 type hash covers)
    texts[action] = (
        f"{action}_Goal goal\n{action}_Result result\n{action}_Feedback feedback\n"
        f"{action}_SendGoal send_goal_service\n{action}_GetResult get_result_service\n"
        f"{action}_FeedbackMessage feedback_message\n"
    )
    return texts


def action_typedefs(action: str) -> dict[str, Any]:
    """rosbags type definitions (for ``Typestore.register``) of everything ``action`` needs."""
    return typedefs_from_texts(action_message_definitions(action))
