"""ROS 2's DDS mapping as posekit writes it (names, USER_DATA, discovery configuration, the
``ros_discovery_info`` payload).

Oracles: the rmw implementations' documented behaviour (rmw_cyclonedds's discovery settings
per ``ROS_AUTOMATIC_DISCOVERY_RANGE``, Fast DDS's NUL-terminated USER_DATA), Cyclone DDS
itself (it must accept every configuration), and rosbags, which decodes the
``ParticipantEntitiesInfo`` payload with its own Jazzy definitions. Services: the names,
id strings and header layout of rmw_cyclonedds's source, written out here by hand.
"""

from __future__ import annotations

import struct
import subprocess
import sys

import numpy as np
import pytest

from posekit.transport.dds_wire import (
    REQUEST_HEADER_SIZE,
    DiscoveryOptions,
    DiscoveryRange,
    NodeEntities,
    ParticipantEntities,
    client_service_id,
    cyclone_config,
    dds_topic_name,
    decode_participant_entities,
    decode_service_payload,
    encode_participant_entities,
    encode_service_payload,
    format_client_service_id,
    parse_user_data,
    ros_service_name,
    ros_service_type,
    ros_topic_name,
    service_topic_names,
)


def test_topic_names_carry_the_rt_prefix() -> None:
    assert dds_topic_name("/tf") == "rt/tf"
    assert dds_topic_name("/robot1/odometry/filtered") == "rt/robot1/odometry/filtered"
    assert ros_topic_name("rt/robot1/odom") == "/robot1/odom"
    assert ros_topic_name("ros_discovery_info") is None
    assert ros_topic_name("rq/add_two_intsRequest") is None
    with pytest.raises(ValueError, match="fully qualified"):
        dds_topic_name("tf")


def test_user_data_parsing_tolerates_fast_dds_nul_and_junk() -> None:
    assert parse_user_data(b"enclave=/;\x00") == {"enclave": "/"}
    assert parse_user_data(b"typehash=RIHS01_ab;") == {"typehash": "RIHS01_ab"}
    assert parse_user_data(b"noequals;k=v=w;\xff=1;") == {"k": "v=w", "\ufffd": "1"}
    assert parse_user_data(b"") == {}


def _options(**env: str) -> DiscoveryOptions:
    return DiscoveryOptions.from_env(env)


def test_localhost_is_the_default_and_stays_on_loopback_without_multicast() -> None:
    options = _options()
    assert options.range is DiscoveryRange.LOCALHOST
    assert options.domain_id == 0
    xml = cyclone_config(options)
    assert '<NetworkInterface address="127.0.0.1"/>' in xml
    assert "<AllowMulticast>false</AllowMulticast>" in xml
    assert '<Peer address="localhost"/>' in xml
    assert "<MaxAutoParticipantIndex>32</MaxAutoParticipantIndex>" in xml


def test_subnet_allows_multicast_and_adds_static_peers() -> None:
    options = _options(ROS_AUTOMATIC_DISCOVERY_RANGE="subnet",
                       ROS_STATIC_PEERS="192.168.1.20; robot.local;;", ROS_DOMAIN_ID="7")
    assert options.static_peers == ("192.168.1.20", "robot.local")
    assert options.domain_id == 7
    xml = cyclone_config(options)
    assert "AllowMulticast" not in xml
    assert "NetworkInterface" not in xml
    assert '<Peer address="192.168.1.20"/><Peer address="robot.local"/>' in xml
    assert "localhost" not in xml


def test_localhost_with_static_peers_and_off_and_system_default() -> None:
    xml = cyclone_config(_options(ROS_STATIC_PEERS="10.0.0.2"))
    assert '<Peer address="localhost"/><Peer address="10.0.0.2"/>' in xml
    assert "<AllowMulticast>false</AllowMulticast>" in xml
    assert "NetworkInterface" not in xml  # the peer must be reachable
    off = cyclone_config(_options(ROS_AUTOMATIC_DISCOVERY_RANGE="OFF", ROS_STATIC_PEERS="x"))
    assert "<ParticipantIndex>none</ParticipantIndex>" in off
    assert "<Tag>ros_discovery_off_" in off
    assert "Peer" not in off
    assert "<AllowMulticast>false</AllowMulticast>" in off
    assert cyclone_config(_options(ROS_AUTOMATIC_DISCOVERY_RANGE="SYSTEM_DEFAULT")) == ""
    extra = "<CycloneDDS><Domain><Tracing><Verbosity>config</Verbosity></Tracing></Domain>" \
            "</CycloneDDS>"
    assert cyclone_config(_options(CYCLONEDDS_URI=extra)).endswith("," + extra)


