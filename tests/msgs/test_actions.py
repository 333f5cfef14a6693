"""Action types: rosidl's derived types, their type hashes and CDR.

Oracles: the real ROS 2 Jazzy rosidl toolchain in .venv-ros2 — rosidl_adapter converts
posekit's ``.action`` text to IDL and rosidl_generator_type_description computes every
derived type's RIHS01 hash and field list (what rmw_zenoh puts in its key expressions);
the action_msgs hashes ROS ships (share/action_msgs/*.json); the real rclpy's
serialize/deserialize for action_msgs messages (both ways).
"""

from __future__ import annotations

import dataclasses
import json
from typing import Any

import numpy as np
import pytest

from _support.ros2 import ROS2_VENV, ros2_python, run_ros2_script
from posekit.msgs import from_cdr, to_cdr, type_hash_rihs01
from posekit.msgs._action_defs import ACTION_DEFINITIONS
from posekit.msgs.action_msgs import CancelGoal, GoalInfo, GoalStatus, GoalStatusArray
from posekit.msgs.builtin_interfaces import Time
from posekit.msgs.registry import ACTION_CLASSES, MESSAGE_CLASSES, get_action_class
from posekit.msgs.unique_identifier_msgs import UUID

NAV = "posekit_interfaces/action/NavigateToPose"

ROSIDL = """
import contextlib, io, json, os, sys, tempfile
from pathlib import Path
from rosidl_adapter.action import convert_action_to_idl
from rosidl_generator_type_description import generate_type_hash
share = Path(sys.prefix) / "share"
out = {}
for full, (goal, result, feedback) in json.loads(DEFS).items():
    pkg, _, name = full.split("/")
    tmp = Path(tempfile.mkdtemp())
    (tmp / "action").mkdir()
    text = "\\n---\\n".join(t.replace("/msg/", "/") for t in (goal, result, feedback))
    (tmp / "action" / f"{name}.action").write_text(text)
    idl_dir = tmp / "idl"
    (idl_dir / "action").mkdir(parents=True)
    with contextlib.redirect_stdout(io.StringIO()):  # it reports what it writes
        convert_action_to_idl(tmp, pkg, Path("action") / f"{name}.action", idl_dir / "action")
    args = {"package_name": pkg, "output_dir": str(tmp / "json"),
            "idl_tuples": [f"{idl_dir}:action/{name}.idl"],
            "include_paths": [f"{p.name}:{p}" for p in share.iterdir() if p.is_dir()]}
    (tmp / "args.json").write_text(json.dumps(args))
    with contextlib.redirect_stdout(io.StringIO()):
        generated = generate_type_hash(str(tmp / "args.json"))
    for path in generated:
        content = json.loads(Path(path).read_text())
        description = content["type_description_msg"]["type_description"]
        out[description["type_name"]] = {
            "hash": content["type_hashes"][0]["hash_string"],
            "fields": [f["name"] for f in description["fields"]],
        }
print(json.dumps(out))
"""


@pytest.mark.slow
def test_derived_types_and_hashes_equal_rosidls() -> None:
    result = run_ros2_script(f"DEFS = {json.dumps(json.dumps(ACTION_DEFINITIONS))}\n" + ROSIDL,
                             domain_id=137, timeout=120)
    assert result.returncode == 0, result.stderr
    reference = json.loads(result.stdout)
    expected_names = {f"{NAV}{suffix}" for suffix in (
        "", "_Goal", "_Result", "_Feedback", "_FeedbackMessage", "_SendGoal",
        "_SendGoal_Request", "_SendGoal_Response", "_SendGoal_Event", "_GetResult",
        "_GetResult_Request", "_GetResult_Response", "_GetResult_Event")}
    assert expected_names <= set(reference)
    for type_name, ref in reference.items():
        assert type_hash_rihs01(type_name) == ref["hash"], type_name
        cls = MESSAGE_CLASSES.get(type_name)
        if cls is not None:  # the message classes posekit has (not the _Event ones)
            fields = [f.name for f in dataclasses.fields(cls)]
            assert fields == ref["fields"], type_name


