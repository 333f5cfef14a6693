"""rmw_zenoh wire format against the worked examples of docs/specs/rmw_zenoh.md and against
zenoh-ext's own serializer."""

from __future__ import annotations

import contextlib
import random
import struct

import pytest
import zenoh.ext as zext

from posekit.transport.zenoh_wire import (
    Attachment,
    EntityKind,
    GraphCache,
    WireFormatError,
    WireQoS,
    data_key,
    dds_type_name,
    decode_attachment,
    encode_attachment,
    encode_attachment_legacy,
    endpoint_token,
    entity_gid,
    node_token,
    parse_token,
    qos_from_keyexpr,
    qos_to_keyexpr,
    ros_type_name,
    type_hash,
)

ZID = "1234567890abcdef1234567890abcdef"
TF_HASH = "RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087"

# rmw_zenoh.md section 7 (computed there independently of this code)
SPEC_HASHES = {
    "tf2_msgs/msg/TFMessage": TF_HASH,
    "geometry_msgs/msg/TransformStamped": (
        "RIHS01_0a241f87d04668d94099cbb5ba11691d5ad32c2f29682e4eb5653424bd275206"
    ),
    "geometry_msgs/msg/TwistStamped": (
        "RIHS01_5f0fcd4f81d5d06ad9b4c4c63e3ea51b82d6ae4d0558f1d475229b1121db6f64"
    ),
    "nav_msgs/msg/Odometry": (
        "RIHS01_3cc97dc7fb7502f8714462c526d369e35b603cfc34d946e3f2eda2766dfec6e0"
    ),
    "sensor_msgs/msg/Image": (
        "RIHS01_d31d41a9a4c4bc8eae9be757b0beed306564f7526c88ea6a4588fb9582527d47"
    ),
    "sensor_msgs/msg/CameraInfo": (
        "RIHS01_b3dfd68ff46c9d56c80fd3bd4ed22c7a4ddce8c8348f2f59c299e73118e7e275"
    ),
    "sensor_msgs/msg/Imu": (
        "RIHS01_7d9a00ff131080897a5ec7e26e315954b8eae3353c3f995c55faf71574000b5b"
    ),
    "std_msgs/msg/String": (
        "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"
    ),
}

TF_PUB_TOKEN = (
    f"@ros2_lv/0/{ZID}/0/1/MP/%/%/zbridge/%tf/tf2_msgs::msg::dds_::TFMessage_/{TF_HASH}/"
    "::,100:,:,:,,"
)


@pytest.mark.parametrize(("ros_type", "expected"), sorted(SPEC_HASHES.items()))
def test_type_hashes_match_spec(ros_type: str, expected: str) -> None:
    assert type_hash(ros_type) == expected


def test_data_keys_match_spec() -> None:
    assert data_key(0, "/tf", "tf2_msgs/msg/TFMessage") == (
        f"0/tf/tf2_msgs::msg::dds_::TFMessage_/{TF_HASH}"
    )
    assert data_key(0, "/tf_static", "tf2_msgs/msg/TFMessage") == (
        f"0/tf_static/tf2_msgs::msg::dds_::TFMessage_/{TF_HASH}"
    )
    assert data_key(0, "/cmd_vel", "geometry_msgs/msg/TwistStamped") == (
        "0/cmd_vel/geometry_msgs::msg::dds_::TwistStamped_/"
        "RIHS01_5f0fcd4f81d5d06ad9b4c4c63e3ea51b82d6ae4d0558f1d475229b1121db6f64"
    )
    assert data_key(0, "/robot1/odom", "nav_msgs/msg/Odometry") == (
        "0/robot1/odom/nav_msgs::msg::dds_::Odometry_/"
        "RIHS01_3cc97dc7fb7502f8714462c526d369e35b603cfc34d946e3f2eda2766dfec6e0"
    )
    assert data_key(7, "/tf/", "tf2_msgs/msg/TFMessage").startswith("7/tf/tf2_msgs::")


