"""posekit.msgs.point_cloud2: clouds as numpy structured arrays.

Oracles: byte layouts written here by hand with ``struct`` (fields, padding, padded rows, a
big-endian cloud, a multi-element field), and rosbags' CDR deserialization of the clouds
``create_cloud`` builds.
"""

from __future__ import annotations

import math
import struct

import numpy as np
import pytest

from posekit.msgs.cdr import to_cdr
from posekit.msgs.point_cloud2 import (
    PointCloudError,
    create_cloud,
    dtype_from_fields,
    read_points,
    xyz_fields,
)
from posekit.msgs.sensor_msgs import PointCloud2, PointField
from posekit.msgs.std_msgs import Header

F32, U8, U16, F64 = PointField.FLOAT32, PointField.UINT8, PointField.UINT16, PointField.FLOAT64


def _field(name: str, offset: int, datatype: int, count: int = 1) -> PointField:
    return PointField(name=name, offset=offset, datatype=datatype, count=count)


def test_read_points_of_hand_packed_bytes_with_padding_and_padded_rows() -> None:
    # 2 rows x 2 points; a point: x f32 @0, ring u16 @4, 2 pad, v f64 @8 (16 bytes);
    # each row padded with 8 bytes.
    rows = []
    values = [[(1.0, 7, 2.5), (math.nan, 8, -1.0)], [(3.0, 9, 0.25), (4.0, 10, 1e9)]]
    for row in values:
        raw = b"".join(struct.pack("<fHxxd", x, ring, v) for x, ring, v in row)
        rows.append(raw + b"\xee" * 8)
    msg = PointCloud2(header=Header(frame_id="f"), height=2, width=2,
                      fields=[_field("x", 0, F32), _field("ring", 4, U16), _field("v", 8, F64)],
                      point_step=16, row_step=40, data=np.frombuffer(b"".join(rows), np.uint8))
    pts = read_points(msg)
    assert pts.shape == (4,)
    flat = [p for row in values for p in row]
    np.testing.assert_array_equal(pts["x"], np.array([p[0] for p in flat], np.float32))
    assert pts["ring"].tolist() == [p[1] for p in flat]
    assert pts["v"].tolist() == [p[2] for p in flat]
    kept = read_points(msg, ["v", "x"], skip_nans=True)
    assert kept.dtype.names == ("v", "x")
    assert kept["v"].tolist() == [2.5, 0.25, 1e9]


def test_big_endian_and_multi_element_fields() -> None:
    raw = struct.pack(">f3B", 1.5, 1, 2, 3) + struct.pack(">f3B", -2.0, 4, 5, 6)
    msg = PointCloud2(height=1, width=2, fields=[_field("x", 0, F32), _field("c", 4, U8, 3)],
                      is_bigendian=True, point_step=7, row_step=14,
                      data=np.frombuffer(raw, np.uint8))
    pts = read_points(msg)
    assert pts["x"].tolist() == [1.5, -2.0]
    assert pts["c"].tolist() == [[1, 2, 3], [4, 5, 6]]


def test_create_cloud_round_trips_through_rosbags() -> None:
    from rosbags.typesys import Stores, get_typestore

    xyz = np.arange(12, dtype=np.float32).reshape(4, 3)
    msg = create_cloud(Header(frame_id="laser"), xyz)
    assert (msg.height, msg.width, msg.point_step, msg.row_step, msg.is_dense) == (
        1, 4, 12, 48, True)
    raw = get_typestore(Stores.ROS2_JAZZY).deserialize_cdr(to_cdr(msg),
                                                           "sensor_msgs/msg/PointCloud2")
    assert [(f.name, f.offset, f.datatype, f.count) for f in raw.fields] == [
        ("x", 0, F32, 1), ("y", 4, F32, 1), ("z", 8, F32, 1)]
    assert np.frombuffer(bytes(raw.data), "<f4").reshape(4, 3).tolist() == xyz.tolist()
    organised = np.zeros((2, 3), dtype=dtype_from_fields(xyz_fields(rgb=True), 32))
    organised["x"][1, 2] = np.nan
    cloud = create_cloud(Header(), organised)
    assert (cloud.height, cloud.width, cloud.point_step, cloud.is_dense) == (2, 3, 32, False)


def test_inconsistent_layouts_are_named() -> None:
    with pytest.raises(PointCloudError, match="does not fit"):
        dtype_from_fields([_field("x", 10, F32)], 12)
    with pytest.raises(PointCloudError, match="unknown PointField datatype"):
        dtype_from_fields([_field("x", 0, 99)], 12)
    with pytest.raises(PointCloudError, match="twice"):
        dtype_from_fields([_field("x", 0, F32), _field("x", 4, F32)], 12)
    msg = create_cloud(Header(), np.zeros((3, 3), np.float32))
    msg.data = msg.data[:-1]
    with pytest.raises(PointCloudError, match="bytes"):
        read_points(msg)
    msg = create_cloud(Header(), np.zeros((3, 3), np.float32))
    msg.row_step = 10
    with pytest.raises(PointCloudError, match="row_step"):
        read_points(msg)
    with pytest.raises(PointCloudError, match="no field"):
        read_points(create_cloud(Header(), np.zeros((3, 3), np.float32)), ["intensity"])
