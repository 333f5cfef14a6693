"""``sensor_msgs/PointCloud2`` as numpy structured arrays.

What ``sensor_msgs_py.point_cloud2`` does for rclpy users, vectorised.

* :func:`dtype_from_fields` - the numpy dtype of one point, from the message's ``fields``,
  ``point_step`` and byte order (padding bytes kept, so the dtype's itemsize is
  ``point_step``);
* :func:`read_points` - the points of a cloud, ``(height * width,)`` structured array
  (a zero-copy view of ``data`` when the rows are packed), optionally only some fields and
  only the points whose fields are all finite;
* :func:`create_cloud` - a cloud from a structured array (or an ``(N, 3)`` float32 array as
  x, y, z); ``height`` and ``width`` from the array's shape (1-D: an unordered cloud).

Errors raise :class:`PointCloudError` naming the problem (a field past ``point_step``, an
unknown datatype, ``data`` shorter than the rows declare).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Literal

import numpy as np
import numpy.typing as npt

from posekit.msgs.sensor_msgs import PointCloud2, PointField
from posekit.msgs.std_msgs import Header

__all__ = [
    "DATATYPES",
    "PointCloudError",
    "create_cloud",
    "dtype_from_fields",
    "read_points",
    "xyz_fields",
]

#: PointField datatype -> numpy scalar type.
DATATYPES: dict[int, type[np.generic]] = {
    PointField.INT8: np.int8,
    PointField.UINT8: np.uint8,
    PointField.INT16: np.int16,
    PointField.UINT16: np.uint16,
    PointField.INT32: np.int32,
    PointField.UINT32: np.uint32,
    PointField.FLOAT32: np.float32,
    PointField.FLOAT64: np.float64,
}
_DATATYPE_OF = {np.dtype(v).newbyteorder("<"): k for k, v in DATATYPES.items()}


class PointCloudError(ValueError):
    """A PointCloud2 whose layout is inconsistent; the message says how."""


def xyz_fields(*, rgb: bool = False) -> list[PointField]:
    """Fields ``x, y, z`` (float32 at 0, 4, 8) and, with ``rgb``, ``rgb`` (float32 at 16).

    The memory-aligned layout gz-sensors and PCL's ``PointXYZRGB`` use (point_step 32).
    """
    out = [PointField(name=n, offset=4 * i, datatype=PointField.FLOAT32, count=1)
           for i, n in enumerate("xyz")]
    if rgb:
        out.append(PointField(name="rgb", offset=16, datatype=PointField.FLOAT32, count=1))
    return out


def dtype_from_fields(fields: Sequence[PointField], point_step: int,
                      is_bigendian: bool = False) -> np.dtype[np.void]:
    """The structured dtype of one point (itemsize ``point_step``).

    Raises:
        PointCloudError: unknown datatype, a field past ``point_step``, duplicate names.
    """
    order: Literal["<", ">"] = ">" if is_bigendian else "<"
    names: list[str] = []
    formats: list[np.dtype[np.generic]] = []
    offsets: list[int] = []
    for f in fields:
        scalar = DATATYPES.get(int(f.datatype))
        if scalar is None:
            raise PointCloudError(f"field {f.name!r}: unknown PointField datatype {f.datatype}")
        if f.name in names:
            raise PointCloudError(f"field {f.name!r} appears twice")
        count = max(int(f.count), 1)
        dt = np.dtype(scalar).newbyteorder(order)
        fmt = np.dtype((dt, (count,))) if count > 1 else dt
        if int(f.offset) < 0 or int(f.offset) + fmt.itemsize > point_step:
            raise PointCloudError(
                f"field {f.name!r} (offset {f.offset}, {fmt.itemsize} bytes) does not fit in "
                f"point_step {point_step}"
            )
        names.append(str(f.name))
        formats.append(fmt)
        offsets.append(int(f.offset))
    return np.dtype({"names": names, "formats": formats, "offsets": offsets,
                     "itemsize": int(point_step)})


def read_points(
    msg: PointCloud2,
    field_names: Sequence[str] | None = None,
    *,
    skip_nans: bool = False,
) -> npt.NDArray[np.void]:
    """The points of ``msg`` as a ``(height * width,)`` structured array (row-major).

    Args:
        msg: the cloud.
        field_names: keep only these fields (in this order); ``None`` keeps all.
        skip_nans: drop the points where any kept floating field is not finite.

    Raises:
        PointCloudError: inconsistent layout (see :func:`dtype_from_fields`), ``row_step``
            smaller than ``width * point_step``, or ``data`` shorter than ``height * row_step``.
    """
    dtype = dtype_from_fields(msg.fields, int(msg.point_step), bool(msg.is_bigendian))
    h, w, step, row = int(msg.height), int(msg.width), int(msg.point_step), int(msg.row_step)
    if row < w * step:
        raise PointCloudError(f"row_step {row} is smaller than width {w} x point_step {step}")
    data: Any = msg.data
    raw = np.frombuffer(memoryview(data).cast("B"), dtype=np.uint8)
    if raw.size < h * row:
        raise PointCloudError(f"data holds {raw.size} bytes, the cloud needs {h} x {row}")
    if h * w == 0:
        points = np.zeros(0, dtype=dtype)
    elif row == w * step:
        points = raw[: h * row].view(dtype)
    else:  # padded rows: gather each row's points
        rows = raw[: h * row].reshape(h, row)[:, : w * step]
        points = np.ascontiguousarray(rows).view(dtype).reshape(-1)
    if field_names is not None:
        missing = [n for n in field_names if n not in dtype.names]  # type: ignore[operator]
        if missing:
            raise PointCloudError(f"the cloud has no field(s) {missing}; it has {dtype.names}")
        points = points[list(field_names)]
    if skip_nans:
        keep = np.ones(points.shape[0], dtype=bool)
        for name in points.dtype.names or ():
            column = points[name]
            if np.issubdtype(column.dtype, np.floating):
                finite = np.isfinite(column)
                keep &= finite if finite.ndim == 1 else finite.all(axis=1)
        points = points[keep]
    return points


def create_cloud(header: Header, points: npt.ArrayLike, *, is_dense: bool | None = None
                 ) -> PointCloud2:
    """A PointCloud2 of ``points``.

    ``points`` is a structured array (its fields, offsets and itemsize become ``fields`` and
    ``point_step``) or an ``(..., 3)`` array taken as float32 x, y, z.

    A 2-D structured array ``(H, W)`` gives an organised cloud of ``H`` rows; anything else an
    unordered one (``height`` 1). ``is_dense`` defaults to "every floating field finite".

    Raises:
        PointCloudError: a field type PointField cannot express.
    """
    arr = np.asarray(points)
    if arr.dtype.names is None:
        xyz = np.asarray(arr, dtype=np.float32)
        if xyz.shape[-1] != 3:
            raise PointCloudError(f"plain points must have shape (..., 3), got {xyz.shape}")
        structured = np.empty(xyz.shape[:-1], dtype=dtype_from_fields(xyz_fields(), 12))
        for i, n in enumerate("xyz"):
            structured[n] = xyz[..., i]
        arr = structured
    fields = []
    for name in arr.dtype.names or ():
        ft, offset = arr.dtype.fields[name][:2]  # type: ignore[index]
        base, shape = (ft.base, ft.shape) if ft.shape else (ft, ())
        datatype = _DATATYPE_OF.get(base.newbyteorder("<"))
        if datatype is None or base.byteorder == ">":
            raise PointCloudError(f"field {name!r}: dtype {ft} has no little-endian PointField")
        fields.append(PointField(name=name, offset=int(offset), datatype=datatype,
                                 count=int(np.prod(shape)) if shape else 1))
    height, width = (arr.shape[0], arr.shape[1]) if arr.ndim == 2 else (1, arr.size)
    if is_dense is None:
        is_dense = all(
            bool(np.all(np.isfinite(arr[n])))
            for n in arr.dtype.names or ()
            if np.issubdtype(arr.dtype.fields[n][0].base, np.floating)  # type: ignore[index]
        )
    data = np.ascontiguousarray(arr).reshape(-1).view(np.uint8)
    return PointCloud2(
        header=header, height=int(height), width=int(width), fields=fields,
        is_bigendian=False, point_step=int(arr.dtype.itemsize),
        row_step=int(arr.dtype.itemsize) * int(width), data=data, is_dense=bool(is_dense),
    )
