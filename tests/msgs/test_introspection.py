"""get_fields_and_field_types() / _fields_and_field_types on every posekit message class.

Oracle: the real ROS 2 Jazzy rosidl-generated classes in .venv-ros2 (every type whose
package the reference environment has is printed there and compared string for string).
"""

from __future__ import annotations

import json

import pytest

from _support.ros2 import run_ros2_script
from posekit.msgs.geometry_msgs import PoseWithCovariance
from posekit.msgs.registry import MESSAGE_CLASSES
from posekit.msgs.sensor_msgs import Image

PROBE = """
import importlib, json, sys
out = {}
for name in json.loads(sys.argv[1] if len(sys.argv) > 1 else NAMES):
    pkg, kind, typ = name.split("/")
    try:
        module = importlib.import_module(f"{pkg}.{kind}")
    except ImportError:
        continue
    if kind == "srv" and typ.endswith(("_Request", "_Response")):
        base, _, part = typ.rpartition("_")
        cls = getattr(getattr(module, base), part)
    else:
        cls = getattr(module, typ)
    out[name] = cls.get_fields_and_field_types()
print(json.dumps(out))
"""


@pytest.mark.slow
def test_field_types_match_rosidl_for_every_shared_type() -> None:
    names = sorted(MESSAGE_CLASSES)
    result = run_ros2_script(f"NAMES = {json.dumps(json.dumps(names))}\n" + PROBE,
                             domain_id=135)
    assert result.returncode == 0, result.stderr
    reference = json.loads(result.stdout)
    # the reference environment has most of posekit's packages (tf2_msgs is not installed)
    assert len(reference) >= 25, sorted(reference)
    for name, fields in reference.items():
        cls = MESSAGE_CLASSES[name]
        assert cls.get_fields_and_field_types() == fields, name
        assert list(cls.get_fields_and_field_types()) == list(fields), name  # order too
        assert cls._fields_and_field_types == fields, name


def test_rosidl_spellings() -> None:
    assert PoseWithCovariance.get_fields_and_field_types() == {
        "pose": "geometry_msgs/Pose", "covariance": "double[36]"}
    assert Image().get_fields_and_field_types()["data"] == "sequence<uint8>"
    # a copy: changing it does not change the class's answer
    fields = Image.get_fields_and_field_types()
    fields.clear()
    assert Image.get_fields_and_field_types()["encoding"] == "string"
