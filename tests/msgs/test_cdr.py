"""CDR bytes against rosbags' own serializer (independent typestore), round trips,
docs/specs/rmw_zenoh.md's
worked TFMessage, and malformed input."""

from __future__ import annotations

import dataclasses
import random
from typing import Any

import numpy as np
import pytest
from rosbags.typesys import Stores, get_typestore

from _support.cdr_values import build_message, random_values
from posekit.msgs import CdrError, UnknownMessageTypeError, from_cdr, to_cdr
from posekit.msgs.builtin_interfaces import Time
from posekit.msgs.cdr import cdr_decoder
from posekit.msgs.geometry_msgs import (
    Quaternion,
    Transform,
    TransformStamped,
    Vector3,
)
from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.registry import MESSAGE_CLASSES
from posekit.msgs.sensor_msgs import CameraInfo, Image, JointState
from posekit.msgs.std_msgs import Header
from posekit.msgs.tf2_msgs import TFMessage

REF = get_typestore(Stores.ROS2_JAZZY)  # a separate store: rosbags' own classes

ISSUE_TYPES = [
    "builtin_interfaces/msg/Time",
    "builtin_interfaces/msg/Duration",
    "std_msgs/msg/Header",
    "std_msgs/msg/Bool",
    "std_msgs/msg/String",
    "std_msgs/msg/Float64",
    *(f"std_msgs/msg/{name}" for name in (
        "Byte", "Char", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64",
        "UInt64", "Float32", "ColorRGBA", "Empty", "MultiArrayDimension", "MultiArrayLayout",
        "ByteMultiArray", "Int8MultiArray", "UInt8MultiArray", "Int16MultiArray",
        "UInt16MultiArray", "Int32MultiArray", "UInt32MultiArray", "Int64MultiArray",
        "UInt64MultiArray", "Float32MultiArray", "Float64MultiArray")),
    "geometry_msgs/msg/Point",
    "geometry_msgs/msg/Quaternion",
    "geometry_msgs/msg/Vector3",
    "geometry_msgs/msg/Pose",
    "geometry_msgs/msg/PoseStamped",
    "geometry_msgs/msg/PointStamped",
    "geometry_msgs/msg/Vector3Stamped",
    "geometry_msgs/msg/Twist",
    "geometry_msgs/msg/TwistStamped",
    "geometry_msgs/msg/Transform",
    "geometry_msgs/msg/TransformStamped",
    "geometry_msgs/msg/PoseWithCovariance",
    "geometry_msgs/msg/TwistWithCovariance",
    "nav_msgs/msg/Odometry",
    "sensor_msgs/msg/Image",
    "sensor_msgs/msg/CameraInfo",
    "unique_identifier_msgs/msg/UUID",
    "action_msgs/msg/GoalInfo",
    "action_msgs/msg/GoalStatus",
    "action_msgs/msg/GoalStatusArray",
    "sensor_msgs/msg/Imu",
    "sensor_msgs/msg/JointState",
    "sensor_msgs/msg/LaserScan",
    "sensor_msgs/msg/PointCloud2",
    "sensor_msgs/msg/PointField",
    "tf2_msgs/msg/TFMessage",
    "rosgraph_msgs/msg/Clock",
    "rcl_interfaces/msg/ParameterValue",
    "rcl_interfaces/msg/Parameter",
    "rcl_interfaces/msg/ParameterType",
    "rcl_interfaces/msg/FloatingPointRange",
    "rcl_interfaces/msg/IntegerRange",
    "rcl_interfaces/msg/ParameterDescriptor",
    "rcl_interfaces/msg/SetParametersResult",
    "rcl_interfaces/msg/ListParametersResult",
    "rcl_interfaces/msg/ParameterEvent",
    "rcl_interfaces/msg/Log",
]

def _cases() -> list[tuple[str, int]]:
    return [(t, seed) for t in ISSUE_TYPES for seed in range(6)]


