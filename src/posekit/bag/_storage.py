"""Opening rosbag2 directories with rosbags, with posekit's named errors.

rosbags is imported here, lazily, so ``import posekit.bag`` stays light.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager, suppress
from pathlib import Path
from typing import Any

from posekit.bag.errors import BagError, BagFormatError, BagNotFoundError

__all__ = ["SUPPORTED_VERSIONS", "check_bag_dir", "open_reader"]

#: rosbag2 metadata versions posekit writes (rosbags' Writer supports exactly these).
SUPPORTED_VERSIONS = (8, 9)



def check_bag_dir(path: str | Path) -> Path:
    """``path`` as a Path if it is a rosbag2 directory with ``metadata.yaml``.

    Raises :class:`BagNotFoundError` (missing) or :class:`BagFormatError` (not a bag directory).
    """
    p = Path(path)
    if not p.exists():
        raise BagNotFoundError(f"bag {str(p)!r} does not exist")
    if not p.is_dir():
        raise BagFormatError(
            f"{str(p)!r} is a file; a rosbag2 bag is a directory holding metadata.yaml and "
            "the storage files"
        )
    if not (p / "metadata.yaml").is_file():
        raise BagNotFoundError(
            f"{str(p)!r} is not a rosbag2 bag: it has no metadata.yaml"
        )
    return p


@contextmanager
def open_reader(path: str | Path) -> Iterator[Any]:
    """An open ``rosbags.rosbag2.Reader`` on the bag directory ``path``.

    Every failure while opening *or* iterating inside the ``with`` block becomes a
    :class:`BagFormatError` naming the bag and the original error (corruption of a chunk
    only shows while reading). Damaged input makes rosbags and the decompressor raise a wide
    range of exception types (ReaderError, ZstdError, OverflowError, struct.error...), so
    every ``Exception`` is translated; keep the code inside the block to storage access.
    """
    from rosbags.rosbag2 import Reader

    p = check_bag_dir(path)
    try:
        reader = Reader(p)
        reader.open()
    except FileNotFoundError as exc:
        raise BagNotFoundError(f"bag {str(p)!r}: {exc}") from exc
    except Exception as exc:
        raise BagFormatError(f"cannot open bag {str(p)!r}: {_reason(exc)}") from exc
    try:
        yield reader
    except BagError:
        raise
    except Exception as exc:
        raise BagFormatError(f"cannot read bag {str(p)!r}: {_reason(exc)}") from exc
    finally:
        with suppress(Exception):  # closing a damaged file must not hide the real error
            reader.close()


def _reason(exc: BaseException) -> str:
    text = str(exc).strip()
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__
