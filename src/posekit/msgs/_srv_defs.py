"""ROS 2 Jazzy service definitions (``.srv`` text) of posekit's service types.

rosbags' Jazzy typestore holds message definitions only; posekit registers these in its
private typestore (:func:`posekit.msgs.cdr.get_typestore`) as the messages rosidl derives
from a service: ``<Srv>_Request``, ``<Srv>_Response``, ``<Srv>_Event`` (service
introspection) and the service description ``<Srv>`` itself (fields ``request_message``,
``response_message``, ``event_message``), so type hashes (RIHS01) of services come out as
rosidl computes them. Comments are left out: they change neither CDR nor hashes.
"""

from __future__ import annotations

from typing import Any

__all__ = [
    "SERVICE_DEFINITIONS",
    "service_definition_text",
    "service_message_definitions",
    "service_typedefs",
    "typedefs_from_texts",
]

_EMPTY = "uint8 structure_needs_at_least_one_member\n"

#: ``pkg/srv/Name`` -> (request text, response text).
SERVICE_DEFINITIONS: dict[str, tuple[str, str]] = {
    "std_srvs/srv/Empty": ("", ""),
    "std_srvs/srv/Trigger": ("", "bool success\nstring message\n"),
    "std_srvs/srv/SetBool": ("bool data\n", "bool success\nstring message\n"),
    "rcl_interfaces/srv/ListParameters": (
        "uint64 DEPTH_RECURSIVE=0\nstring[] prefixes\nuint64 depth\n",
        "rcl_interfaces/msg/ListParametersResult result\n",
    ),
    "rcl_interfaces/srv/GetParameters": (
        "string[] names\n",
        "rcl_interfaces/msg/ParameterValue[] values\n",
    ),
    "rcl_interfaces/srv/SetParameters": (
        "rcl_interfaces/msg/Parameter[] parameters\n",
        "rcl_interfaces/msg/SetParametersResult[] results\n",
    ),
    "rcl_interfaces/srv/SetParametersAtomically": (
        "rcl_interfaces/msg/Parameter[] parameters\n",
        "rcl_interfaces/msg/SetParametersResult result\n",
    ),
    "rcl_interfaces/srv/DescribeParameters": (
        "string[] names\n",
        "rcl_interfaces/msg/ParameterDescriptor[] descriptors\n",
    ),
    "rcl_interfaces/srv/GetParameterTypes": ("string[] names\n", "uint8[] types\n"),
    "type_description_interfaces/srv/GetTypeDescription": (
        "string type_name\nstring type_hash\nbool include_type_sources true\n",
        "bool successful\nstring failure_reason\n"
        "type_description_interfaces/msg/TypeDescription type_description\n"
        "type_description_interfaces/msg/TypeSource[] type_sources\n"
        "type_description_interfaces/msg/KeyValue[] extra_information\n",
    ),
    "lifecycle_msgs/srv/ChangeState": ("lifecycle_msgs/msg/Transition transition\n",
                                       "bool success\n"),
    "lifecycle_msgs/srv/GetState": ("", "lifecycle_msgs/msg/State current_state\n"),
    "lifecycle_msgs/srv/GetAvailableStates": ("", "lifecycle_msgs/msg/State[] available_states\n"),
    "lifecycle_msgs/srv/GetAvailableTransitions": (
        "", "lifecycle_msgs/msg/TransitionDescription[] available_transitions\n"),
    "action_msgs/srv/CancelGoal": (
        "action_msgs/msg/GoalInfo goal_info\n",
        "int8 ERROR_NONE=0\nint8 ERROR_REJECTED=1\nint8 ERROR_UNKNOWN_GOAL_ID=2\n"
        "int8 ERROR_GOAL_TERMINATED=3\nint8 return_code\n"
        "action_msgs/msg/GoalInfo[] goals_canceling\n",
    ),
}


