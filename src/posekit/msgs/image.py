"""``sensor_msgs/Image`` <-> numpy, what cv_bridge's ``imgmsg_to_cv2`` / ``cv2_to_imgmsg`` give.

Arrays are ``(height, width)`` for one channel and ``(height, width, channels)`` otherwise,
in the channel order the encoding names (``bgr8`` is OpenCV's order, ``rgb8`` is not).
Both directions are zero-copy when possible: :func:`image_to_numpy` returns a view of
``msg.data`` (honouring row padding in ``step``), and :func:`numpy_to_image` stores a view
of a C-contiguous input array, so the message and the array share memory. Copy if you
need independence (``arr.copy()``).

Supported encodings: ``rgb8``, ``bgr8``, ``rgba8``, ``bgra8``, ``mono8``, ``mono16``,
``rgb16``, ``bgr16``, ``rgba16``, ``bgra16`` and the OpenCV-style ``8UC1`` .. ``64FC4``.
"""

from __future__ import annotations

import re
import sys
from typing import Any

import numpy as np
import numpy.typing as npt

from posekit.msgs.errors import ImageConversionError
from posekit.msgs.sensor_msgs import Image
from posekit.msgs.std_msgs import Header

__all__ = ["encoding_layout", "image_to_numpy", "numpy_to_image"]

_NAMED: dict[str, tuple[str, int]] = {
    "rgb8": ("u1", 3),
    "bgr8": ("u1", 3),
    "rgba8": ("u1", 4),
    "bgra8": ("u1", 4),
    "mono8": ("u1", 1),
    "mono16": ("u2", 1),
    "rgb16": ("u2", 3),
    "bgr16": ("u2", 3),
    "rgba16": ("u2", 4),
    "bgra16": ("u2", 4),
}
_CV_TYPE = re.compile(r"^(8|16|32|64)([USF])C([1-4])$")
_CV_DTYPES = {
    ("8", "U"): "u1",
    ("8", "S"): "i1",
    ("16", "U"): "u2",
    ("16", "S"): "i2",
    ("32", "S"): "i4",
    ("32", "F"): "f4",
    ("64", "F"): "f8",
}


def encoding_layout(encoding: str) -> tuple[np.dtype[Any], int]:
    """Return ``(element dtype in native byte order, channels)`` of an image encoding."""
    if encoding in _NAMED:
        code, channels = _NAMED[encoding]
        return np.dtype(code), channels
    match = _CV_TYPE.match(encoding)
    if match and (match.group(1), match.group(2)) in _CV_DTYPES:
        return np.dtype(_CV_DTYPES[(match.group(1), match.group(2))]), int(match.group(3))
    raise ImageConversionError(
        f"unsupported image encoding {encoding!r}; supported: {sorted(_NAMED)} and "
        "OpenCV types like '8UC3', '16UC1', '32FC1'"
    )


def image_to_numpy(msg: Any) -> npt.NDArray[Any]:
    """View an Image message's pixels as a numpy array (no copy).

    Args:
        msg: a ``sensor_msgs/Image`` (posekit, rosbags or duck-typed) whose ``data`` is a
            uint8 array or any bytes-like buffer of ``height * step`` bytes.

    Returns:
        ``(height, width)`` or ``(height, width, channels)`` array sharing memory with
        ``msg.data`` (read-only if ``msg.data`` is). Multi-byte elements keep the message's
        byte order (``is_bigendian``).

    Raises:
        ImageConversionError: unsupported encoding, or sizes inconsistent with ``data``.
    """
    dtype, channels = encoding_layout(msg.encoding)
    if dtype.itemsize > 1:
        dtype = dtype.newbyteorder(">" if msg.is_bigendian else "<")
    height, width, step = int(msg.height), int(msg.width), int(msg.step)
    row_bytes = width * channels * dtype.itemsize
    if height < 0 or width < 0 or step < row_bytes:
        raise ImageConversionError(
            f"{msg.encoding} image {width}x{height}: step {step} is smaller than a row "
            f"({row_bytes} bytes)"
        )
    buffer = msg.data
    if not isinstance(buffer, np.ndarray):
        buffer = np.frombuffer(buffer, dtype=np.uint8)
    if buffer.nbytes != height * step:
        raise ImageConversionError(
            f"{msg.encoding} image {width}x{height} with step {step} needs "
            f"{height * step} bytes of data, got {buffer.nbytes}"
        )
    if buffer.dtype != np.uint8 or buffer.ndim != 1 or not buffer.flags.c_contiguous:
        buffer = np.ascontiguousarray(buffer).reshape(-1).view(np.uint8)
    shape: tuple[int, ...] = (height, width) if channels == 1 else (height, width, channels)
    strides: tuple[int, ...] = (step, channels * dtype.itemsize)
    if channels > 1:
        strides = (*strides, dtype.itemsize)
    if height == 0 or width == 0:
        return np.zeros(shape, dtype=dtype)
    return np.ndarray(shape, dtype=dtype, buffer=buffer, strides=strides)


def numpy_to_image(
    array: npt.NDArray[Any], encoding: str, header: Header | None = None
) -> Image:
    """Wrap a numpy image in a ``sensor_msgs/Image`` (no copy for C-contiguous input).

    Args:
        array: ``(height, width)`` or ``(height, width, channels)``, dtype matching the
            encoding (uint8 for ``rgb8``/``bgr8``/``mono8``).
        encoding: ROS encoding; it only labels the channel order (no conversion).
        header: stamp and frame; a default Header when omitted.

    Raises:
        ImageConversionError: dtype or channel count does not match ``encoding``.
    """
    dtype, channels = encoding_layout(encoding)
    arr = np.asarray(array)
    if arr.ndim == 2:
        have_channels = 1
    elif arr.ndim == 3:
        have_channels = arr.shape[2]
    else:
        raise ImageConversionError(
            f"an image array must be 2-D or 3-D (height, width[, channels]), got shape {arr.shape}"
        )
    if have_channels != channels:
        raise ImageConversionError(
            f"encoding {encoding!r} has {channels} channel(s), array shape {arr.shape} has "
            f"{have_channels}"
        )
    if arr.dtype.kind != dtype.kind or arr.dtype.itemsize != dtype.itemsize:
        raise ImageConversionError(
            f"encoding {encoding!r} stores {dtype.name} elements, array dtype is {arr.dtype}"
        )
    big_endian = arr.dtype.byteorder == ">" or (
        arr.dtype.byteorder == "=" and sys.byteorder == "big"
    )
    if not arr.flags.c_contiguous:
        arr = np.ascontiguousarray(arr)
    height, width = int(arr.shape[0]), int(arr.shape[1])
    return Image(
        header=header if header is not None else Header(),
        height=height,
        width=width,
        encoding=encoding,
        is_bigendian=int(big_endian and dtype.itemsize > 1),
        step=width * channels * dtype.itemsize,
        data=arr.reshape(-1).view(np.uint8),
    )