@pytest.mark.parametrize("topic", ["", "/", "/a//b", "/a/*", "/x/**", "/a$b"])
def test_bad_topics_rejected(topic: str) -> None:
    with pytest.raises(WireFormatError):
        data_key(0, topic, "tf2_msgs/msg/TFMessage")


def test_type_name_mangling() -> None:
    assert dds_type_name("tf2_msgs/msg/TFMessage") == "tf2_msgs::msg::dds_::TFMessage_"
    assert dds_type_name("std_srvs/srv/Empty") == "std_srvs::srv::dds_::Empty_"
    assert ros_type_name("nav_msgs::msg::dds_::Odometry_") == "nav_msgs/msg/Odometry"
    for bad in ("nav_msgs::msg::Odometry_", "a::b::dds_::C", "::msg::dds_::X_", "x"):
        with pytest.raises(WireFormatError):
            ros_type_name(bad)


def test_tokens_match_spec() -> None:
    assert node_token(0, ZID, 0, "/", "zbridge") == f"@ros2_lv/0/{ZID}/0/0/NN/%/%/zbridge"
    assert (
        endpoint_token(
            0,
            ZID,
            0,
            1,
            EntityKind.PUBLISHER,
            "/",
            "zbridge",
            "/tf",
            "tf2_msgs/msg/TFMessage",
            WireQoS(depth=100),
        )
        == TF_PUB_TOKEN
    )
    static_qos = WireQoS(durability=1, depth=100)
    assert endpoint_token(
        0,
        ZID,
        0,
        2,
        EntityKind.SUBSCRIPTION,
        "/",
        "zbridge",
        "/tf_static",
        "tf2_msgs/msg/TFMessage",
        static_qos,
    ) == (
        f"@ros2_lv/0/{ZID}/0/2/MS/%/%/zbridge/%tf_static/tf2_msgs::msg::dds_::TFMessage_/"
        f"{TF_HASH}/:1:,100:,:,:,,"
    )
    ns = node_token(3, ZID, 4, "/robot1", "driver")
    assert ns == f"@ros2_lv/3/{ZID}/4/4/NN/%/%robot1/driver"


@pytest.mark.parametrize(
    ("qos", "chunk"),
    [
        (WireQoS(depth=10), "::,10:,:,:,,"),
        (WireQoS(depth=100), "::,100:,:,:,,"),
        (WireQoS(durability=1, depth=1), ":1:,1:,:,:,,"),
        (WireQoS(reliability=2, depth=5), "2::,5:,:,:,,"),
        (WireQoS(), "::,:,:,:,,"),
    ],
)
def test_qos_chunks_match_spec_table(qos: WireQoS, chunk: str) -> None:
    assert qos_to_keyexpr(qos) == chunk
    assert qos_from_keyexpr(chunk) == qos


def test_explicit_qos_and_non_default_durations() -> None:
    assert qos_to_keyexpr(WireQoS(depth=100), explicit=True) == "1:2:1,100:,:,:,,"
    static = qos_from_keyexpr("1:1:1,1:,:,:,,")
    assert static.transient_local
    assert static.reliable
    assert static.depth == 1
    q = WireQoS(deadline=(1, 500), lifespan=(0, 7), liveliness=3, liveliness_lease=(2, 0))
    chunk = qos_to_keyexpr(q)
    assert chunk == "::,:1,500:0,7:3,2,0"
    assert qos_from_keyexpr(chunk) == q


@pytest.mark.parametrize(
    "chunk", ["", "::,10:,:,:", "::10:,:,:,,", "x::,10:,:,:,,", "::,10:,:,:,", "::,1,2:,:,:,,"]
)
def test_malformed_qos_chunks(chunk: str) -> None:
    with pytest.raises(WireFormatError):
        qos_from_keyexpr(chunk)


