"""Type descriptions (REP-2011) of posekit's types.

Oracles: rosbags' RIHS01 hash (its own implementation of REP-2011's hashing) of every type
of posekit's store, against the hash of :func:`describe_type`'s description; the real Jazzy
``.msg`` / ``.srv`` files of the reference ROS 2 install for the default values. The
answers of a real node's ``~/get_type_description`` are compared in
tests/rclpy/differential/type_description.py.
"""

from __future__ import annotations

import hashlib
import json
import re
from typing import Any

import pytest

from _support.ros2 import ros2_python
from posekit.msgs.cdr import get_typestore
from posekit.msgs.errors import UnknownMessageTypeError
from posekit.msgs.type_description import FIELD_DEFAULTS, describe_type
from posekit.msgs.type_description_interfaces import FieldType, TypeDescription


def rihs01(description: TypeDescription) -> str:
    """REP-2011: SHA-256 of the description's JSON without the default values."""
    def individual(t: Any) -> dict[str, Any]:
        return {"type_name": t.type_name, "fields": [
            {"name": f.name, "type": {
                "type_id": f.type.type_id, "capacity": f.type.capacity,
                "string_capacity": f.type.string_capacity,
                "nested_type_name": f.type.nested_type_name}}
            for f in t.fields]}

    text = json.dumps({
        "type_description": individual(description.type_description),
        "referenced_type_descriptions": [
            individual(t) for t in description.referenced_type_descriptions],
    }, separators=(", ", ": "))
    return "RIHS01_" + hashlib.sha256(text.encode()).hexdigest()


def test_every_type_hashes_as_rosbags_hashes_it() -> None:
    store = get_typestore()
    names = sorted(store.fielddefs)
    assert len(names) > 200  # the Jazzy store and posekit's services and actions
    for name in names:
        assert rihs01(describe_type(name)) == store.hash_rihs01(name), name


def test_field_kinds_are_numbered_as_rosidl() -> None:
    fields = {f.name: f.type for f in describe_type(
        "sensor_msgs/msg/CameraInfo").type_description.fields}
    assert fields["d"] == FieldType(type_id=FieldType.FIELD_TYPE_DOUBLE_UNBOUNDED_SEQUENCE)
    assert fields["k"] == FieldType(type_id=FieldType.FIELD_TYPE_DOUBLE_ARRAY, capacity=9)
    assert fields["roi"].type_id == FieldType.FIELD_TYPE_NESTED_TYPE
    assert fields["roi"].nested_type_name == "sensor_msgs/msg/RegionOfInterest"
    field_type = {f.name: f.type for f in describe_type(
        "type_description_interfaces/msg/FieldType").type_description.fields}
    assert field_type["nested_type_name"] == FieldType(
        type_id=FieldType.FIELD_TYPE_BOUNDED_STRING, string_capacity=255)
    event = {f.name: f.type for f in describe_type(
        "std_srvs/srv/SetBool_Event").type_description.fields}
    assert event["request"] == FieldType(
        type_id=FieldType.FIELD_TYPE_NESTED_TYPE_BOUNDED_SEQUENCE, capacity=1,
        nested_type_name="std_srvs/srv/SetBool_Request")


def test_referenced_types_are_each_nested_type_once_sorted() -> None:
    d = describe_type("tf2_msgs/msg/TFMessage")
    assert [t.type_name for t in d.referenced_type_descriptions] == [
        "builtin_interfaces/msg/Time", "geometry_msgs/msg/Quaternion",
        "geometry_msgs/msg/Transform", "geometry_msgs/msg/TransformStamped",
        "geometry_msgs/msg/Vector3", "std_msgs/msg/Header"]


def test_a_caller_cannot_change_the_next_answer() -> None:
    describe_type("std_msgs/msg/String").type_description.fields.clear()
    assert [f.name for f in describe_type("std_msgs/msg/String").type_description.fields] == [
        "data"]


def test_an_unknown_type_is_a_named_error() -> None:
    with pytest.raises(UnknownMessageTypeError, match="nope/msg/Nothing"):
        describe_type("nope/msg/Nothing")


_FIELD = re.compile(r"^([A-Za-z0-9_/]+)(\[[^\]]*\])?\s+([a-z][a-z0-9_]*)\s+(\S.*)$")


def _rosidl_text(base: str, literal: str) -> str:
    """A default literal as rosidl writes it in a type description (the parsed value's str)."""
    if base == "bool":
        return str(literal.lower() in ("true", "1"))
    if base.startswith("float"):
        return str(float(literal))
    return str(int(literal))


@pytest.mark.slow
def test_defaults_are_those_of_the_real_jazzy_files() -> None:
    share = ros2_python().parents[1] / "share"
    found: dict[str, dict[str, str]] = {}
    for path in sorted([*share.glob("*/msg/*.msg"), *share.glob("*/srv/*.srv")]):
        package, kind = path.parts[-3], path.parts[-2]
        parts = [path.stem] if kind == "msg" else [f"{path.stem}_Request", f"{path.stem}_Response"]
        texts = re.split(r"^---[ \t]*$", path.read_text(), flags=re.MULTILINE)
        for part, text in zip(parts, texts, strict=True):
            for line in text.splitlines():
                m = _FIELD.match(line.split("#", 1)[0].strip())
                if m and "=" not in line.split("#", 1)[0]:
                    type_name = f"{package}/{kind}/{part}"
                    found.setdefault(type_name, {})[m[3]] = _rosidl_text(m[1], m[4].strip())
    store = get_typestore().fielddefs
    assert {name: found[name] for name in found if name in store} == FIELD_DEFAULTS