@pytest.mark.parametrize(("env", "message"), [
    ({"ROS_DOMAIN_ID": "abc"}, "not an integer"),
    ({"ROS_DOMAIN_ID": "300"}, "outside 0..232"),
    ({"ROS_AUTOMATIC_DISCOVERY_RANGE": "GALAXY"}, "expected one of"),
])
def test_bad_environment_is_a_named_error(env: dict[str, str], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        DiscoveryOptions.from_env(env)


@pytest.mark.slow
def test_cyclone_accepts_every_configuration() -> None:
    ranges = ["LOCALHOST", "SUBNET", "OFF", "SYSTEM_DEFAULT"]
    script = (
        "import sys\n"
        "from cyclonedds.domain import Domain, DomainParticipant\n"
        "from posekit.transport.dds_wire import DiscoveryOptions, cyclone_config\n"
        "for i, rng in enumerate(sys.argv[1:]):\n"
        "    env = {'ROS_AUTOMATIC_DISCOVERY_RANGE': rng, 'ROS_STATIC_PEERS': '127.0.0.1'}\n"
        "    options = DiscoveryOptions.from_env(env)\n"
        "    domain = Domain(200 + i, cyclone_config(options))\n"
        "    DomainParticipant(200 + i)\n"
        "    print(rng, 'ok')\n"
    )
    result = subprocess.run([sys.executable, "-c", script, *ranges], capture_output=True,
                            text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    assert result.stdout.split() == [w for r in ranges for w in (r, "ok")]


def test_participant_entities_payload_decodes_with_rosbags() -> None:
    from rosbags.typesys import Stores, get_typestore

    info = ParticipantEntities(bytes(range(16)), [
        NodeEntities("/", "talker", [bytes([1] * 16)], [bytes([2] * 16), bytes([3] * 16)]),
        NodeEntities("/robot", "ekf_node"),
    ])
    data = encode_participant_entities(info)
    assert data[:4] == b"\x00\x01\x00\x00"
    msg = get_typestore(Stores.ROS2_JAZZY).deserialize_cdr(
        data, "rmw_dds_common/msg/ParticipantEntitiesInfo")
    assert bytes(msg.gid.data) == bytes(range(16))
    assert [(n.node_namespace, n.node_name) for n in msg.node_entities_info_seq] == [
        ("/", "talker"), ("/robot", "ekf_node")]
    first = msg.node_entities_info_seq[0]
    assert [bytes(g.data) for g in first.reader_gid_seq] == [bytes([1] * 16)]
    assert [bytes(g.data) for g in first.writer_gid_seq] == [bytes([2] * 16), bytes([3] * 16)]
    assert decode_participant_entities(data) == info
    assert np.array_equal(np.frombuffer(data[4:20], dtype=np.uint8), np.arange(16))


def test_service_names_and_types_as_rmw_cyclonedds_mangles_them() -> None:
    assert service_topic_names("/robot/flip") == ("rq/robot/flipRequest", "rr/robot/flipReply")
    assert ros_service_name("rq/robot/flipRequest") == ("/robot/flip", True)
    assert ros_service_name("rr/robot/flipReply") == ("/robot/flip", False)
    for not_a_service in ("rt/robot/flip", "rq/flipReply", "rr/flipRequest", "rq/Request",
                          "ros_discovery_info"):
        assert ros_service_name(not_a_service) is None, not_a_service
    assert ros_service_type("std_srvs::srv::dds_::SetBool_Request_") == "std_srvs/srv/SetBool"
    assert ros_service_type("rcl_interfaces::srv::dds_::GetParameters_Response_") == \
        "rcl_interfaces/srv/GetParameters"
    assert ros_service_type("posekit_interfaces::action::dds_::NavigateToPose_SendGoal_Request_") \
        == "posekit_interfaces/action/NavigateToPose_SendGoal"
    assert ros_service_type("std_msgs::msg::dds_::String_") is None
    assert ros_service_type("not a type") is None
    with pytest.raises(ValueError, match="fully qualified"):
        service_topic_names("flip")


def test_client_service_ids_are_the_participant_prefix_and_a_counter() -> None:
    participant = bytes(range(1, 17))
    csid = client_service_id(participant, 0x0102)
    assert csid == bytes(range(1, 13)) + b"\x00\x00\x01\x02"
    # rmw_cyclonedds prints the first byte with two digits, the others without padding
    assert format_client_service_id(csid) == "01.2.3.4.5.6.7.8.9.a.b.c.0.0.1.2"


def test_service_payload_header_sits_between_encapsulation_and_body() -> None:
    body = b"\x00\x01\x00\x00" + b"\x01\x00\x00\x00" + struct.pack("<d", 2.5)
    payload = encode_service_payload(body, 0xFEDCBA9876543210, 7)
    assert len(payload) == len(body) + REQUEST_HEADER_SIZE
    assert payload == (b"\x00\x01\x00\x00" + bytes.fromhex("1032547698badcfe")
                       + (7).to_bytes(8, "little") + body[4:])
    assert decode_service_payload(payload) == (0xFEDCBA9876543210, 7, body)
    big = b"\x00\x00\x00\x00\x01"  # big-endian CDR: the header follows its byte order
    encoded = encode_service_payload(big, 1, -2)
    assert encoded[4:20] == (1).to_bytes(8, "big") + (-2).to_bytes(8, "big", signed=True)
    assert decode_service_payload(encoded) == (1, -2, big)
    with pytest.raises(ValueError, match="shorter than"):
        decode_service_payload(b"\x00\x01\x00\x00" + bytes(15))
    with pytest.raises(ValueError, match="encapsulation"):
        decode_service_payload(b"\x00\x07\x00\x00" + bytes(17))
