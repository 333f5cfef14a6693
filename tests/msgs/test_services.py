"""Service message classes: CDR bytes and RIHS01 type hashes against the real ROS 2 Jazzy.

Oracles: ``rclpy.serialization.serialize_message`` of the real Jazzy rclpy (.venv-ros2)
for the bytes of every request and response, filled with values derived from the field
types; the type hashes ROS 2 ships in ``share/<pkg>/srv/<Srv>.json`` of that install; and
the field lists of the real generated classes (``get_fields_and_field_types``).
"""

from __future__ import annotations

import dataclasses
import json
from typing import Any

import numpy as np
import pytest

from _support.ros2 import ROS2_VENV, run_ros2_script
from posekit.msgs import SERVICE_CLASSES, from_cdr, get_service_class, to_cdr, type_hash_rihs01
from posekit.msgs.cdr import get_typestore
from posekit.msgs.std_srvs import SetBool

pytestmark = pytest.mark.slow


def _filled(cls: type, depth: int = 0) -> Any:
    """An instance with a value in every field (2 elements per unbounded sequence)."""
    from rosbags.interfaces import Nodetype

    store = get_typestore()
    obj = cls()
    for name, desc in store.fielddefs[cls.__msgtype__][1]:
        kind, info = desc
        if name == "structure_needs_at_least_one_member":
            continue  # not settable in rclpy

        def scalar(base: str, i: int, name: str = name) -> Any:
            if base == "bool":
                return i % 2 == 0
            if base == "string":
                return f"s{i}_{name}"
            if base in ("float32", "float64"):
                return 0.25 * (i + 1)
            return (i + 3) % 10

        if kind == Nodetype.BASE:
            value: Any = scalar(info[0], depth)
        elif kind == Nodetype.NAME:
            value = _filled(_class_of(info), depth + 1)
        else:
            (subkind, subinfo), count = info
            n = count if count else 2
            if subkind == Nodetype.NAME:
                value = [_filled(_class_of(subinfo), depth + i + 1) for i in range(n)]
            else:
                value = [scalar(subinfo[0], i) for i in range(n)]
        setattr(obj, name, value)
    return obj


def _class_of(type_name: str) -> type:
    from posekit.msgs.registry import MESSAGE_CLASSES

    return MESSAGE_CLASSES[type_name]


def _ros_expr(obj: Any) -> str:
    """Python source building the same message with the real generated classes."""
    if dataclasses.is_dataclass(obj):
        pkg, kind, name = obj.__msgtype__.split("/")
        name = name.replace("_Request", ".Request").replace("_Response", ".Response")
        ctor = f"{pkg}.{kind}.{name}"
        args = ", ".join(
            f"{f.name}={_ros_field(obj, f.name)}" for f in dataclasses.fields(obj)
            if f.name != "structure_needs_at_least_one_member"
        )
        return f"{ctor}({args})"
    if isinstance(obj, np.ndarray):
        return repr(obj.tolist())
    if isinstance(obj, list):
        return "[" + ", ".join(_ros_expr(x) for x in obj) + "]"
    return repr(obj)


def _ros_field(obj: Any, name: str) -> str:
    value = getattr(obj, name)
    if name == "byte_array_value":  # rclpy's byte[]: a list of 1-byte bytes
        return repr([bytes([v % 256]) for v in value])
    return _ros_expr(value)


def _cases() -> list[tuple[str, Any]]:
    cases = []
    for srv_name, srv in sorted(SERVICE_CLASSES.items()):
        if "/srv/" not in srv_name or srv_name.startswith("action_msgs/"):
            continue  # actions' services and CancelGoal (UUID arrays): tests/msgs/test_actions.py
        for part in (srv.Request, srv.Response):
            cases.append((f"{srv_name}/{part.__name__}/default", part()))
            cases.append((f"{srv_name}/{part.__name__}/filled", _filled(part)))
    return cases


def test_service_registry_and_classes() -> None:
    assert get_service_class("std_srvs/srv/SetBool") is SetBool
    assert get_service_class("std_srvs/SetBool") is SetBool
    assert SetBool.Request.__msgtype__ == "std_srvs/srv/SetBool_Request"
    assert {
        "std_srvs/srv/Empty", "std_srvs/srv/Trigger", "std_srvs/srv/SetBool",
        "rcl_interfaces/srv/ListParameters", "rcl_interfaces/srv/GetParameters",
        "rcl_interfaces/srv/SetParameters", "rcl_interfaces/srv/SetParametersAtomically",
        "rcl_interfaces/srv/DescribeParameters", "rcl_interfaces/srv/GetParameterTypes",
    } <= set(SERVICE_CLASSES)


def test_cdr_and_fields_equal_the_real_rclpy() -> None:
    """Both ways: the real rclpy decodes posekit's bytes into a message equal to the one it
    builds itself, and posekit decodes rclpy's bytes back to its own bytes. (rclpy leaves
    alignment padding uninitialised, so the raw bytes are compared up to padding: same
    length up to the final padding, same decoded values.)"""
    cases = _cases()
    script = ["import rclpy.serialization as ser, json",
              "import std_srvs.srv, rcl_interfaces.srv, rcl_interfaces.msg",
              "import type_description_interfaces.srv, type_description_interfaces.msg",
              "import lifecycle_msgs.srv, lifecycle_msgs.msg",
              "out = {}"]
    for label, msg in cases:
        script.append(f"m = {_ros_expr(msg)}")
        script.append(
            f"out[{label!r}] = [ser.serialize_message(m).hex(), "
            "list(m.get_fields_and_field_types()), "
            f"ser.deserialize_message(bytes.fromhex({to_cdr(msg).hex()!r}), type(m)) == m]"
        )
    script.append("print(json.dumps(out))")
    proc = run_ros2_script("\n".join(script), domain_id=0, timeout=120)
    assert proc.returncode == 0, proc.stderr
    ref = json.loads(proc.stdout)
    for label, msg in cases:
        ros_hex, ros_fields, ros_decodes_ours = ref[label]
        ours = to_cdr(msg)
        assert ros_decodes_ours, label
        # Fast CDR may pad the end to 4 bytes (empty structures); posekit stops at the last
        # field as rosbags does
        assert len(bytes.fromhex(ros_hex)) in (len(ours), (len(ours) + 3) // 4 * 4), label
        back = from_cdr(bytes.fromhex(ros_hex), type(msg))
        assert to_cdr(back) == ours, label
        names = [f.name for f in dataclasses.fields(msg)]
        assert names == (ros_fields or ["structure_needs_at_least_one_member"]), label


@pytest.mark.parametrize("srv_name", sorted(n for n in SERVICE_CLASSES if "/srv/" in n))
def test_type_hashes_equal_those_ros_ships(srv_name: str) -> None:
    pkg, _, name = srv_name.split("/")
    path = ROS2_VENV / "share" / pkg / "srv" / f"{name}.json"
    if not path.exists():
        from _support.ros2 import ros2_python

        ros2_python()  # builds the reference venv
    shipped = {
        h["type_name"]: h["hash_string"] for h in json.loads(path.read_text())["type_hashes"]
    }
    for type_name in (srv_name, f"{srv_name}_Request", f"{srv_name}_Response",
                      f"{srv_name}_Event"):
        assert type_hash_rihs01(type_name) == shipped[type_name], type_name
    assert type_hash_rihs01(get_service_class(srv_name)) == shipped[srv_name]
