"""Message registry: names <-> classes, short names, errors."""

from __future__ import annotations

import pytest
from rosbags.typesys import Stores, get_typestore

from posekit.msgs import UnknownMessageTypeError, get_message_class, message_type_name
from posekit.msgs.geometry_msgs import TransformStamped
from posekit.msgs.registry import MESSAGE_CLASSES, normalize_type_name
from posekit.msgs.tf2_msgs import TFMessage


def test_lookup_both_ways() -> None:
    assert get_message_class("geometry_msgs/msg/TransformStamped") is TransformStamped
    assert get_message_class("tf2_msgs/TFMessage") is TFMessage
    assert message_type_name(TFMessage()) == "tf2_msgs/msg/TFMessage"
    assert message_type_name(TFMessage) == "tf2_msgs/msg/TFMessage"


def test_every_registered_name_is_a_jazzy_type() -> None:
    jazzy = get_typestore(Stores.ROS2_JAZZY)
    # rosbags' store has no service or action types (tests/msgs/test_services.py and
    # test_actions.py check those)
    assert {n for n in MESSAGE_CLASSES if n.split("/")[1] == "msg"} <= set(jazzy.fielddefs)
    for name, cls in MESSAGE_CLASSES.items():
        assert get_message_class(name) is cls
        assert cls.__module__ == f"posekit.msgs.{name.split('/')[0]}"


def test_rosbags_objects_have_type_names() -> None:
    jazzy = get_typestore(Stores.ROS2_JAZZY)
    msg = jazzy.types["tf2_msgs/msg/TFMessage"](transforms=[])
    assert message_type_name(msg) == "tf2_msgs/msg/TFMessage"


@pytest.mark.parametrize("bad", ["", "TFMessage", "a//b", "a/b/c/d", "pkg/foo/Type"])
def test_malformed_names(bad: str) -> None:
    with pytest.raises(UnknownMessageTypeError):
        normalize_type_name(bad)


def test_unknown_names_and_objects() -> None:
    with pytest.raises(UnknownMessageTypeError, match="no message class"):
        get_message_class("visualization_msgs/msg/Marker")  # a Jazzy type posekit lacks
    with pytest.raises(UnknownMessageTypeError, match="not a ROS message"):
        message_type_name(42)