def _instances(typename: str, seed: int) -> tuple[Any, Any]:
    rng = random.Random(f"{typename}-{seed}")
    tree = random_values(rng, REF, typename, big=seed == 5)
    ours = build_message(tree, typename, dict(MESSAGE_CLASSES))
    ref = build_message(tree, typename, REF.types)
    return ours, ref


def _assert_same_fields(a: Any, b: Any) -> None:
    """Compare a posekit message with a rosbags one field by field (arrays by value)."""
    for f in dataclasses.fields(b):
        va, vb = getattr(a, f.name), getattr(b, f.name)
        if hasattr(vb, "__msgtype__"):
            _assert_same_fields(va, vb)
        elif isinstance(vb, np.ndarray):
            assert isinstance(va, np.ndarray)
            assert va.dtype == vb.dtype
            np.testing.assert_array_equal(va, vb)
        elif isinstance(vb, list) and vb and hasattr(vb[0], "__msgtype__"):
            assert len(va) == len(vb)
            for x, y in zip(va, vb, strict=True):
                _assert_same_fields(x, y)
        else:
            assert va == vb or (va != va and vb != vb), f.name  # NaN-tolerant


def test_every_issue_type_is_registered() -> None:
    assert set(ISSUE_TYPES) <= set(MESSAGE_CLASSES)
    for name, cls in MESSAGE_CLASSES.items():
        assert cls.__msgtype__ == name
        if "/srv/" in name or "/action/" in name:  # rosbags has no service or action
            continue  # types: see test_services.py and test_actions.py
        ros = [f for f, _ in REF.fielddefs[name][1]]
        assert [f.name for f in dataclasses.fields(cls)] == ros


@pytest.mark.parametrize(("typename", "seed"), _cases())
def test_bytes_equal_rosbags(typename: str, seed: int) -> None:
    ours, ref = _instances(typename, seed)
    expected = bytes(REF.serialize_cdr(ref, typename, little_endian=True))
    got = to_cdr(ours)
    assert isinstance(got, bytes)
    assert got == expected
    # posekit also serializes rosbags' objects (duck typing) to the same bytes
    assert to_cdr(ref) == expected
    # and decodes into posekit classes equal to what was sent and to rosbags' decoding
    back = from_cdr(got, type(ours))
    assert type(back) is type(ours)
    _assert_same_fields(back, REF.deserialize_cdr(expected, typename))
    assert to_cdr(back) == expected
    assert from_cdr(got, typename) == back


def test_default_instances_match_rosbags_defaults_bytes() -> None:
    for typename in ISSUE_TYPES:
        ours = MESSAGE_CLASSES[typename]()
        back = from_cdr(to_cdr(ours), typename)
        assert back == ours, typename


def test_spec_worked_tfmessage_bytes() -> None:
    # rmw_zenoh.md section 4: 1 transform, stamp 1.000000002, odom -> base_link, t=(1,2,3)
    expected = bytes.fromhex(
        "00010000010000000100000002000000"
        "050000006f646f6d000000000a000000"
        "626173655f6c696e6b00000000000000"
        "0000f03f000000000000004000000000"
        "00000840000000000000000000000000"
        "00000000000000000000000000000000"
        "0000f03f"
    )
    msg = TFMessage(
        transforms=[
            TransformStamped(
                header=Header(stamp=Time(sec=1, nanosec=2), frame_id="odom"),
                child_frame_id="base_link",
                transform=Transform(
                    translation=Vector3(x=1.0, y=2.0, z=3.0),
                    rotation=Quaternion(x=0.0, y=0.0, z=0.0, w=1.0),
                ),
            )
        ]
    )
    assert len(expected) == 100
    assert to_cdr(msg) == expected
    assert from_cdr(expected, TFMessage) == msg
    # a subscription's decoder: the type bound once, by class or by name
    assert cdr_decoder(TFMessage)(expected) == msg
    assert cdr_decoder("tf2_msgs/TFMessage")(bytearray(expected)) == msg


