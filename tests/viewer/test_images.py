"""Image -> JPEG for the image panels: channel order, depth scaling, downscaling, bad input.
Decoded with cv2.imdecode and compared with the source pixels."""

from __future__ import annotations

import numpy as np
import pytest

cv2 = pytest.importorskip("cv2")

from posekit.msgs.errors import ImageConversionError  # noqa: E402
from posekit.msgs.image import numpy_to_image  # noqa: E402
from posekit.msgs.sensor_msgs import Image  # noqa: E402
from posekit.viewer.images import encode_jpeg  # noqa: E402


def decode(jpeg: bytes) -> np.ndarray:
    image = cv2.imdecode(np.frombuffer(jpeg, np.uint8), cv2.IMREAD_UNCHANGED)
    assert image is not None
    return image


def blocks() -> np.ndarray:
    """A 64x96 RGB test card: flat blocks, so JPEG keeps colours within a few levels."""
    rgb = np.zeros((64, 96, 3), np.uint8)
    rgb[:, :32] = (220, 20, 20)   # red
    rgb[:, 32:64] = (20, 220, 20)  # green
    rgb[:, 64:] = (20, 20, 220)   # blue
    return rgb


def test_rgb8_and_bgr8_keep_their_colours() -> None:
    rgb = blocks()
    got_from_rgb = decode(encode_jpeg(numpy_to_image(rgb, "rgb8"), quality=95))
    got_from_bgr = decode(encode_jpeg(numpy_to_image(np.ascontiguousarray(rgb[:, :, ::-1]),
                                                     "bgr8"), quality=95))
    expected_bgr = rgb[:, :, ::-1].astype(int)
    for got in (got_from_rgb, got_from_bgr):
        assert got.shape == (64, 96, 3)
        centre = (slice(8, 56), slice(4, 28))
        assert np.abs(got[centre].astype(int) - expected_bgr[centre]).max() < 12
        assert np.abs(got.astype(int) - expected_bgr).mean() < 6


def test_rgba8_and_mono8() -> None:
    rgba = np.dstack([blocks(), np.full((64, 96), 255, np.uint8)])
    got = decode(encode_jpeg(numpy_to_image(np.ascontiguousarray(rgba), "rgba8"), quality=95))
    assert np.abs(got.astype(int) - blocks()[:, :, ::-1]).mean() < 6
    mono = np.tile(np.linspace(0, 255, 96).astype(np.uint8), (64, 1))
    got = decode(encode_jpeg(numpy_to_image(mono, "mono8"), quality=95))
    assert got.ndim == 2
    assert np.abs(got.astype(int) - mono).mean() < 3


def test_depth_images_are_scaled_to_their_range() -> None:
    depth = np.tile(np.linspace(1000, 5000, 96).astype(np.uint16), (64, 1))
    got = decode(encode_jpeg(numpy_to_image(depth, "mono16"), quality=95))
    expected = (depth.astype(float) - 1000) * 255 / 4000
    assert np.abs(got.astype(float) - expected).mean() < 3
    f32 = np.full((8, 8), np.nan, np.float32)
    f32[:4] = 2.0
    f32[4:] = 4.0
    got = decode(encode_jpeg(numpy_to_image(f32, "32FC1"), quality=95))
    assert got[1, 1] < 10
    assert got[6, 6] > 245


def test_wide_images_are_downscaled() -> None:
    rgb = np.zeros((720, 1280, 3), np.uint8)
    got = decode(encode_jpeg(numpy_to_image(rgb, "rgb8"), max_width=640))
    assert got.shape == (360, 640, 3)


def test_bad_images_raise_named_errors() -> None:
    with pytest.raises(ImageConversionError):
        encode_jpeg(Image(height=2, width=2, encoding="yuv422_weird", step=4,
                          data=np.zeros(8, np.uint8)))
    with pytest.raises(ImageConversionError):
        encode_jpeg(Image(height=10, width=10, encoding="rgb8", step=30,
                          data=np.zeros(5, np.uint8)))