@pytest.mark.parametrize("name", ["GoalInfo", "GoalStatus", "GoalStatusArray"])
def test_action_msgs_hashes_equal_those_ros_ships(name: str) -> None:
    ros2_python()  # builds the reference venv if needed
    path = ROS2_VENV / "share" / "action_msgs" / "msg" / f"{name}.json"
    shipped = {h["type_name"]: h["hash_string"]
               for h in json.loads(path.read_text())["type_hashes"]}
    for type_name, hash_string in shipped.items():
        assert type_hash_rihs01(type_name) == hash_string, type_name


def _uuid(seed: int) -> UUID:
    return UUID(uuid=np.arange(seed, seed + 16, dtype=np.uint8))


def _status_array() -> GoalStatusArray:
    return GoalStatusArray(status_list=[
        GoalStatus(GoalInfo(_uuid(1), Time(12, 345)), GoalStatus.STATUS_EXECUTING),
        GoalStatus(GoalInfo(_uuid(40), Time(13, 0)), GoalStatus.STATUS_CANCELED),
    ])


def _ros_uuid(u: UUID) -> str:
    return f"unique_identifier_msgs.msg.UUID(uuid=list({bytes(u.uuid)!r}))"


def _ros_info(info: GoalInfo) -> str:
    return (f"action_msgs.msg.GoalInfo(goal_id={_ros_uuid(info.goal_id)}, stamp="
            f"builtin_interfaces.msg.Time(sec={info.stamp.sec}, nanosec={info.stamp.nanosec}))")


@pytest.mark.slow
def test_action_msgs_cdr_both_ways_with_the_real_rclpy() -> None:
    array = _status_array()
    request = CancelGoal.Request(goal_info=GoalInfo(_uuid(7), Time(1, 2)))
    response = CancelGoal.Response(
        return_code=CancelGoal.Response.ERROR_NONE,
        goals_canceling=[s.goal_info for s in array.status_list])
    cases: dict[str, tuple[Any, str]] = {
        "status": (array, "action_msgs.msg.GoalStatusArray(status_list=[" + ", ".join(
            f"action_msgs.msg.GoalStatus(goal_info={_ros_info(s.goal_info)}, status={s.status})"
            for s in array.status_list) + "])"),
        "request": (request, f"action_msgs.srv.CancelGoal.Request(goal_info="
                             f"{_ros_info(request.goal_info)})"),
        "response": (response, "action_msgs.srv.CancelGoal.Response(return_code=0, "
                               "goals_canceling=[" + ", ".join(
                                   _ros_info(g) for g in response.goals_canceling) + "])"),
    }
    script = ["import json", "import rclpy.serialization as ser",
              "import action_msgs.msg, action_msgs.srv, unique_identifier_msgs.msg",
              "import builtin_interfaces.msg", "out = {}"]
    for label, (msg, ros_expr) in cases.items():
        script += [f"m = {ros_expr}",
                   f"out[{label!r}] = [ser.serialize_message(m).hex(), ser.deserialize_message("
                   f"bytes.fromhex({to_cdr(msg).hex()!r}), type(m)) == m]"]
    script.append("print(json.dumps(out))")
    result = run_ros2_script("\n".join(script), domain_id=138)
    assert result.returncode == 0, result.stderr
    reference = json.loads(result.stdout)
    for label, (msg, _) in cases.items():
        ros_hex, ros_decodes_ours = reference[label]
        assert ros_decodes_ours, label
        back = from_cdr(bytes.fromhex(ros_hex), type(msg))
        assert to_cdr(back) == to_cdr(msg), label  # equal up to Fast CDR's padding bytes


def test_action_class_layout_follows_rosidl() -> None:
    nav = get_action_class(NAV)
    assert get_action_class("posekit_interfaces/NavigateToPose") is nav
    assert ACTION_CLASSES[NAV] is nav
    impl = nav.Impl
    assert impl.SendGoalService.Request().goal == nav.Goal()
    assert impl.GetResultService.Response().result == nav.Result()
    assert impl.FeedbackMessage().feedback == nav.Feedback()
    assert impl.CancelGoalService is CancelGoal
    assert impl.GoalStatusMessage is GoalStatusArray
    assert impl.FeedbackMessage.get_fields_and_field_types() == {
        "goal_id": "unique_identifier_msgs/UUID",
        "feedback": "posekit_interfaces/NavigateToPose_Feedback"}
