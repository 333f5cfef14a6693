"""Topic/node/namespace names: expansion, validation errors, remapping (rcl's rules)."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from posekit.msgs.std_msgs import String
from posekit.runtime.names import (
    InvalidNamespaceException,
    InvalidNodeNameException,
    InvalidTopicNameException,
    expand_topic_name,
    normalize_namespace,
    parse_remap_rules,
    resolve_topic_name,
    validate_node_name,
)
from posekit.runtime.node import Node

# Expected values from the ROS 2 design article "Topic and Service name mapping to DDS" /
# rcl's expand_topic_name tests (node "my_node", namespace "/my_ns").
EXPANSIONS = [
    ("ping", "/my_ns", "/my_ns/ping"),
    ("/ping", "/my_ns", "/ping"),
    ("~", "/my_ns", "/my_ns/my_node"),
    ("~/ping", "/my_ns", "/my_ns/my_node/ping"),
    ("{node}/ping", "/my_ns", "/my_ns/my_node/ping"),
    ("{ns}/ping", "/my_ns", "/my_ns/ping"),
    ("/{node}", "/my_ns", "/my_node"),
    ("ping", "/", "/ping"),
    ("~/ping", "/", "/my_node/ping"),
    ("a/b/c", "/x/y", "/x/y/a/b/c"),
]


@pytest.mark.parametrize(("name", "ns", "expected"), EXPANSIONS)
def test_expansion(name: str, ns: str, expected: str) -> None:
    assert expand_topic_name(name, "my_node", ns) == expected


@pytest.mark.parametrize(
    ("name", "index"),
    [("", 0), ("/", 0), ("foo/", 3), ("foo//bar", 3), ("1foo", 0), ("foo/1bar", 4),
     ("fo o", 2), ("~foo", 1), ("foo~", 3), ("{bad", 0), ("foo}", 3), ("a-b", 1)],
)
def test_invalid_topic_names_report_index(name: str, index: int) -> None:
    with pytest.raises(InvalidTopicNameException) as info:
        expand_topic_name(name, "n", "/")
    assert info.value.index == index
    assert repr(name) in str(info.value) or name in str(info.value)


@pytest.mark.parametrize("bad", ["", "1node", "my-node", "a/b", "a b"])
def test_invalid_node_names(bad: str) -> None:
    with pytest.raises(InvalidNodeNameException):
        validate_node_name(bad)


def test_namespaces() -> None:
    assert normalize_namespace("") == "/"
    assert normalize_namespace(None) == "/"
    assert normalize_namespace("robot1") == "/robot1"
    for bad in ["/a/", "/a//b", "/1a", "/a b"]:
        with pytest.raises(InvalidNamespaceException):
            normalize_namespace(bad)


def test_remapping_rules_match_on_expanded_names() -> None:
    rules = parse_remap_rules(["cmd_vel:=/robot/cmd_vel", "other:odom:=/nope", "~/dbg:=debug"])
    assert resolve_topic_name("cmd_vel", "ctl", "/", rules) == "/robot/cmd_vel"
    assert resolve_topic_name("/cmd_vel", "ctl", "/", rules) == "/robot/cmd_vel"
    assert resolve_topic_name("odom", "ctl", "/", rules) == "/odom"  # rule is for node 'other'
    assert resolve_topic_name("odom", "other", "/", rules) == "/nope"
    assert resolve_topic_name("~/dbg", "ctl", "/ns", rules) == "/ns/debug"
    with pytest.raises(ValueError, match="from:=to"):
        parse_remap_rules(["no_separator"])


def test_node_applies_namespace_remaps_and_validation(ctx) -> None:
    node = Node("talker", namespace="robot1", context=ctx,
                remappings={"chatter": "/global_chatter"})
    assert node.get_namespace() == "/robot1"
    assert node.get_fully_qualified_name() == "/robot1/talker"
    assert node.create_publisher(String, "chatter", 10).topic_name == "/global_chatter"
    assert node.create_publisher(String, "status", 10).topic_name == "/robot1/status"
    assert node.create_publisher(String, "~/debug", 10).topic_name == "/robot1/talker/debug"
    with pytest.raises(InvalidTopicNameException):
        node.create_publisher(String, "bad topic", 10)
    with pytest.raises(InvalidNodeNameException):
        Node("bad-name", context=ctx)


def test_special_remaps_rename_node(ctx) -> None:
    node = Node("orig", context=ctx, cli_args=["--ros-args", "-r", "__node:=renamed",
                                                 "-r", "__ns:=/team"])
    assert node.get_fully_qualified_name() == "/team/renamed"


token = st.from_regex(r"[A-Za-z_][A-Za-z0-9_]{0,6}", fullmatch=True)


@given(
    parts=st.lists(token, min_size=1, max_size=4),
    ns_parts=st.lists(token, max_size=3),
    node=token,
    kind=st.sampled_from(["relative", "absolute", "private"]),
)
def test_expansion_properties(parts, ns_parts, node, kind) -> None:
    namespace = "/" + "/".join(ns_parts)
    body = "/".join(parts)
    name = {"relative": body, "absolute": "/" + body, "private": "~/" + body}[kind]
    full = expand_topic_name(name, node, namespace)
    # Independent construction of the expected absolute name.
    prefix = {"relative": ns_parts, "absolute": [], "private": [*ns_parts, node]}[kind]
    assert full == "/" + "/".join([*prefix, *parts])
    assert expand_topic_name(full, "other", "/elsewhere") == full  # absolute is a fixed point
