"""``sensor_msgs/Image`` -> JPEG bytes for the page's image panels (OpenCV ``cv2.imencode``)."""

from __future__ import annotations

from typing import Any

import numpy as np

from posekit.msgs.image import image_to_numpy

__all__ = ["encode_jpeg", "to_bgr8"]


def to_bgr8(msg: Any) -> np.ndarray:
    """The image as an 8-bit array OpenCV encodes as shown (BGR, BGRA dropped to BGR, mono).

    16-bit and float images are scaled from their own min..max to 0..255 (what
    rqt_image_view does for depth images without a fixed range).
    """
    import cv2

    array = image_to_numpy(msg)
    encoding = str(msg.encoding)
    if array.dtype != np.uint8:
        finite = np.isfinite(array) if array.dtype.kind == "f" else np.ones(array.shape, bool)
        values = array[finite]
        lo = float(values.min()) if values.size else 0.0
        hi = float(values.max()) if values.size else 1.0
        scale = 255.0 / (hi - lo) if hi > lo else 0.0
        array = np.where(finite, (array.astype(np.float64) - lo) * scale, 0.0).astype(np.uint8)
    if array.ndim == 2:
        return array
    channels = array.shape[2]
    if channels == 1:
        return array[:, :, 0]
    if encoding.startswith("rgba"):
        return cv2.cvtColor(array, cv2.COLOR_RGBA2BGR)
    if encoding.startswith("rgb"):
        return cv2.cvtColor(array, cv2.COLOR_RGB2BGR)
    if channels == 4:
        return cv2.cvtColor(array, cv2.COLOR_BGRA2BGR)
    if channels == 2:
        return array[:, :, 0]
    return array


def encode_jpeg(msg: Any, quality: int = 80, max_width: int = 1280) -> bytes:
    """JPEG bytes of an Image message, downscaled to ``max_width`` px if wider.

    Raises:
        ImageConversionError: unsupported encoding or inconsistent size (from image_to_numpy).
        ValueError: the encoder failed.
    """
    import cv2

    bgr = to_bgr8(msg)
    if max_width > 0 and bgr.shape[1] > max_width:
        height = max(1, round(bgr.shape[0] * max_width / bgr.shape[1]))
        bgr = cv2.resize(bgr, (max_width, height), interpolation=cv2.INTER_AREA)
    ok, jpeg = cv2.imencode(".jpg", np.ascontiguousarray(bgr), [cv2.IMWRITE_JPEG_QUALITY, quality])
    if not ok:
        raise ValueError("cv2.imencode failed to produce a JPEG")
    return bytes(jpeg.tobytes())