def service_message_definitions(
    srv: str, request: str | None = None, response: str | None = None
) -> dict[str, str]:
    """Message texts rosidl derives from service ``srv`` (``pkg/srv/Name``), by type name.

    ``request``/``response`` default to the texts in :data:`SERVICE_DEFINITIONS` (an
    action's services pass theirs, under ``pkg/action/...`` names).
    """
    if request is None or response is None:
        request, response = SERVICE_DEFINITIONS[srv]
    request, response = request or _EMPTY, response or _EMPTY
    return {
        f"{srv}_Request": request,
        f"{srv}_Response": response,
        f"{srv}_Event": (
            "service_msgs/msg/ServiceEventInfo info\n"
            f"{srv}_Request[<=1] request\n"
            f"{srv}_Response[<=1] response\n"
        ),
        srv: (
            f"{srv}_Request request_message\n"
            f"{srv}_Response response_message\n"
            f"{srv}_Event event_message\n"
        ),
    }


_DELIMITER = "=" * 80 + "\n"


def service_definition_text(srv: str) -> str:
    """The complete definition of service ``srv`` as rosbag2 Jazzy stores it in a bag's schema.

    The schema of the service's event topic (rosbag2_cpp's ``LocalMessageDefinitionSource``): an
    80-``=`` line, ``SRV: pkg/srv/Name``, the ``.srv`` text (request, ``---``, response), then
    every message it uses, each after an 80-``=`` line and ``MSG: name`` (sorted by name, each
    once; nested ones after their user).
    """
    from posekit.msgs.cdr import get_typestore

    request, response = SERVICE_DEFINITIONS[srv]
    text = (request + "---\n" + response).replace("/msg/", "/")
    out = f"{_DELIMITER}SRV: {srv}\n{text}"
    deps = sorted({word for line in text.splitlines()
                   if "/" in (word := line.split(" ", 1)[0].split("[", 1)[0])})
    seen: set[str] = set()
    store = get_typestore()
    for dep in deps:
        if dep in seen:
            continue
        pkg, name = dep.split("/")
        full, _ = store.generate_msgdef(f"{pkg}/msg/{name}", ros_version=2)
        own, *nested = full.split(_DELIMITER)
        seen.add(dep)
        out += f"\n{_DELIMITER}MSG: {dep}\n{own.rstrip(chr(10))}\n"
        for block in nested:
            header, _, body = block.partition("\n")
            nested_name = header.removeprefix("MSG: ")
            if nested_name not in seen:
                seen.add(nested_name)
                out += f"\n{_DELIMITER}{header}\n{body.rstrip(chr(10))}\n"
    return out


def service_typedefs(srv: str) -> dict[str, Any]:
    """rosbags type definitions (for ``Typestore.register``) of ``srv``'s four types."""
    return typedefs_from_texts(service_message_definitions(srv))


def typedefs_from_texts(texts: dict[str, str]) -> dict[str, Any]:
    """rosbags type definitions of message texts named ``pkg/{msg,srv,action}/Name``.

    rosbags' parser files every name under ``pkg/msg/``, so the texts are parsed under
    ``msg`` names and the service/action-derived names are moved back afterwards.
    """
    from rosbags.interfaces import Nodetype
    from rosbags.typesys import get_types_from_msg

    def as_msg(text: str) -> str:
        return text.replace("/srv/", "/msg/").replace("/action/", "/msg/")

    renamed = {as_msg(name): name for name in texts}

    def fix(desc: Any) -> Any:
        kind, info = desc
        if kind == Nodetype.NAME:
            return (kind, renamed.get(info, info))
        if kind in (Nodetype.ARRAY, Nodetype.SEQUENCE):
            (subkind, subinfo), count = info
            if subkind == Nodetype.NAME:
                return (kind, ((subkind, renamed.get(subinfo, subinfo)), count))
        return desc

    out: dict[str, Any] = {}
    for name, text in texts.items():
        msg_name = as_msg(name)
        parsed = get_types_from_msg(as_msg(text), msg_name)
        consts, fields = parsed[msg_name]
        out[name] = (consts, [(fname, fix(desc)) for fname, desc in fields])
    return out
