"""Compact point clouds for the PointCloud2 display.

Oracle: clouds whose bytes are laid out here with a numpy dtype written in the test (fields,
padding, packed rgb), and the points they hold computed directly from the arrays that filled
them; thinning checked against numpy slicing of those arrays.
"""

from __future__ import annotations

import numpy as np
import pytest

from posekit.msgs.point_cloud2 import PointCloudError
from posekit.msgs.sensor_msgs import PointCloud2, PointField
from posekit.msgs.std_msgs import Header
from posekit.viewer.cloud_feed import compact_point_cloud

F32 = PointField.FLOAT32


def _cloud(h: int, w: int, *, rng: np.random.Generator) -> tuple[PointCloud2, dict]:
    dtype = np.dtype({"names": ["x", "y", "z", "intensity", "rgb"],
                      "formats": ["<f4", "<f4", "<f4", "<f4", "<u4"],
                      "offsets": [0, 4, 8, 16, 20], "itemsize": 32})
    arr = np.zeros((h, w), dtype=dtype)
    xyz = rng.normal(size=(h, w, 3)).astype(np.float32)
    xyz[rng.random((h, w)) < 0.2] = np.nan
    for i, n in enumerate("xyz"):
        arr[n] = xyz[..., i]
    inten = rng.random((h, w)).astype(np.float32)
    rgb = rng.integers(0, 256, size=(h, w, 3))
    arr["intensity"] = inten
    arr["rgb"] = (rgb[..., 0] << 16) | (rgb[..., 1] << 8) | rgb[..., 2]
    fields = [PointField(name=n, offset=o, datatype=F32, count=1)
              for n, o in (("x", 0), ("y", 4), ("z", 8), ("intensity", 16))]
    fields.append(PointField(name="rgb", offset=20, datatype=PointField.UINT32, count=1))
    msg = PointCloud2(header=Header(frame_id="cam"), height=h, width=w, fields=fields,
                      point_step=32, row_step=32 * w, data=arr.reshape(-1).view(np.uint8),
                      is_dense=False)
    return msg, {"xyz": xyz, "intensity": inten, "rgb": rgb}


def test_every_finite_point_with_its_channels_when_small() -> None:
    msg, src = _cloud(20, 30, rng=np.random.default_rng(1))
    out = compact_point_cloud(msg)
    keep = np.isfinite(src["xyz"]).all(axis=2).reshape(-1)
    assert out.stride == 1
    assert out.total == 600
    assert out.header.frame_id == "cam"
    assert out.fields == ["x", "y", "z", "intensity", "rgb"]
    np.testing.assert_array_equal(out.points.reshape(-1, 3), src["xyz"].reshape(-1, 3)[keep])
    np.testing.assert_array_equal(out.intensity, src["intensity"].reshape(-1)[keep])
    np.testing.assert_array_equal(out.rgb.reshape(-1, 3), src["rgb"].reshape(-1, 3)[keep])
    assert out.points.dtype == np.float32
    assert out.rgb.dtype == np.uint8


def test_an_organised_cloud_is_thinned_by_rows_and_columns() -> None:
    msg, src = _cloud(90, 160, rng=np.random.default_rng(2))
    out = compact_point_cloud(msg, max_points=1000)
    assert out.stride == 4  # ceil(sqrt(14400 / 1000))
    sub = src["xyz"][::4, ::4].reshape(-1, 3)
    np.testing.assert_array_equal(out.points.reshape(-1, 3), sub[np.isfinite(sub).all(axis=1)])
    assert out.points.size // 3 <= 1000


def test_an_unordered_cloud_is_thinned_by_points() -> None:
    msg, src = _cloud(1, 5000, rng=np.random.default_rng(3))
    out = compact_point_cloud(msg, max_points=1000)
    assert out.stride == 5
    sub = src["xyz"].reshape(-1, 3)[::5]
    np.testing.assert_array_equal(out.points.reshape(-1, 3), sub[np.isfinite(sub).all(axis=1)])


def test_a_cloud_without_xyz_or_with_a_bad_layout_is_refused() -> None:
    msg, _ = _cloud(2, 2, rng=np.random.default_rng(4))
    msg.fields = msg.fields[1:]
    with pytest.raises(PointCloudError, match="no x field"):
        compact_point_cloud(msg)
    msg, _ = _cloud(2, 2, rng=np.random.default_rng(4))
    msg.data = msg.data[:-1]
    with pytest.raises(PointCloudError, match="bytes"):
        compact_point_cloud(msg)
