"""image_to_numpy / numpy_to_image: layouts, zero-copy, padding, byte order, errors."""

from __future__ import annotations

import struct

import numpy as np
import pytest

from posekit.msgs import ImageConversionError, from_cdr, image_to_numpy, numpy_to_image, to_cdr
from posekit.msgs.sensor_msgs import Image
from posekit.msgs.std_msgs import Header


@pytest.mark.parametrize(("encoding", "channels"), [("rgb8", 3), ("bgr8", 3), ("mono8", 1)])
def test_round_trip_and_shared_memory(encoding: str, channels: int) -> None:
    rng = np.random.default_rng(7)
    shape = (4, 5, channels) if channels > 1 else (4, 5)
    arr = rng.integers(0, 256, size=shape, dtype=np.uint8)
    header = Header(frame_id="camera")
    msg = numpy_to_image(arr, encoding, header)
    assert (msg.height, msg.width, msg.step) == (4, 5, 5 * channels)
    assert msg.encoding == encoding
    assert msg.header is header
    assert msg.data.dtype == np.uint8
    assert msg.data.shape == (4 * 5 * channels,)
    # row-major, interleaved channels: pixel (r, c), channel k sits at r*step + c*channels + k
    r, c = 2, 3
    for k in range(channels):
        idx = (r, c, k) if channels > 1 else (r, c)
        assert msg.data[r * msg.step + c * channels + k] == arr[idx]
    assert np.shares_memory(msg.data, arr)
    back = image_to_numpy(msg)
    assert back.shape == shape
    np.testing.assert_array_equal(back, arr)
    assert np.shares_memory(back, arr)


def test_padded_rows_are_skipped_without_copy() -> None:
    # 2 x 3 rgb8 with step 12 (3 padding bytes per row, value 255)
    rows = [bytes(range(r * 9, r * 9 + 9)) + b"\xff\xff\xff" for r in range(2)]
    msg = Image(height=2, width=3, encoding="rgb8", step=12)
    msg.data = np.frombuffer(b"".join(rows), dtype=np.uint8)
    arr = image_to_numpy(msg)
    assert arr.shape == (2, 3, 3)
    np.testing.assert_array_equal(arr.reshape(2, 9), np.arange(18).reshape(2, 9))
    assert np.shares_memory(arr, msg.data)


def test_bytes_data_and_cdr_round_trip() -> None:
    msg = Image(height=1, width=2, encoding="bgr8", step=6)
    msg.data = b"\x01\x02\x03\x04\x05\x06"  # type: ignore[assignment]
    np.testing.assert_array_equal(image_to_numpy(msg), [[[1, 2, 3], [4, 5, 6]]])
    decoded = from_cdr(to_cdr(msg), Image)
    np.testing.assert_array_equal(image_to_numpy(decoded), [[[1, 2, 3], [4, 5, 6]]])


def test_sixteen_bit_byte_order() -> None:
    values = [1, 258, 65535, 4096]
    be = Image(height=2, width=2, encoding="mono16", is_bigendian=1, step=4)
    be.data = np.frombuffer(struct.pack(">4H", *values), dtype=np.uint8)
    le = Image(height=2, width=2, encoding="16UC1", is_bigendian=0, step=4)
    le.data = np.frombuffer(struct.pack("<4H", *values), dtype=np.uint8)
    np.testing.assert_array_equal(image_to_numpy(be), np.array(values).reshape(2, 2))
    np.testing.assert_array_equal(image_to_numpy(le), np.array(values).reshape(2, 2))
    msg = numpy_to_image(np.array(values, dtype=">u2").reshape(2, 2), "mono16")
    assert msg.is_bigendian == 1
    assert bytes(msg.data) == struct.pack(">4H", *values)


def test_float_depth_image() -> None:
    depth = np.array([[0.5, 1.25], [2.0, np.inf]], dtype=np.float32)
    msg = numpy_to_image(depth, "32FC1")
    assert msg.step == 8
    np.testing.assert_array_equal(image_to_numpy(msg), depth)


def test_non_contiguous_input_is_copied_correctly() -> None:
    arr = np.arange(2 * 6 * 3, dtype=np.uint8).reshape(2, 6, 3)[:, ::2]
    msg = numpy_to_image(arr, "rgb8")
    assert msg.step == 9
    np.testing.assert_array_equal(image_to_numpy(msg), arr)


@pytest.mark.parametrize(
    ("arr", "encoding", "match"),
    [
        (np.zeros((2, 2, 3), np.uint8), "yuv422_fancy", "unsupported image encoding"),
        (np.zeros((2, 2, 3), np.uint8), "mono8", "channel"),
        (np.zeros((2, 2), np.uint8), "rgb8", "channel"),
        (np.zeros((2, 2, 3), np.float32), "rgb8", "dtype"),
        (np.zeros((2, 2, 3, 1), np.uint8), "rgb8", "2-D or 3-D"),
    ],
)
def test_numpy_to_image_errors(arr: np.ndarray, encoding: str, match: str) -> None:
    with pytest.raises(ImageConversionError, match=match):
        numpy_to_image(arr, encoding)


def test_image_to_numpy_errors() -> None:
    msg = Image(height=2, width=2, encoding="rgb8", step=6, data=np.zeros(11, np.uint8))
    with pytest.raises(ImageConversionError, match="needs 12 bytes"):
        image_to_numpy(msg)
    msg = Image(height=2, width=2, encoding="rgb8", step=5, data=np.zeros(10, np.uint8))
    with pytest.raises(ImageConversionError, match="step"):
        image_to_numpy(msg)
    msg = Image(height=1, width=1, encoding="", step=3, data=np.zeros(3, np.uint8))
    with pytest.raises(ImageConversionError, match="encoding"):
        image_to_numpy(msg)


def test_empty_image() -> None:
    msg = Image(encoding="mono8")
    assert image_to_numpy(msg).shape == (0, 0)
