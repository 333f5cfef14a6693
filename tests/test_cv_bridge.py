"""posekit.cv_bridge.CvBridge: round trips and conversions.

Oracles: OpenCV's own ``cv2.cvtColor`` for channel orders, hand-built message bytes (row
padding, big-endian data) for decoding, numpy for value scaling, and the cv_bridge
contract (passthrough returns the message's encoding; cv2_to_imgmsg labels passthrough
images with the OpenCV type name; CvBridgeError is a TypeError).
"""

from __future__ import annotations

import numpy as np
import pytest

from posekit.cv_bridge import CvBridge, CvBridgeError
from posekit.msgs.sensor_msgs import Image
from posekit.msgs.std_msgs import Header

cv2 = pytest.importorskip("cv2")

RNG = np.random.default_rng(7)
BRIDGE = CvBridge()


def _rgb() -> np.ndarray:
    return RNG.integers(0, 256, (5, 7, 3), dtype=np.uint8)


def test_passthrough_round_trip_keeps_bytes_encoding_and_header() -> None:
    rgb = _rgb()
    header = Header(frame_id="oak_rgb_camera_optical_frame")
    msg = BRIDGE.cv2_to_imgmsg(rgb, encoding="rgb8", header=header)
    assert (msg.height, msg.width, msg.step, msg.encoding) == (5, 7, 21, "rgb8")
    assert msg.header.frame_id == "oak_rgb_camera_optical_frame"
    out = BRIDGE.imgmsg_to_cv2(msg)
    np.testing.assert_array_equal(out, rgb)
    assert out.flags.writeable
    out[0, 0] = 0  # the caller owns the array: the message is unchanged
    assert bytes(np.asarray(msg.data)[:3]) == rgb[0, 0].tobytes()


def test_message_is_a_copy_of_the_array() -> None:
    rgb = _rgb()
    msg = BRIDGE.cv2_to_imgmsg(rgb, "rgb8")
    rgb[:] = 0
    assert np.asarray(msg.data).any()


@pytest.mark.parametrize(("source", "target", "code"), [
    ("rgb8", "bgr8", "COLOR_RGB2BGR"), ("bgr8", "rgb8", "COLOR_BGR2RGB"),
    ("rgb8", "mono8", "COLOR_RGB2GRAY"), ("bgr8", "mono8", "COLOR_BGR2GRAY"),
    ("bgr8", "bgra8", "COLOR_BGR2BGRA"), ("rgba8", "bgr8", "COLOR_RGBA2BGR"),
])
def test_colour_conversions_match_opencv(source: str, target: str, code: str) -> None:
    channels = 4 if source.endswith("a8") else 3
    pixels = RNG.integers(0, 256, (4, 6, channels), dtype=np.uint8)
    msg = BRIDGE.cv2_to_imgmsg(pixels, source)
    np.testing.assert_array_equal(BRIDGE.imgmsg_to_cv2(msg, target),
                                  cv2.cvtColor(pixels, getattr(cv2, code)))


def test_mono8_to_bgr8_and_bit_depth_scaling() -> None:
    grey = RNG.integers(0, 256, (3, 4), dtype=np.uint8)
    msg = BRIDGE.cv2_to_imgmsg(grey, "mono8")
    np.testing.assert_array_equal(BRIDGE.imgmsg_to_cv2(msg, "bgr8"), np.dstack([grey] * 3))
    wide = BRIDGE.imgmsg_to_cv2(msg, "mono16")
    assert wide.dtype == np.uint16
    np.testing.assert_array_equal(wide, grey.astype(np.uint32) * 65535 // 255)
    back = BRIDGE.imgmsg_to_cv2(BRIDGE.cv2_to_imgmsg(wide, "mono16"), "mono8")
    np.testing.assert_array_equal(back, grey)


def test_relabel_between_same_layouts() -> None:
    grey = RNG.integers(0, 256, (3, 4), dtype=np.uint8)
    msg = BRIDGE.cv2_to_imgmsg(grey, "mono8")
    np.testing.assert_array_equal(BRIDGE.imgmsg_to_cv2(msg, "8UC1"), grey)


def test_depth_images_pass_through() -> None:
    mm = RNG.integers(0, 10_000, (4, 5), dtype=np.uint16)
    metres = RNG.random((4, 5), dtype=np.float32)
    for array, encoding in ((mm, "16UC1"), (metres, "32FC1")):
        msg = BRIDGE.cv2_to_imgmsg(array, encoding)
        assert msg.step == 5 * array.itemsize
        out = BRIDGE.imgmsg_to_cv2(msg, "passthrough")
        assert out.dtype == array.dtype
        np.testing.assert_array_equal(out, array)


def test_passthrough_encoding_is_the_opencv_type_name() -> None:
    assert BRIDGE.cv2_to_imgmsg(_rgb()).encoding == "8UC3"
    assert BRIDGE.cv2_to_imgmsg(np.zeros((2, 2), np.float32)).encoding == "32FC1"
    assert BRIDGE.cv2_to_imgmsg(np.zeros((2, 2, 4), np.uint16)).encoding == "16UC4"


def test_padded_and_big_endian_messages_decode() -> None:
    rows = np.arange(12, dtype=">u2").reshape(3, 4)
    padded = np.zeros((3, 10), np.uint8)  # step 10 > 8 bytes of pixels per row
    padded[:, :8] = rows.view(np.uint8).reshape(3, 8)
    msg = Image(height=3, width=4, encoding="16UC1", is_bigendian=1, step=10,
                data=padded.reshape(-1))
    out = BRIDGE.imgmsg_to_cv2(msg)
    np.testing.assert_array_equal(out, np.arange(12).reshape(3, 4))
    assert out.dtype.isnative


def test_errors_are_cv_bridge_errors_and_type_errors() -> None:
    with pytest.raises(CvBridgeError, match="32FC1"):
        BRIDGE.imgmsg_to_cv2(BRIDGE.cv2_to_imgmsg(np.zeros((2, 2), np.float32), "32FC1"),
                             "bgr8")
    with pytest.raises(CvBridgeError, match=r"bgr8, but image has incompatible type 32FC1"):
        BRIDGE.cv2_to_imgmsg(np.zeros((2, 2), np.float32), "bgr8")
    with pytest.raises(CvBridgeError, match="unsupported image encoding"):
        BRIDGE.imgmsg_to_cv2(Image(height=1, width=1, encoding="yuv422", step=2,
                                   data=np.zeros(2, np.uint8)))
    with pytest.raises(TypeError):
        BRIDGE.cv2_to_imgmsg([[1, 2], [3, 4]])
    short = Image(height=2, width=2, encoding="mono8", step=2, data=np.zeros(3, np.uint8))
    with pytest.raises(CvBridgeError, match="needs 4 bytes"):
        BRIDGE.imgmsg_to_cv2(short)