def test_gid_and_compact_attachment_match_spec() -> None:
    gid = entity_gid(TF_PUB_TOKEN)
    assert gid.hex() == "1af5ebd06f1e0476ce4b11129c796641"
    att = encode_attachment(1, 1700000000123456789, gid)
    expected = bytes.fromhex("010000000000000015cd853dfe9c9717101af5ebd06f1e0476ce4b11129c796641")
    assert att == expected
    # zenoh-ext's serializer (what rmw_zenoh's C++ side uses) gives the same bytes
    ref = zext.z_serialize(
        (zext.Int64(1), zext.Int64(1700000000123456789), [zext.UInt8(b) for b in gid])
    )
    assert ref.to_bytes() == expected
    assert decode_attachment(att) == Attachment(1, 1700000000123456789, gid)
    assert decode_attachment(att + b"trailing") == Attachment(1, 1700000000123456789, gid)


def test_compact_attachment_same_from_every_input_type() -> None:
    """The exact 33-byte ``bytes`` form (decoded on a shortcut) gives what the general
    decoder gives for the same bytes as a bytearray or memoryview, as a named tuple with
    ``bytes`` fields; 33 bytes that begin with the legacy label stay a legacy error."""
    gid = bytes(range(100, 116))
    att = encode_attachment(2**40 + 7, -123, gid)
    fast = decode_attachment(att)
    assert type(fast) is Attachment
    assert type(fast.gid) is bytes
    assert (fast.sequence_number, fast.source_timestamp, fast.gid, fast.legacy) == (
        2**40 + 7, -123, gid, False)
    for other in (bytearray(att), memoryview(att)):
        slow = decode_attachment(other)  # type: ignore[arg-type]
        assert slow == fast
        assert type(slow.gid) is bytes
    legacy_label = encode_attachment_legacy(1, 2, gid)[:16]
    mimic = legacy_label + b"\x10" + gid
    assert len(mimic) == 33
    with pytest.raises(WireFormatError, match="legacy"):
        decode_attachment(mimic)


def test_legacy_attachment_matches_zenoh_ext() -> None:
    gid = bytes(range(16))
    att = encode_attachment_legacy(42, -5, gid)
    ref = zext.z_serialize(
        ("sequence_number", zext.Int64(42), "source_timestamp", zext.Int64(-5), "source_gid", gid)
    )
    assert att == ref.to_bytes()
    assert len(att) == 77
    assert decode_attachment(att) == Attachment(42, -5, gid, legacy=True)


def test_bad_attachments() -> None:
    gid = bytes(16)
    good = encode_attachment(5, 6, gid)
    with pytest.raises(WireFormatError, match="33"):
        decode_attachment(good[:32])
    with pytest.raises(WireFormatError, match="0x10"):
        decode_attachment(good[:16] + b"\x0f" + good[17:])
    legacy = encode_attachment_legacy(1, 2, gid)
    with pytest.raises(WireFormatError, match="legacy"):
        decode_attachment(legacy[:60])
    with pytest.raises(WireFormatError, match="labels"):
        decode_attachment(legacy.replace(b"source_gid", b"source_xid"))
    with pytest.raises(WireFormatError):
        encode_attachment(1, 2, b"short")