def test_empty_message_encodings() -> None:
    assert to_cdr(TFMessage()) == b"\x00\x01\x00\x00\x00\x00\x00\x00"
    assert from_cdr(b"\x00\x01\x00\x00\x00\x00\x00\x00", TFMessage) == TFMessage()


def test_big_endian_input_is_decoded() -> None:
    msg = Odometry(child_frame_id="base")
    msg.pose.pose.position.x = 1.25
    msg.twist.covariance = np.arange(36, dtype=np.float64)
    ref = REF.types["nav_msgs/msg/Odometry"]
    ref_msg = REF.deserialize_cdr(to_cdr(msg), "nav_msgs/msg/Odometry")
    assert isinstance(ref_msg, ref)
    be = bytes(REF.serialize_cdr(ref_msg, "nav_msgs/msg/Odometry", little_endian=False))
    assert be[:2] == b"\x00\x00"
    back = from_cdr(be, Odometry)
    assert back.pose.pose.position.x == 1.25
    np.testing.assert_array_equal(back.twist.covariance, np.arange(36))


def test_lists_and_bytes_are_accepted_without_mutating_the_message() -> None:
    odo = Odometry()
    odo.pose.covariance = [float(i) for i in range(36)]  # type: ignore[assignment]
    reference = Odometry()
    reference.pose.covariance = np.arange(36, dtype=np.float64)
    assert to_cdr(odo) == to_cdr(reference)
    assert isinstance(odo.pose.covariance, list)  # caller's object untouched

    pixels = bytes(range(12))
    img = Image(height=2, width=2, encoding="rgb8", step=6, data=pixels)  # type: ignore[arg-type]
    img_ref = Image(
        height=2, width=2, encoding="rgb8", step=6, data=np.arange(12, dtype=np.uint8)
    )
    assert to_cdr(img) == to_cdr(img_ref)
    assert to_cdr(img) == bytes(REF.serialize_cdr(img_ref, "sensor_msgs/msg/Image"))

    js = JointState(name=["a"], position=[1, 2])  # type: ignore[arg-type]  # ints -> float64
    js_ref = JointState(name=["a"], position=np.array([1.0, 2.0]))
    assert to_cdr(js) == to_cdr(js_ref)
    cam = CameraInfo(k=np.eye(3))  # 3x3 is flattened row-major
    assert from_cdr(to_cdr(cam), CameraInfo).k.tolist() == np.eye(3).ravel().tolist()


@pytest.mark.parametrize(
    ("msg", "reason"),
    [
        (Time(sec=2**31), "'sec': 2147483648 is out of int32"),
        (Time(sec=0, nanosec=-1), "'nanosec': -1 is out of uint32"),
        (Time(sec=1.5), "'sec': expected an integer"),  # type: ignore[arg-type]
        (Header(frame_id=None), "'frame_id': expected str"),  # type: ignore[arg-type]
        (Odometry(pose=None), "'pose': expected"),  # type: ignore[arg-type]
        (
            TFMessage([TransformStamped(), TransformStamped(child_frame_id=3)]),  # type: ignore[arg-type]
            r"'transforms\[1\]\.child_frame_id'",
        ),
    ],
)
def test_unserializable_fields_raise_cdr_error_naming_the_field(msg: Any, reason: str) -> None:
    with pytest.raises(CdrError, match=reason):
        to_cdr(msg)


def test_wrong_array_lengths_and_types_are_named() -> None:
    odo = Odometry()
    odo.pose.covariance = np.zeros(35)
    with pytest.raises(CdrError, match=r"covariance.*36"):
        to_cdr(odo)
    js = JointState(position=np.array([1.0 + 2j]))
    with pytest.raises(CdrError, match="position"):
        to_cdr(js)
    img = Image(data=np.zeros(4, dtype=np.float64))
    with pytest.raises(CdrError, match="data"):
        to_cdr(img)


