# rclpy's small utility modules: serialization, constants, type hashes, name validation,
# topic name expansion and hidden names (exception classes compared; posekit words the
# validation messages its own way, see docs/runtime.md).
import rclpy.constants
from geometry_msgs.msg import TransformStamped
from rclpy.clock_type import ClockType
from rclpy.duration import Infinite
from rclpy.expand_topic_name import expand_topic_name
from rclpy.logging import (
    LoggingSeverity,
    get_logger_effective_level,
    get_logger_level,
    get_logging_severity_from_string,
    set_logger_level,
)
from rclpy.node import HIDDEN_NODE_PREFIX
from rclpy.serialization import deserialize_message, serialize_message
from rclpy.topic_or_service_is_hidden import topic_or_service_is_hidden
from rclpy.type_hash import TypeHash
from rclpy.utilities import timeout_sec_to_nsec
from rclpy.validate_full_topic_name import validate_full_topic_name
from rclpy.validate_namespace import validate_namespace
from rclpy.validate_node_name import validate_node_name
from rclpy.validate_parameter_name import validate_parameter_name
from rclpy.validate_topic_name import validate_topic_name
from std_msgs.msg import String

show("S_TO_NS", lambda: rclpy.constants.S_TO_NS)
show("Infinite", lambda: (str(Infinite), repr(Infinite), Infinite.nanoseconds))
show("hidden node prefix", lambda: HIDDEN_NODE_PREFIX)
show("timeouts", lambda: [timeout_sec_to_nsec(t) for t in (None, -1, 0, 1.5, 2)])
for name in ("info", "WARN", "Unset", "fatal", "debug", "error", "warning", " info", "loud"):
    kind(f"severity {name!r}", lambda n=name: int(get_logging_severity_from_string(n)))
show("own level unset", lambda: (int(get_logger_level("small.a")),
                                 int(get_logger_effective_level("small.a"))))
set_logger_level("small", LoggingSeverity.WARN)
show("inherited level", lambda: (int(get_logger_level("small")), int(get_logger_level("small.a")),
                                 int(get_logger_effective_level("small.a"))))
show("clock types", lambda: [(t.name, int(t)) for t in ClockType])

t = TransformStamped()
t.header.frame_id, t.child_frame_id = "odom", "base_link"
t.header.stamp.sec, t.header.stamp.nanosec = 12, 34
t.transform.translation.x, t.transform.rotation.w = 1.5, 1.0
show("serialize String", lambda: serialize_message(String(data="hi")).hex())
# (rclpy leaves the alignment padding uninitialised: the bytes are compared decoded)
show("TransformStamped size", lambda: len(serialize_message(t)))
show("round trip", lambda: deserialize_message(serialize_message(t), TransformStamped) == t)
show("deserialize", lambda: deserialize_message(bytes.fromhex("0001000003000000686900"),
                                                String).data)
tf_bytes = bytes.fromhex(
    "000100000c00000022000000050000006f646f6d000000000a000000626173655f6c696e6b0000000000"
    "0000000000000000f83f0000000000000000000000000000000000000000000000000000000000000000"
    "0000000000000000000000000000f03f")
show("deserialize TransformStamped", lambda: (lambda m: (
    m.header.stamp.sec, m.header.stamp.nanosec, m.header.frame_id, m.child_frame_id,
    m.transform.translation.x, m.transform.rotation.w))(
        deserialize_message(tf_bytes, TransformStamped)))
show("returns bytes", lambda: type(serialize_message(String())).__name__)
kind("serialize a non-message", lambda: serialize_message("text"))
kind("deserialize into a non-type", lambda: deserialize_message(b"\x00\x01\x00\x00", "x"))

h = TypeHash(version=1, value=bytes(range(32)))
show("type hash str", lambda: str(h))
show("type hash fields", lambda: (h.version, bytes(h.value).hex()))
show("type hash equal", lambda: h == TypeHash(version=1, value=bytes(range(32))))

for name in ("chatter", "/robot/odom", "~/private", "{node}/x", "a b", "", "/a//b", "1abc",
             "/a/", "_hidden/x"):
    kind(f"topic {name!r}", lambda n=name: validate_topic_name(n))
    kind(f"service {name!r}", lambda n=name: validate_topic_name(n, is_service=True))
    kind(f"full {name!r}", lambda n=name: validate_full_topic_name(n))
for name in ("talker", "_hidden", "1st", "a-b", "", "with space"):
    kind(f"node {name!r}", lambda n=name: validate_node_name(n))
for name in ("gain", "wheels.count", "", "a b", "1x"):
    kind(f"parameter {name!r}", lambda n=name: validate_parameter_name(n))
for name in ("/", "/robot", "robot", "/robot/", "/a//b", "/1a", ""):
    kind(f"namespace {name!r}", lambda n=name: validate_namespace(n))

for name, node, ns in (("chatter", "talker", "/robot"), ("~/state", "talker", "/robot"),
                       ("/abs", "talker", "/robot"), ("{node}/x", "talker", "/"),
                       ("{ns}/y", "talker", "/robot"), ("~", "talker", "/")):
    show(f"expand {name!r} {node!r} {ns!r}", lambda a=(name, node, ns): expand_topic_name(*a))
kind("expand bad namespace", lambda: expand_topic_name("x", "talker", "robot"))
kind("expand bad node", lambda: expand_topic_name("x", "bad name", "/"))

for name in ("/a/b", "/_a/b", "/a/_b", "_x", "/a_b", "", "/a/b_"):
    show(f"hidden {name!r}", lambda n=name: topic_or_service_is_hidden(n))