def test_parse_tokens_announced_by_ros2_nodes() -> None:
    # the shapes rmw_zenoh_cpp announces (design.md: listener node 0/0/NN, subscription 0/10/MS)
    ros_zid = "a1b2c3d4e5f60718293a4b5c6d7e8f90"
    string_hash = SPEC_HASHES["std_msgs/msg/String"]
    node = f"@ros2_lv/0/{ros_zid}/0/0/NN/%/%/listener"
    sub = (
        f"@ros2_lv/0/{ros_zid}/0/10/MS/%/%/listener/%chatter/std_msgs::msg::dds_::String_/"
        f"{string_hash}/::,10:,:,:,,"
    )
    ns_pub = (
        f"@ros2_lv/0/{ros_zid}/1/3/MP/%/%robot1/odometry/%robot1%odom/"
        "nav_msgs::msg::dds_::Odometry_/"
        "RIHS01_3cc97dc7fb7502f8714462c526d369e35b603cfc34d946e3f2eda2766dfec6e0/2::,5:,:,:,,"
    )
    info = parse_token(sub)
    assert info.kind is EntityKind.SUBSCRIPTION
    assert (info.node_id, info.entity_id) == (0, 10)
    assert info.topic == "/chatter"
    assert info.ros_type == "std_msgs/msg/String"
    assert info.type_hash == string_hash
    assert info.qos == WireQoS(depth=10)
    assert info.data_key == f"0/chatter/std_msgs::msg::dds_::String_/{string_hash}"
    pub = parse_token(ns_pub)
    assert pub.node_fqn == "/robot1/odometry"
    assert pub.topic == "/robot1/odom"
    assert pub.qos is not None
    assert not pub.qos.reliable

    graph = GraphCache()
    for token in (node, sub, ns_pub, f"@ros2_lv/0/{ros_zid}/1/1/NN/%/%robot1/odometry"):
        assert graph.add(token) is not None
    assert graph.add("@ros2_lv/0/zz/0/0/XX/%/%/bad") is None
    assert graph.rejected == 1
    assert graph.node_names() == ["/listener", "/robot1/odometry"]
    assert graph.topic_names_and_types() == [
        ("/chatter", ["std_msgs/msg/String"]),
        ("/robot1/odom", ["nav_msgs/msg/Odometry"]),
    ]
    assert [t.node_name for t in graph.endpoints("/chatter", EntityKind.SUBSCRIPTION)] == [
        "listener"
    ]
    assert graph.endpoints("/chatter", EntityKind.PUBLISHER) == []
    graph.remove(sub)
    assert graph.topic_names_and_types() == [("/robot1/odom", ["nav_msgs/msg/Odometry"])]


@pytest.mark.parametrize(
    "token",
    [
        "@ros2_lv/0/zid/0/0/NN/%/%",  # too short
        "@ros2_lv/0/zid/0/0/NN/%/%/n/extra",  # node token with 10 chunks
        "@ros2_lv/x/zid/0/0/NN/%/%/n",  # non-numeric domain
        "@ros2_lv/0/zid/0/0/NN/%//n",  # empty chunk
        "@other/0/zid/0/0/NN/%/%/n",
        f"@ros2_lv/0/zid/0/1/MP/%/%/n/%tf/bad_type/{TF_HASH}/::,1:,:,:,,",
        f"@ros2_lv/0/zid/0/1/MP/%/%/n/%tf/tf2_msgs::msg::dds_::TFMessage_/{TF_HASH}/junk",
    ],
)
def test_malformed_tokens(token: str) -> None:
    with pytest.raises(WireFormatError):
        parse_token(token)


def test_fuzzed_parsers_only_raise_wire_format_error() -> None:
    rng = random.Random(99)
    alphabet = "@ros2_lv/0123456789%:,NMPS-abc"
    base_att = encode_attachment(3, 4, bytes(16))
    for _ in range(3000):
        text = "".join(rng.choice(alphabet) for _ in range(rng.randint(0, 80)))
        mutated = list(TF_PUB_TOKEN)
        for _ in range(rng.randint(1, 4)):
            mutated[rng.randrange(len(mutated))] = rng.choice(alphabet)
        for candidate in (text, "".join(mutated)):
            with contextlib.suppress(WireFormatError):
                parse_token(candidate)
        blob = bytearray(base_att[: rng.randint(0, 40)])
        if blob:
            blob[rng.randrange(len(blob))] = rng.randrange(256)
        try:
            att = decode_attachment(bytes(blob))
        except WireFormatError:
            continue
        assert len(att.gid) == 16
        assert att.sequence_number == struct.unpack_from("<q", blob)[0]