def test_unknown_types() -> None:
    with pytest.raises(UnknownMessageTypeError):
        from_cdr(b"\x00\x01\x00\x00", "nope_msgs/msg/Nothing")
    with pytest.raises(UnknownMessageTypeError):
        to_cdr(object())
    with pytest.raises(UnknownMessageTypeError):
        from_cdr(b"\x00\x01\x00\x00", "not a type")
    with pytest.raises(UnknownMessageTypeError):  # at once, not at the first message
        cdr_decoder("nope_msgs/msg/Nothing")


def test_other_jazzy_types_fall_back_to_rosbags_classes() -> None:
    data = bytes(REF.serialize_cdr(REF.types["std_msgs/msg/Int32"](data=-7), "std_msgs/msg/Int32"))
    msg = from_cdr(data, "std_msgs/msg/Int32")
    assert msg.data == -7
    assert to_cdr(msg) == data


def test_decoded_arrays_are_views_of_the_input() -> None:
    img = Image(height=720, width=1280, encoding="rgb8", step=3840)
    img.data = np.random.default_rng(0).integers(0, 255, 720 * 3840, dtype=np.uint8)
    data = to_cdr(img)
    assert data == bytes(REF.serialize_cdr(img, "sensor_msgs/msg/Image", little_endian=True))
    back = from_cdr(data, Image)
    assert np.shares_memory(back.data, np.frombuffer(data, dtype=np.uint8))
    np.testing.assert_array_equal(back.data, img.data)


def _valid_samples() -> list[tuple[str, bytes]]:
    out = []
    for typename in ISSUE_TYPES:
        for seed in (1, 2):
            ours, _ = _instances(typename, seed)
            out.append((typename, to_cdr(ours)))
    return out


def test_every_truncation_raises_cdr_error() -> None:
    for typename, data in _valid_samples():
        lengths = range(len(data)) if len(data) < 2000 else range(0, len(data), 97)
        for n in lengths:
            with pytest.raises(CdrError):
                from_cdr(data[:n], typename)


def test_trailing_garbage_and_bad_headers_raise() -> None:
    data = to_cdr(TFMessage())
    decode = cdr_decoder(TFMessage)
    for long in (data + b"\x00" * 8, bytearray(data + b"\x00" * 8),
                 memoryview(data + b"\x00" * 8)):
        with pytest.raises(CdrError, match="8 unexpected trailing bytes"):
            from_cdr(long, TFMessage)
        with pytest.raises(CdrError, match="8 unexpected trailing bytes"):
            decode(long)
    assert decode(data + b"\x00" * 3) == TFMessage()  # final padding is legal
    for header in (b"\x00\x02\x00\x00", b"\x01\x01\x00\x00", b"\xff\xff\x00\x00"):
        with pytest.raises(CdrError, match="encapsulation"):
            from_cdr(header + data[4:], TFMessage)
    with pytest.raises(CdrError):
        from_cdr(12345, TFMessage)  # type: ignore[arg-type]


def test_random_and_mutated_bytes_decode_or_raise_cdr_error() -> None:
    rng = random.Random(1234)
    samples = _valid_samples()
    decoded = rejected = 0
    for i in range(4000):
        typename, data = samples[i % len(samples)]
        if i % 4 == 0:
            blob = b"\x00\x01\x00\x00" + rng.randbytes(rng.randint(0, 300))
        else:
            buf = bytearray(data[:4000])
            for _ in range(rng.randint(1, 6)):
                buf[rng.randrange(len(buf))] = rng.randrange(256)
            blob = bytes(buf)
        try:
            msg = from_cdr(blob, typename)
        except CdrError:
            rejected += 1
        else:
            assert type(msg) is MESSAGE_CLASSES[typename]
            decoded += 1
    assert decoded > 0
    assert rejected > 0


def test_serializable_type_names_class_and_rejects_unknown() -> None:
    from posekit.msgs.cdr import serializable_type
    from posekit.msgs.tf2_msgs import TFMessage

    assert serializable_type("tf2_msgs/TFMessage") == ("tf2_msgs/msg/TFMessage", TFMessage)
    with pytest.raises(LookupError):
        serializable_type("my_pkg/msg/NotAType")
