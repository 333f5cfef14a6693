"""``CvBridge``: ``sensor_msgs/Image`` <-> OpenCV arrays with cv_bridge's interface.

Code written for ROS 2's ``cv_bridge`` runs after one changed import::

    from posekit.cv_bridge import CvBridge, CvBridgeError   # was: from cv_bridge import ...

* ``imgmsg_to_cv2(msg, desired_encoding="passthrough")`` returns a **writable** numpy array
  the caller owns (``(H, W)`` for one channel, ``(H, W, C)`` otherwise; row padding in
  ``step`` dropped, multi-byte pixels in the machine's byte order). ``passthrough`` keeps the
  message's encoding; any other encoding converts.
* ``cv2_to_imgmsg(array, encoding="passthrough", header=None)`` wraps an array; with
  ``passthrough`` the encoding is the OpenCV type name of the array (``8UC3``, ``32FC1``...),
  otherwise the named encoding must fit the array's element type and channel count (it only
  labels the channel order, as in cv_bridge: a ``bgr8`` label on RGB pixels is not checked).

Conversions (``desired_encoding``):

* among the colour and mono encodings ``mono8``, ``bgr8``, ``rgb8``, ``bgra8``, ``rgba8``
  and their 16-bit forms: channel order with ``cv2.cvtColor``; a bit-depth change scales the
  value range (8 -> 16 bit multiplies by 65535/255, 16 -> 8 bit divides);
* between two encodings with the same element type and channel count (``mono8`` and
  ``8UC1``, ``mono16`` and ``16UC1``, ``bgr8`` and ``8UC3``...): relabelled, no change;
* anything else (e.g. ``32FC1`` to ``bgr8``) raises :class:`CvBridgeError` naming both.

Depth images keep their encodings: ``16UC1`` (millimetres) and ``32FC1`` (metres) pass
through. Needs OpenCV only when a colour conversion is asked for.
"""

from __future__ import annotations

import re
from typing import Any

import numpy as np
import numpy.typing as npt

from posekit.msgs.errors import ImageConversionError
from posekit.msgs.image import encoding_layout, image_to_numpy, numpy_to_image
from posekit.msgs.sensor_msgs import Image
from posekit.msgs.std_msgs import Header

__all__ = ["CvBridge", "CvBridgeError"]

#: Channel orders of the colour/mono encodings, by base name.
_ORDER = {"mono": "GRAY", "bgr": "BGR", "rgb": "RGB", "bgra": "BGRA", "rgba": "RGBA"}
_COLOUR = re.compile(r"^(mono|bgr|rgb|bgra|rgba)(8|16)$")
_CV_DEPTH = {("u", 1): "8U", ("i", 1): "8S", ("u", 2): "16U", ("i", 2): "16S",
             ("i", 4): "32S", ("f", 4): "32F", ("f", 8): "64F"}


class CvBridgeError(TypeError):
    """An image cannot be converted (unknown or incompatible encoding, wrong array type).

    A ``TypeError`` as in cv_bridge, so ``except CvBridgeError`` and ``except TypeError``
    both catch it.
    """


def _cv_type_name(array: npt.NDArray[Any]) -> str:
    channels = 1 if array.ndim == 2 else int(array.shape[2])
    depth = _CV_DEPTH.get((array.dtype.kind, array.dtype.itemsize))
    if depth is None or array.ndim not in (2, 3) or not 1 <= channels <= 4:
        raise CvBridgeError(
            f"cannot wrap an array of dtype {array.dtype} and shape {array.shape} in an Image "
            "(need (H, W) or (H, W, 1..4) of uint8, int8, uint16, int16, int32, float32 or "
            "float64)"
        )
    return f"{depth}C{channels}"


class CvBridge:
    """Converts between ``sensor_msgs/Image`` and numpy/OpenCV arrays (see the module doc)."""

    def imgmsg_to_cv2(self, img_msg: Any, desired_encoding: str = "passthrough"
                      ) -> npt.NDArray[Any]:
        """A new writable array of the message's pixels in ``desired_encoding``.

        Raises:
            CvBridgeError: unknown encoding, sizes inconsistent with the data, or no
                conversion from the message's encoding to ``desired_encoding``.
        """
        try:
            view = image_to_numpy(img_msg)
        except ImageConversionError as exc:
            raise CvBridgeError(str(exc)) from exc
        native = view.dtype.newbyteorder("=")
        array = np.array(view, dtype=native, order="C", copy=True)
        source = str(img_msg.encoding)
        if desired_encoding in ("passthrough", source):
            return array
        return self._convert(array, source, desired_encoding)

    def cv2_to_imgmsg(self, cvim: Any, encoding: str = "passthrough",
                      header: Header | None = None) -> Image:
        """An Image holding ``cvim`` (2-D or 3-D array) labelled ``encoding``.

        Raises:
            CvBridgeError: ``cvim`` is not an image array, or its element type or channel
                count does not fit ``encoding``.
        """
        if not isinstance(cvim, np.ndarray):
            raise CvBridgeError(f"Your input type is not a numpy array: {type(cvim).__name__}")
        cv_type = _cv_type_name(cvim)
        label = cv_type if encoding == "passthrough" else encoding
        try:
            # A copy, as cv_bridge's: drawing on cvim later does not change the message.
            msg = numpy_to_image(np.array(cvim, order="C", copy=True), label, header)
        except ImageConversionError as exc:
            raise CvBridgeError(
                f"encoding specified as {label}, but image has incompatible type {cv_type}"
            ) from exc
        return msg

    @staticmethod
    def _convert(array: npt.NDArray[Any], source: str, target: str) -> npt.NDArray[Any]:
        try:
            src_dtype, src_channels = encoding_layout(source)
            dst_dtype, dst_channels = encoding_layout(target)
        except ImageConversionError as exc:
            raise CvBridgeError(str(exc)) from exc
        if (src_dtype, src_channels) == (dst_dtype, dst_channels) and not (
            _COLOUR.match(source) and _COLOUR.match(target)
        ):
            return array  # same layout, another name (mono8 <-> 8UC1, bgr8 <-> 8UC3, ...)
        src, dst = _COLOUR.match(source), _COLOUR.match(target)
        if src is None or dst is None:
            raise CvBridgeError(
                f"cannot convert an image of encoding {source} to {target}: only the colour "
                "and mono encodings (mono8, bgr8, rgb8, bgra8, rgba8 and their 16-bit forms) "
                "convert; other encodings pass through or relabel to one of the same layout"
            )
        out = array
        src_order, dst_order = _ORDER[src.group(1)], _ORDER[dst.group(1)]
        if src_order != dst_order:
            import cv2

            code = getattr(cv2, f"COLOR_{src_order}2{dst_order}")
            out = np.asarray(cv2.cvtColor(out, code))
        src_bits, dst_bits = int(src.group(2)), int(dst.group(2))
        if src_bits == 8 and dst_bits == 16:
            out = (out.astype(np.uint16) * 257).astype(np.uint16)
        elif src_bits == 16 and dst_bits == 8:
            out = np.rint(out.astype(np.float64) / 257.0).astype(np.uint8)
        return np.ascontiguousarray(out)
